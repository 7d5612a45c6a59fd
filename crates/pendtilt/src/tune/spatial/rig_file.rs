//! The 3-D tune's output: the start's rig file as it was, its `[ekf3d]` table (if any)
//! replaced by the tuned one, each value under a comment saying how it was found (or that
//! it was kept: a doubt). The tune's own header lines go inside the table, so that tuning
//! a tuned file again replaces them too. `pendtilt estimate --params` reads it as it is.
use super::Tuned3d;
use crate::bank::spatial::rig::Ekf3dConfig;
use crate::tune::Note;

/// `text` without its `[ekf3d]` table (the header line to the next table's).
fn without_ekf3d(text: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with('[') {
            inside = t.trim_start_matches('[').trim_end_matches(']').trim() == "ekf3d";
        }
        if !inside {
            out.push_str(line);
            out.push('\n');
        }
    }
    while out.ends_with("\n\n") {
        out.pop();
    }
    out
}

/// The `(key, value)` lines of an `[ekf3d]` table, every key given.
fn keys(c: &Ekf3dConfig) -> Vec<(&'static str, String)> {
    let f = |v: Option<f64>| v.map(|x| format!("{x:?}"));
    let b = |v: Option<bool>| v.map(|x| x.to_string());
    [
        ("vibration_density", f(c.vibration_density)),
        ("encoder_jitter", f(c.encoder_jitter)),
        ("encoder_bits", c.encoder_bits.map(|x| x.to_string())),
        ("encoder_noise", f(c.encoder_noise)),
        ("gyro_density", f(c.gyro_density)),
        ("gyro_bias_walk", f(c.gyro_bias_walk)),
        ("gyro_bias", f(c.gyro_bias)),
        ("accel_density", f(c.accel_density)),
        ("speed_noise", f(c.speed_noise)),
        ("jerk_density", f(c.jerk_density)),
        ("angular_accel_hz", f(c.angular_accel_hz)),
        ("angular_accel_lead", b(c.angular_accel_lead)),
        ("path_turn_hz", f(c.path_turn_hz)),
        ("path_pitch_hz", f(c.path_pitch_hz)),
        ("use_accel", b(c.use_accel)),
        ("adapt", b(c.adapt)),
        ("adapt_min_factor", f(c.adapt_min_factor)),
        ("adapt_max_factor", f(c.adapt_max_factor)),
        ("guard_angle", f(c.guard_angle)),
        ("pendulum_range", f(c.pendulum_range)),
    ]
    .into_iter()
    .filter_map(|(k, v)| v.map(|v| (k, v)))
    .collect()
}

/// The comment lines of one note (about 86 characters wide).
fn comment(n: &Note) -> Vec<String> {
    let head = if n.kept_default {
        format!("{} = {}: KEPT:", n.key, n.value)
    } else {
        format!("{} = {}: tuned:", n.key, n.value)
    };
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in format!("{head} {}", n.how).split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > 86 {
            lines.push(format!("# {}", std::mem::take(&mut line)));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(format!("# {line}"));
    }
    lines
}

/// True for a note whose value is a doubt: kept from the start, or measured with a
/// doubt its text gives (`DOUBT:`).
pub fn is_doubt(n: &Note) -> bool {
    n.kept_default || n.how.contains("DOUBT")
}

/// The tuned rig file: `start_text` (the `--params` file, or a rig written for the
/// default) without its `[ekf3d]`, then the tuned table with `header` and the notes of
/// `t` as comments.
pub fn tuned_toml(start_text: &str, t: &Tuned3d, header: &[String]) -> String {
    let mut out = without_ekf3d(start_text);
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    out.push_str("\n[ekf3d]\n");
    for h in header {
        out.push_str(&format!("# {h}\n"));
    }
    let doubts: Vec<&str> = t
        .notes
        .iter()
        .filter(|n| is_doubt(n))
        .map(|n| n.key.as_str())
        .collect();
    if !doubts.is_empty() {
        out.push_str(&format!(
            "# doubts (values the log did not tell, the start's kept, or told only in part: \
             see each one's note): {}\n",
            doubts.join(", ")
        ));
    }
    for (k, v) in keys(&t.config) {
        let key = format!("ekf3d.{k}");
        for n in t.notes.iter().filter(|n| n.key == key) {
            for c in comment(n) {
                out.push_str(&c);
                out.push('\n');
            }
        }
        out.push_str(&format!("{k} = {v}\n"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_old_table_goes_and_the_others_stay() {
        let t = "[pendulum3d]\nmass = 0.05\n\n[ekf3d]\n# old\nvibration_density = 0.1\n\n\
                 [gyro]\nfull_scale = 8.0\n";
        let w = without_ekf3d(t);
        assert_eq!(w, "[pendulum3d]\nmass = 0.05\n\n[gyro]\nfull_scale = 8.0\n");
    }

    /// Every key of the table is written (a key added later must be added to `keys`).
    #[test]
    fn every_key_is_written() {
        let c = Ekf3dConfig {
            vibration_density: Some(1.0),
            angular_accel_hz: Some(1.0),
            angular_accel_lead: Some(true),
            speed_noise: Some(1.0),
            jerk_density: Some(1.0),
            path_turn_hz: Some(1.0),
            path_pitch_hz: Some(1.0),
            encoder_jitter: Some(1.0),
            use_accel: Some(true),
            adapt: Some(true),
            adapt_min_factor: Some(1.0),
            adapt_max_factor: Some(2.0),
            guard_angle: Some(1.0),
            pendulum_range: Some(1.0),
            encoder_bits: Some(1),
            encoder_noise: Some(1.0),
            gyro_density: Some(1.0),
            gyro_bias_walk: Some(1.0),
            gyro_bias: Some(1.0),
            accel_density: Some(1.0),
        };
        let text: String = keys(&c)
            .iter()
            .map(|(k, v)| format!("{k} = {v}\n"))
            .collect();
        let rig = format!("[pendulum3d]\n[ekf3d]\n{text}");
        let r = crate::bank::spatial::rig::Rig3dConfig::from_toml_str(&rig, "t").unwrap();
        assert_eq!(r.ekf3d, c);
    }
}
