//! What `pendtilt replay` writes and the checks on its inputs: the 3-D log of a replay
//! (MODEL.md 7.6), the rig file beside it, the physical pendulum of a rig's `[pendulum3d]`,
//! the added vehicle vibration of a named scenario, and the doubt about the
//! accelerometer's unit.
use std::io::Write;
use std::path::Path;

use anyhow::bail;

use super::{AddedVibration, Replay};
use crate::bank::spatial::rig::{Pendulum3dConfig, Rig3dConfig};
use crate::sim::spatial::{LogRow3d, Mounting, Pendulum3d, Rig3d};

/// The physical pendulum of a rig's `[pendulum3d]`: a normalised one is given m g l = 1
/// (unobservable, MODEL.md 7.3: the dynamics are the same).
pub fn physical(p: &Pendulum3dConfig) -> Pendulum3d {
    match *p {
        Pendulum3dConfig::Physical(p) => p,
        Pendulum3dConfig::Normalised(c) => Pendulum3d {
            mass: 1.0,
            length: 1.0 / c.gravity,
            inertia_xx: c.b_x,
            inertia_yy: c.b_y,
            inertia_zz: c.b_z,
            ring_inertia: c.b_ring,
            damping_x: c.a_x,
            damping_y: c.a_y,
            pivot_offset: c.c.map(|x| x * c.gravity),
            gravity: c.gravity,
        },
    }
}

/// Writes the replay's rows as a 7.6 log: the IMU columns, the encoders, the truth when
/// the recording has one. Shortest round-trip numbers: a wrapped encoder never prints
/// beyond pi.
pub fn write_log<W: Write>(r: &Replay, has_truth: bool, mut w: W) -> std::io::Result<()> {
    let cols = if has_truth { 11 } else { 9 };
    let names: Vec<&str> = LogRow3d::COLUMNS
        .iter()
        .copied()
        .filter(|c| *c != "speed")
        .take(cols)
        .collect();
    writeln!(w, "{}", names.join(","))?;
    let mut buf = ryu::Buffer::new();
    for row in &r.rows {
        let v = row.values();
        let vals = v[..9].iter().chain(v[10..].iter()).take(cols);
        for (i, x) in vals.enumerate() {
            if i > 0 {
                w.write_all(b",")?;
            }
            if x.is_finite() {
                w.write_all(buf.format(*x).as_bytes())?;
            }
        }
        w.write_all(b"\n")?;
    }
    w.flush()
}

/// The named 3-D scenario's vibration to add to a replay (`--vibration`), clipped at
/// `accel_full_scale` m/s^2 and its random tones drawn with `seed`; None without a name.
pub fn added_vibration(
    name: Option<&str>,
    seed: u64,
    accel_full_scale: f64,
) -> anyhow::Result<Option<AddedVibration>> {
    Ok(match name {
        Some(name) => {
            if !crate::sim::spatial::SCENARIO3D_NAMES.contains(&name) {
                bail!(
                    "--vibration {name}: not a 3-D scenario (they are: {})",
                    crate::sim::spatial::SCENARIO3D_NAMES.join(", ")
                );
            }
            if !(accel_full_scale.is_finite() && accel_full_scale > 0.0) {
                bail!("--accel-full-scale {accel_full_scale}: must be > 0 m/s^2");
            }
            let mut v = AddedVibration::of_scenario(name, seed)?;
            v.accel_full_scale = accel_full_scale;
            Some(v)
        }
        None => None,
    })
}

/// The rig file written beside the log: the virtual pendulum (its gravity the recording's
/// at rest) and the `--params` rig's mounting; `input` is the recording it was made from.
pub fn rig_text(input: &Path, out: &Replay, rig: Option<&Rig3dConfig>) -> anyhow::Result<String> {
    let rig_text = Rig3d {
        pendulum3d: out.pendulum,
        mounting: rig.map_or(Mounting::default(), |r| r.mounting),
    }
    .to_toml_string()?;
    Ok(format!(
        "# Written by `pendtilt replay` for {}: the virtual pendulum, its gravity the\n\
         # recording's mean |a| at rest.\n{rig_text}",
        input.display()
    ))
}

/// A warning when the specific force at rest is not gravity's in size (an accelerometer in
/// g or mg, read as m/s^2), with the option that fixes it; `input` is the recording.
pub fn accel_unit_doubt(input: &Path, gravity: f64) -> Option<String> {
    let g = crate::io::STANDARD_GRAVITY;
    if (0.5 * g..=2.0 * g).contains(&gravity) {
        return None;
    }
    let fix = if (0.5..=2.0).contains(&gravity) {
        "--accel-unit g"
    } else if (500.0..=2000.0).contains(&gravity) {
        "--accel-unit mg"
    } else {
        "--accel-unit"
    };
    Some(format!(
        "warning: {}: the specific force at rest is {gravity:.4} in the accelerometer's \
         unit, not gravity's 9.81 m/s^2: give {fix} (the pendulum was driven as read)",
        input.display()
    ))
}
