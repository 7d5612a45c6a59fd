//! Help texts made from the code's own tables (the estimator registry, the named
//! scenarios, the default rig), so that `--help` shows every default and name without a
//! second copy that could drift.
use crate::bank::planar::{Inputs, REGISTRY};
use crate::config::RigConfig;
use crate::sim::planar::motion::Motion;
use crate::sim::planar::{Scenario, SCENARIO_NAMES};

/// The input columns and their units (MODEL.md section 5), for `estimate` and `stream`.
pub const INPUT_UNITS: &str = "Input columns (MODEL.md section 5, SI units): t [s], strictly \
increasing; phi [rad], the pendulum angle relative to the body (encoder); gyro [rad/s], body \
rate about the tilt axis, CCW positive; ax, ay [m/s^2], accelerometer specific force in body \
axes; theta [rad], the true tilt (optional, copied to the output). Angles in degrees: --deg; \
t in ms or us: --time-unit; the accelerometer in g or mg: --accel-unit. Other column names: \
--map. A gyro or accelerometer reading beyond \
the rig's [gyro]/[accel] full_scale (without one: 100 rad/s, 500 m/s^2) is read as missing \
and flagged implausible; one at it is kept and flagged saturated; without a full scale, a \
clip is found in the readings themselves (one value on several rows in a row, which a noisy \
sensor never writes), warned and flagged saturated. While the gyro clips often (8 % of the \
readings over 3 s), ekf and ukf do not use it until 1 s after (flagged saturated). The \
estimates are written in rad (--out-deg: deg), t in s.";

/// The estimators the bank knows, one line each: name, the columns it needs, what it is.
pub fn estimator_list() -> String {
    let width = REGISTRY.iter().map(|e| e.name.len()).max().unwrap_or(0);
    let mut s = String::from(
        "Estimators (one output column each; an estimator whose columns are missing is \
         skipped, and said so; --only picks some):\n",
    );
    for e in REGISTRY {
        let needs = Inputs::default().lacking(e.needs()).join(", ");
        s.push_str(&format!(
            "  {:width$}  needs {:22} {}\n",
            e.name,
            needs,
            e.about(),
            width = width
        ));
    }
    s
}

/// What `estimate --help` and `stream --help` print after the options.
pub fn estimate_after_help() -> String {
    format!(
        "{}\n{INPUT_UNITS}\n\n{}",
        estimator_list(),
        estimator3d_list()
    )
}

/// The 3-D estimators ([`crate::bank::spatial::REGISTRY3D`]) and how a 3-D log is told.
pub fn estimator3d_list() -> String {
    use crate::bank::spatial::REGISTRY3D;
    let width = REGISTRY3D.iter().map(|e| e.name.len()).max().unwrap_or(0);
    let mut s = String::from(
        "3-D logs (MODEL.md 7.6: a header with t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, \
         az; roll, pitch as truth, speed optional) run the 3-D estimators, columns \
         <name>_roll, <name>_pitch (--quaternion: <name>_qw.._qz where marked q), and print \
         the inclination error when the log has roll and pitch:\n",
    );
    for e in REGISTRY3D {
        let q = if e.quaternion { "q" } else { " " };
        s.push_str(&format!(
            "  {:width$} {q}  {}\n",
            e.name,
            e.about(),
            width = width
        ));
    }
    s
}

