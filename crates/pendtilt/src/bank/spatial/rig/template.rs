//! The 3-D rig file with every key at its default and what it means (`pendtilt rig
//! --template 3d`).
use pendtilt_core::spatial::ekf;

use crate::sim::spatial::{Mounting, Pendulum3d};

/// A table's (key, value, comment) lines.
type Keys = Vec<(&'static str, String, &'static str)>;

/// A vector as the file writes it.
fn v(x: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", x[0], x[1], x[2])
}

/// A number as the file writes it.
fn f(x: f64) -> String {
    format!("{x:?}")
}

/// A 3-D rig file with every key at its default and what it means: MODEL.md 7.6's rig,
/// the sensors at P1, the filters' defaults. It reads back as
/// [`Rig3dConfig::default`](super::Rig3dConfig::default) with every `[ekf3d]` key given at
/// its default.
pub fn template() -> String {
    let e = ekf::Settings::<f64>::default();
    let mut ekf3d = ekf3d_keys(&e);
    ekf3d.extend(sensor_keys(&e.sensors));
    let tables: [(&str, Keys); 3] = [
        ("pendulum3d", pendulum3d_keys(&Pendulum3d::default())),
        ("mounting", mounting_keys(&Mounting::default())),
        ("ekf3d", ekf3d),
    ];
    let mut out = String::from(
        "# pendtilt 3-D rig file (MODEL.md 7.6). SI units, angles in rad.\n\
         # [pendulum3d] is required, in this physical form or the normalised one (a_x, a_y,\n\
         # b_x, b_y, b_z, b_ring, c, gravity: MODEL.md 7.3, every key); the other tables and\n\
         # every key in them are optional, each shown here at its default.\n",
    );
    for (name, keys) in tables {
        out.push_str(&format!("\n[{name}]\n"));
        for (k, value, what) in keys {
            out.push_str(&format!("{:<36} # {what}\n", format!("{k} = {value}")));
        }
    }
    out.push_str(&format!(
        "\n[gyro]\n{:<36} # the gyro's full scale [rad/s]; default: unknown\n",
        "# full_scale = 8.73"
    ));
    out
}

/// `[pendulum3d]`, the physical form.
fn pendulum3d_keys(p: &Pendulum3d) -> Keys {
    vec![
        ("mass", f(p.mass), "m [kg]"),
        (
            "length",
            f(p.length),
            "l, pivot P2 to the centre of mass [m]",
        ),
        (
            "inertia_xx",
            f(p.inertia_xx),
            "Ixx about P2, pendulum axes, with m l^2 [kg m^2]",
        ),
        ("inertia_yy", f(p.inertia_yy), "Iyy [kg m^2]"),
        ("inertia_zz", f(p.inertia_zz), "Izz, small and > 0 [kg m^2]"),
        (
            "ring_inertia",
            f(p.ring_inertia),
            "the outer ring about body x [kg m^2]",
        ),
        (
            "damping_x",
            f(p.damping_x),
            "C_x, outer joint viscous damping [N m s/rad]",
        ),
        ("damping_y", f(p.damping_y), "C_y, inner joint [N m s/rad]"),
        (
            "pivot_offset",
            v(p.pivot_offset),
            "P2 - P1, body axes (x fwd, y left, z up) [m]",
        ),
        ("gravity", f(p.gravity), "g [m/s^2]"),
    ]
}

/// `[mounting]`.
fn mounting_keys(m: &Mounting) -> Keys {
    vec![
        (
            "accel_at",
            v(m.accel_at),
            "the accelerometer - P1, body axes [m]",
        ),
        (
            "speed_at",
            v(m.speed_at),
            "O - P1: the point `speed` is of; else the pivot of turns [m]",
        ),
    ]
}

/// `[ekf3d]`: the filter's own keys.
fn ekf3d_keys(e: &ekf::Settings<f64>) -> Keys {
    vec![
        (
            "vibration_density",
            f(e.environment.vibration_density),
            "vibration near the pendulum [m/s^2/sqrt(Hz)]",
        ),
        (
            "adapt",
            e.adaptation.enabled.to_string(),
            "adapt the forcing to the log (docs/adaptation.md)",
        ),
        (
            "adapt_min_factor",
            f(e.adaptation.min_factor),
            "the adaptation's floor, times vibration_density^2",
        ),
        (
            "adapt_max_factor",
            f(e.adaptation.max_factor),
            "the adaptation's ceiling, times vibration_density^2",
        ),
        (
            "encoder_jitter",
            f(e.encoder_jitter),
            "encoder jitter from vibration above the band [rad]",
        ),
        (
            "angular_accel_hz",
            f(e.angular_accel_hz),
            "cutoff of the gyro's derivative [Hz]",
        ),
        (
            "angular_accel_lead",
            e.angular_accel_lead.to_string(),
            "take that filter's delay out",
        ),
        (
            "speed_noise",
            f(e.speed.noise),
            "the speed column's noise [m/s]",
        ),
        (
            "jerk_density",
            f(e.speed.jerk_density),
            "the vehicle's jerk [m/s^3/sqrt(Hz)]",
        ),
        (
            "path_turn_hz",
            f(e.path.path_turn_hz),
            "low-pass of the path's turn rate [Hz], inf: as read",
        ),
        (
            "path_pitch_hz",
            f(e.path.path_pitch_hz),
            "low-pass of the path's pitch rate [Hz]",
        ),
        (
            "use_accel",
            e.use_accel.to_string(),
            "the accelerometer as a further up measurement",
        ),
        (
            "guard_angle",
            f(e.guard_angle),
            "reset to the gyro+accel reference beyond this [rad]",
        ),
        (
            "pendulum_range",
            f(e.pendulum_range),
            "the pendulum unused beyond this swing [rad]",
        ),
    ]
}

/// `[ekf3d]`: the sensors' noise figures.
fn sensor_keys(n: &pendtilt_core::ekf::SensorNoise<f64>) -> Keys {
    vec![
        (
            "encoder_bits",
            n.encoder_bits.to_string(),
            "encoder resolution, bits per turn (0: none)",
        ),
        (
            "encoder_noise",
            f(n.encoder_noise),
            "encoder white noise [rad]",
        ),
        (
            "gyro_density",
            f(n.gyro_density),
            "gyro noise density [rad/s/sqrt(Hz)]",
        ),
        (
            "gyro_bias_walk",
            f(n.gyro_bias_walk),
            "gyro bias random walk [rad/s/sqrt(s)]",
        ),
        (
            "gyro_bias",
            f(n.gyro_bias),
            "spread of the gyro's initial bias [rad/s]",
        ),
        (
            "accel_density",
            f(n.accel_density),
            "accelerometer noise density [m/s^2/sqrt(Hz)]",
        ),
    ]
}
