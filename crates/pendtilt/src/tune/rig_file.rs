//! The tuned settings as a rig file: the start's file with the tuned `[kalman]`,
//! `[differentiator]` and `[ekf]` values, each preceded by a comment saying how it was
//! found (or why it kept its default), as `pendtilt tune` writes it. `pendtilt estimate`
//! reads it as it is: the comments are TOML comments.
use super::{Note, Tuned};
use crate::config::{EkfConfig, RigConfig};

/// `rig` with the tuned values of `t`: the Kalman filters' noise, the differentiator of
/// Algorithms 1-3, and the EKF/UKF's sensor figures and process noise (`[ekf]`, every key).
pub fn tuned_rig(rig: &RigConfig, t: &Tuned) -> RigConfig {
    let mut out = rig.clone();
    out.kalman.q_angle = t.kalman.q_angle;
    out.kalman.q_bias = t.kalman.q_bias;
    out.kalman.r_pendulum = t.kalman.r_pendulum;
    out.kalman.r_accel = t.kalman.r_accel;
    out.kalman.r_accel_fused = t.kalman.r_accel_fused;
    out.differentiator = t.differentiator;
    out.alg1.cutoff_times_natural = t.alg1_cutoff.map(|c| c.0);
    out.ekf = EkfConfig::from_settings(&t.ekf);
    out
}

/// The (table, key) of the rig file a note's value is written under; `key` `None` for a
/// value the file has under whichever key of the table it writes (the cutoff is
/// `cutoff_hz` or `cutoff_times_natural`, or absent at its default).
fn place(note_key: &str) -> (&str, Option<&str>) {
    if let Some(k) = note_key.strip_prefix("sensors.") {
        return ("ekf", Some(k));
    }
    match note_key {
        "accel_vibration" => ("ekf", Some("accel_vibration")),
        "ekf.process.jerk" => ("ekf", Some("process_jerk")),
        "ekf.process.pendulum" => ("ekf", Some("process_pendulum")),
        "differentiator.cutoff_hz" => ("differentiator", None),
        other => match other.split_once('.') {
            Some((table, key)) => (table, Some(key)),
            None => ("", None),
        },
    }
}

/// Splits `text` into comment lines of at most about `width` characters.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// The comment lines of one note.
fn comment(n: &Note) -> Vec<String> {
    let head = if n.kept_default {
        format!("{} = {}: KEPT (default):", n.key, n.value)
    } else {
        format!("{} = {}: tuned:", n.key, n.value)
    };
    wrap(&format!("{head} {}", n.how), 86)
        .into_iter()
        .map(|l| format!("# {l}"))
        .collect()
}

/// The rig file text of `rig` (as [`tuned_rig`] made it) with `header` lines first (each
/// written as a comment) and each note of `t` as comments above the value it is about
/// (above its table's header when the file leaves the value out at its default).
pub fn annotated_toml(rig: &RigConfig, t: &Tuned, header: &[String]) -> String {
    let body = rig.to_toml_string();
    let mut out: String = header.iter().map(|h| format!("# {h}\n")).collect();
    let mut table = String::new();
    let lines: Vec<&str> = body.lines().collect();
    // Which notes find their key in the file: the rest go above their table.
    let key_in = |tbl: &str, key: Option<&str>| {
        let mut cur = "";
        lines.iter().any(|l| {
            let l = l.trim();
            if let Some(name) = l.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
                cur = name;
                return false;
            }
            let k = l.split('=').next().unwrap_or("").trim();
            cur == tbl
                && !l.starts_with('#')
                && l.contains('=')
                && key.map_or(k.starts_with("cutoff"), |key| k == key)
        })
    };
    for line in &lines {
        let trimmed = line.trim();
        if let Some(name) = trimmed.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
            table = name.to_string();
            for n in &t.notes {
                let (tbl, key) = place(&n.key);
                if tbl == table && !key_in(tbl, key) {
                    out.extend(comment(n).into_iter().map(|c| c + "\n"));
                }
            }
        } else if trimmed.contains('=') && !trimmed.starts_with('#') {
            let k = trimmed.split('=').next().unwrap_or("").trim();
            for n in &t.notes {
                let (tbl, key) = place(&n.key);
                if tbl == table && key.map_or(k.starts_with("cutoff"), |key| key == k) {
                    out.extend(comment(n).into_iter().map(|c| c + "\n"));
                }
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_note_key_has_a_place_in_the_file() {
        for key in [
            "sensors.encoder_bits",
            "sensors.encoder_noise",
            "ekf.encoder_jitter",
            "sensors.gyro_density",
            "sensors.gyro_bias",
            "sensors.accel_density",
            "accel_vibration",
            "kalman.q_angle",
            "kalman.q_bias",
            "kalman.r_pendulum",
            "kalman.r_accel",
            "kalman.r_accel_fused",
            "ekf.process.jerk",
            "ekf.process.pendulum",
            "differentiator.cutoff_hz",
            "alg1.cutoff_times_natural",
        ] {
            let (table, k) = place(key);
            assert!(
                ["ekf", "kalman", "differentiator", "alg1"].contains(&table),
                "{key}"
            );
            if let Some(k) = k {
                // The key is one the rig file accepts in that table.
                let text = format!("[{table}]\n{k} = 1\n");
                RigConfig::from_toml_str(&text, "t").unwrap();
            }
        }
    }

    #[test]
    fn wrap_keeps_words_and_width() {
        let w = wrap("aaa bbb ccc ddd", 7);
        assert_eq!(w, vec!["aaa bbb", "ccc ddd"]);
    }
}