/// `value` for each named scenario, as "X in every scenario" when they all agree, else
/// "still X, sigmoid Y, ..." (scenarios where `value` is `None` are left out).
pub fn per_scenario(value: impl Fn(&Scenario) -> Option<String>) -> String {
    let values: Vec<(&str, String)> = SCENARIO_NAMES
        .iter()
        .filter_map(|&n| {
            let s = Scenario::named(n).ok()?;
            value(&s).map(|v| (n, v))
        })
        .collect();
    match values.first() {
        Some((_, first))
            if values.len() == SCENARIO_NAMES.len() && values.iter().all(|(_, v)| v == first) =>
        {
            format!("{first} in every scenario")
        }
        _ => values
            .iter()
            .map(|(n, v)| format!("{n} {v}"))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// `text`, then the scenario defaults of `value`.
fn with_scenario_default(text: &str, value: impl Fn(&Scenario) -> Option<String>) -> String {
    format!("{text} [default: {}]", per_scenario(value))
}

fn num(x: f64) -> Option<String> {
    Some(format!("{x}"))
}

/// `simulate --duration`.
pub fn duration() -> String {
    with_scenario_default("Length of the run (s)", |s| num(s.duration))
}

/// `simulate --rate`.
pub fn rate() -> String {
    with_scenario_default("Sample rate (Hz)", |s| num(s.rate))
}

/// `simulate --substeps`.
pub fn substeps() -> String {
    with_scenario_default("RK4 steps per sample", |s| Some(s.substeps.to_string()))
}

/// `simulate --mass`, `--length`, ...: the scenario's pendulum (the MODEL.md rig).
pub fn pendulum(text: &str, field: fn(&crate::sim::planar::PendulumTable) -> f64) -> String {
    with_scenario_default(text, |s| num(field(&s.pendulum)))
}

/// `simulate --amplitude`: the size of each scenario's motion.
pub fn amplitude() -> String {
    with_scenario_default(
        "Size of the body motion (rad): the amplitude, the angle of `still`, the soft limit \
         of `scooter`",
        |s| {
            let a = match &s.motion {
                Motion::Still(m) => m.angle,
                Motion::Sigmoid(m) => m.amplitude,
                Motion::Step(m) => m.amplitude,
                Motion::Sine(m) => m.amplitude,
                Motion::Chirp(m) => m.amplitude,
                Motion::Manoeuvres(m) => m.amplitude,
            };
            Some(format!("{a:.4}"))
        },
    )
}

/// `simulate --frequency`.
pub fn frequency() -> String {
    with_scenario_default("Frequency of the `sine` motion (Hz)", |s| match &s.motion {
        Motion::Sine(m) => num(m.frequency),
        _ => None,
    })
}

/// `simulate --engine-hz`.
pub fn engine_hz() -> String {
    with_scenario_default(
        "Engine fundamental (Hz): every vibration harmonic keeps its ratio to the first; \
         only for scenarios with engine vibration",
        |s| s.vibration.harmonics.first().and_then(|h| num(h.frequency)),
    )
}

/// `simulate --accel-mount`.
pub fn accel_mount() -> String {
    with_scenario_default(
        "Accelerometer position relative to P2 in body axes (m), e.g. `--accel-mount \
         0.02,-0.1`",
        |s| {
            let [x, y] = s.sensors.accel.mount;
            Some(format!("{x},{y}"))
        },
    )
}

/// `simulate --encoder-bits`.
pub fn encoder_bits() -> String {
    with_scenario_default(
        "Encoder resolution (bits per turn); 0 = no quantisation",
        |s| Some(s.sensors.encoder.bits.to_string()),
    )
}

/// `fit --a` and `fit --b`: the start value when neither the option nor `--params` gives
/// one.
pub fn fit_start(which: char) -> String {
    let p = RigConfig::default().params();
    let (v, unit) = if which == 'a' {
        (p.a, "s")
    } else {
        (p.b, "s^2")
    };
    format!(
        "Start {which} ({unit}), overriding the rig file [default: from --params, else the \
         MODEL.md rig's {v:.6e}]"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_has_every_registered_estimator_with_what_it_needs() {
        let list = estimator_list();
        for e in REGISTRY {
            assert!(list.contains(&format!("  {}", e.name)), "{list}");
            assert!(list.contains(e.about()), "{list}");
        }
        assert!(list.contains("needs phi, gyro"), "{list}");
        assert!(list.contains("needs ax/ay"), "{list}");
    }

    #[test]
    fn per_scenario_defaults_name_each_scenario_or_say_every() {
        let d = duration();
        for n in SCENARIO_NAMES {
            let s = Scenario::named(n).unwrap();
            assert!(d.contains(&format!("{n} {}", s.duration)), "{d}");
        }
        assert!(rate().contains("1000 in every scenario"), "{}", rate());
        // Only the sine has a frequency: one entry, not "every scenario".
        assert!(frequency().contains("[default: sine "), "{}", frequency());
    }
}
