//! The rig file a 3-D fit writes: the fitted pendulum as MODEL.md 7.6's `[pendulum3d]`
//! (normalised, or physical when the mass and length are known) and the start rig's
//! `[mounting]`, `[ekf3d]` and `[gyro]` tables as they were, so that `pendtilt estimate
//! LOG --params RIG` reads it as it is.
use pendtilt_core::spatial::cardan::CardanParams;

use crate::bank::spatial::rig::Rig3dConfig;
use crate::sim::spatial::Pendulum3d;

/// A value written so that it reads back exactly (Rust's shortest round-trip form).
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The physical pendulum of `c` with mass `mass` \[kg\] and length `length` \[m\]: every
/// normalised value times m g l (c times g for the pivot offset).
pub fn physical(c: &CardanParams<f64>, mass: f64, length: f64) -> Pendulum3d {
    let mgl = mass * c.gravity * length;
    Pendulum3d {
        mass,
        length,
        inertia_xx: c.b_x * mgl,
        inertia_yy: c.b_y * mgl,
        inertia_zz: c.b_z * mgl,
        ring_inertia: c.b_ring * mgl,
        damping_x: c.a_x * mgl,
        damping_y: c.a_y * mgl,
        pivot_offset: c.c.map(|v| v * c.gravity),
        gravity: c.gravity,
    }
}

/// The rig file's text: `header` as comment lines, `[pendulum3d]` from `c` (physical with
/// `mass_length`, else normalised), then the start rig's other tables.
pub fn rig_toml(
    c: &CardanParams<f64>,
    mass_length: Option<(f64, f64)>,
    start: &Rig3dConfig,
    header: &[String],
) -> Result<String, String> {
    let mut out: String = header.iter().map(|l| format!("# {l}\n")).collect();
    out.push_str("[pendulum3d]\n");
    let v = |x: [f64; 3]| format!("[{}, {}, {}]", num(x[0]), num(x[1]), num(x[2]));
    match mass_length {
        Some((m, l)) => {
            let p = physical(c, m, l);
            for (k, x) in [
                ("mass", p.mass),
                ("length", p.length),
                ("inertia_xx", p.inertia_xx),
                ("inertia_yy", p.inertia_yy),
                ("inertia_zz", p.inertia_zz),
                ("ring_inertia", p.ring_inertia),
                ("damping_x", p.damping_x),
                ("damping_y", p.damping_y),
            ] {
                out.push_str(&format!("{k} = {}\n", num(x)));
            }
            out.push_str(&format!("pivot_offset = {}\n", v(p.pivot_offset)));
            out.push_str(&format!("gravity = {}\n", num(p.gravity)));
        }
        None => {
            for (k, x) in [
                ("a_x", c.a_x),
                ("a_y", c.a_y),
                ("b_x", c.b_x),
                ("b_y", c.b_y),
                ("b_z", c.b_z),
                ("b_ring", c.b_ring),
            ] {
                out.push_str(&format!("{k} = {}\n", num(x)));
            }
            out.push_str(&format!("c = {}\n", v(c.c)));
            out.push_str(&format!("gravity = {}\n", num(c.gravity)));
        }
    }
    if start.mounting_given {
        let m = start.mounting;
        out.push_str(&format!(
            "\n[mounting]\naccel_at = {}\nspeed_at = {}\n",
            v(m.accel_at),
            v(m.speed_at)
        ));
    }
    let ekf = toml::to_string(&start.ekf3d).map_err(|e| e.to_string())?;
    if !ekf.trim().is_empty() {
        out.push_str(&format!("\n[ekf3d]\n{ekf}"));
    }
    if let Some(fs) = start.gyro.full_scale {
        out.push_str(&format!("\n[gyro]\nfull_scale = {}\n", num(fs)));
    }
    // What is written must read back as the same pendulum.
    let back = Rig3dConfig::from_toml_str(&out, "the fitted rig")?;
    let p = back.pendulum3d.params();
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-300);
    if !(same(p.a_x, c.a_x) && same(p.b_x, c.b_x) && same(p.b_y, c.b_y) && same(p.a_y, c.a_y)) {
        return Err(format!(
            "the fitted rig does not read back as fitted: {p:?}"
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both forms read back as the fitted pendulum, and the start rig's tables are kept.
    #[test]
    fn both_forms_round_trip_with_the_start_tables() {
        let start = Rig3dConfig::from_toml_str(
            "[pendulum3d]\n[mounting]\naccel_at = [0.01, 0.0, 0.02]\nspeed_at = [0.0, 0.0, -0.25]\n\
             [ekf3d]\nvibration_density = 0.2\n[gyro]\nfull_scale = 8.7\n",
            "start.toml",
        )
        .unwrap();
        let c = CardanParams {
            a_x: 0.031,
            b_ring: 0.001,
            c: [0.0, 0.0, 5e-4],
            ..CardanParams::default()
        };
        for ml in [None, Some((0.08, 0.04))] {
            let text = rig_toml(&c, ml, &start, &["fitted".into()]).unwrap();
            let back = Rig3dConfig::from_toml_str(&text, "out.toml").unwrap();
            let p = back.pendulum3d.params();
            assert!((p.a_x - c.a_x).abs() < 1e-12 * c.a_x && (p.c[2] - c.c[2]).abs() < 1e-15);
            assert_eq!(back.mounting, start.mounting);
            assert_eq!(back.ekf3d, start.ekf3d);
            assert_eq!(back.gyro.full_scale, Some(8.7));
            assert!(text.starts_with("# fitted\n[pendulum3d]\n"), "{text}");
        }
    }
}
