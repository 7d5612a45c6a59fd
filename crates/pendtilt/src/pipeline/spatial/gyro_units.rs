//! The gyro's unit and signs found from the physics, per axis, against the encoders.
use super::turn::{TurnCheck, TURN_HZ};
use crate::io::Log3dRecord;

/// The gyro's unit found from the physics, per axis, with the planar check
/// ([`crate::units::UnitCheck`]): below the pendulum's frequency the encoders follow the
/// tilt, so d(phi_x)/dt ~ gyro_x and d(phi_y)/dt ~ gyro_y (roll and pitch rates, for the
/// tilts of a vehicle); a gyro 57x that is in deg/s, 1/57 of it converted twice. The
/// sensor's height above the centre the body rotates about is fitted out
/// ([`crate::units::UnitCheck::lever_fit`]): on ship3d (IMU 5 m above it) the pendulum
/// swings 1.8x the pitch rate, so a gyro in deg/s read as 34x on pitch and was not found,
/// and as 45x on roll; with the height fitted (4.8 and 5.0 m) 56.8x and 56.6x.
pub(super) struct GyroUnits {
    axes: [crate::units::UnitCheck; 2],
    /// Gravity \[m/s^2\], for the height.
    gravity: f64,
    /// The yaw rate against the turn, for a vehicle with a speed (see [`TurnCheck`]).
    turn: TurnCheck,
}

impl GyroUnits {
    /// For the rig's pendulum, each axis below its own natural frequency (the default
    /// planar rig's, 2.19 Hz, let a 0.49 Hz pendulum's swing into the comparison: a gyro in
    /// deg/s read as 43x on ship3d's roll and was not found on its pitch).
    pub(super) fn new(params: &pendtilt_core::spatial::cardan::CardanParams<f64>) -> Self {
        // The accelerometer's tilt about each axis stands in for the planar check's angle:
        // its signs are checked against the encoder and the gyro.
        let inputs = crate::sensors::Inputs::ALL;
        let w = params.natural_frequencies();
        Self {
            turn: TurnCheck::new(),
            gravity: params.gravity,
            axes: std::array::from_fn(|i| {
                crate::units::UnitCheck::with_natural_frequency(
                    w[i] / std::f64::consts::TAU,
                    inputs,
                )
                .with_lever()
            }),
        }
    }

    /// One row as written (`k`: the --deg factor), before the plausibility bounds: a gyro
    /// in deg/s is beyond them.
    pub(super) fn add(&mut self, r: &Log3dRecord, dt: f64, k: f64) {
        let f = r.accel;
        // The accelerometer's roll atan2(f_y, f_z) and pitch atan2(-f_x, |f_yz|) (MODEL.md
        // 7.1) as the planar check's atan2(ax, ay).
        let tilt = [(f[1], f[2]), (-f[0], f[1].hypot(f[2]))];
        // The true roll and pitch, when the log has them, tell one reversed column from
        // the two others both reversed.
        let truth = [r.roll, r.pitch];
        for (i, axis) in self.axes.iter_mut().enumerate() {
            let s = pendtilt_core::Sample {
                dt,
                phi: r.phi[i] * k,
                gyro: r.gyro[i] * k,
                ax: tilt[i].0,
                ay: tilt[i].1,
            };
            axis.add(&s, truth[i]);
        }
        self.turn.add(dt, r.gyro[2] * k, r.accel[1], r.speed);
    }

    /// A column of axis `i` (0: x, roll; 1: y, pitch) that counts the other way, from the
    /// signs of the encoder against the accelerometer's tilt, the gyro against the encoder's
    /// rate (`gyro`, the pair or the lever fit) and against the tilt's rate: which one is
    /// reversed, with the fix. One column against the other two is also the other two
    /// reversed together (an IMU turned half round reverses the gyro and the accelerometer):
    /// the true roll or pitch, when logged, decides; without it the message gives both. Measured on scooter3d (30 s, seed 2): gyro_x negated gave
    /// ekf3d 11.3 deg RMS and the warning `gyro_x is -1.0x ...: is the gyro in deg/s?`;
    /// phi_x negated, ekf3d 13.3 with the same wrong warning; ay negated, VQF 8.0 and
    /// nothing said; ax negated, only the wheel-slip warning.
    fn sign_finding(
        axis: &crate::units::UnitCheck,
        i: usize,
        gyro: &crate::units::Fit,
    ) -> Option<String> {
        use crate::units::Comparison;
        let (g, phi, tilt, a, name) = [
            ("gyro_x", "phi_x", "roll atan2(ay, az)", "ay", "roll"),
            (
                "gyro_y",
                "phi_y",
                "pitch atan2(-ax, |(ay, az)|)",
                "ax",
                "pitch",
            ),
        ][i];
        let sign = "MODEL.md 7.1-7.2: body axes FLU (x forward, y left, z up), the gyro \
                    right-handed about them, and a pendulum at rest reads phi_x = roll, \
                    phi_y = pitch";
        let by_accel = axis.reversed(Comparison::EncoderAccel);
        let gyro_accel = axis.reversed(Comparison::GyroAccelRate);
        // One column against two, or those two both reversed (an IMU turned half round
        // about z reverses gyro_x and ay together): the true angle, if logged, decides.
        let truth_phi = axis.reversed(Comparison::TruthEncoder);
        let truth_accel = axis.reversed(Comparison::TruthAccel);
        Some(match (by_accel, crate::units::reversed(gyro), gyro_accel) {
            (Some(true), Some(true), _) if truth_phi == Some(false) => format!(
                "{g} and the accelerometer's {tilt} both count the other way from {phi} and \
                 from the true {name}: is the IMU turned half round? negate {g} and {a} in \
                 the log ({sign})"
            ),
            (Some(true), Some(true), _) => format!(
                "{phi} counts the other way from the accelerometer's {tilt} and from {g}: is \
                 the encoder's axis reversed? negate {phi} in the log{or} ({sign})",
                or = if truth_phi.is_none() {
                    format!("; or, if the IMU is turned half round, negate {g} and {a}")
                } else {
                    String::new()
                }
            ),
            (Some(false) | None, Some(true), Some(true)) => format!(
                "{g} counts the other way from the encoder's d({phi})/dt and from the rate \
                 of the accelerometer's {tilt}: is the gyro's axis reversed? negate {g} in \
                 the log ({sign})"
            ),
            (Some(true), Some(false), Some(true)) if truth_accel == Some(false) => format!(
                "{phi} and {g} both count the other way from the accelerometer's {tilt} and \
                 from the true {name}: are the encoder and the gyro both reversed? negate \
                 {phi} and {g} in the log ({sign})"
            ),
            (Some(true), Some(false), Some(true)) => format!(
                "the accelerometer's {tilt} counts the other way from {phi} and {g}: is {a} \
                 reversed? negate {a} in the log{or} ({sign})",
                or = if truth_accel.is_none() {
                    format!("; or, if the encoder and the gyro both are, negate {phi} and {g}")
                } else {
                    String::new()
                }
            ),
            (None, Some(true), None) => format!(
                "{g} and the encoder's d({phi})/dt count opposite ways: one of them is \
                 reversed; negate it in the log ({sign})"
            ),
            _ => return None,
        })
    }

    /// One warning per gyro axis found in deg/s (or converted twice).
    pub(super) fn findings(&self, file: &str) -> Vec<String> {
        let deg = crate::units::DEG;
        let mut out = Vec::new();
        for (i, axis) in self.axes.iter().enumerate() {
            let (gyro, phi) = [("gyro_x", "phi_x"), ("gyro_y", "phi_y")][i];
            // With the height fitted out, else the plain pair (too little curvature).
            let (f, how) = match axis.lever_fit(self.gravity) {
                Some(l) => (
                    l.fit,
                    format!(
                        "d({phi})/dt on the gyro and its second derivative, which takes out the \
                         swing of a sensor {:.1} m above the centre the body rotates about \
                         (phi ~ theta - (h / g) theta''), over {} rows below f_n / 4, R = {:.2}",
                        l.height, l.fit.samples, l.fit.correlation
                    ),
                ),
                None => match axis.fit(crate::units::Comparison::GyroEncoderRate) {
                    Some(f) => (
                        f,
                        format!(
                            "over {} rows below f_n / 4, r = {:.2}",
                            f.samples, f.correlation
                        ),
                    ),
                    None => continue,
                },
            };
            if let Some(m) = Self::sign_finding(axis, i, &f) {
                out.push(format!("{file}: {m} (least squares of {how})"));
                continue;
            }
            let unit = crate::units::unit_factor(&f);
            let what = if unit == Some(deg) {
                format!(
                    "{:.1}x the encoder's derivative d({phi})/dt: is the gyro in deg/s?",
                    f.factor
                )
            } else if unit == Some(1.0 / deg) {
                format!(
                    "1/{:.1} of the encoder's derivative d({phi})/dt: was the gyro converted \
                     to rad/s twice?",
                    1.0 / f.factor
                )
            } else {
                continue;
            };
            out.push(format!(
                "{file}: {gyro} is {what} Every estimator reading it is wrong by as much: \
                 write gyro_x, gyro_y, gyro_z in rad/s, or give --deg if every angular column \
                 (phi_x, phi_y, gyro_*, roll, pitch) is in degrees (least squares of {how})"
            ));
        }
        // Said once: what the encoders found, else what the turns say.
        if out.is_empty() {
            if let Some(f) = self.turn.fit() {
                if crate::units::unit_factor(&f) == Some(deg) {
                    out.push(format!(
                        "{file}: gyro_z is {:.1}x the yaw rate the turns imply (the lateral \
                         acceleration over the speed, a_y / v): is the gyro in deg/s? Every \
                         estimator reading it is wrong by as much: write gyro_x, gyro_y, gyro_z \
                         in rad/s, or give --deg if every angular column (phi_x, phi_y, gyro_*, \
                         roll, pitch) is in degrees (least squares over {} rows below {TURN_HZ} \
                         Hz, r = {:.2})",
                        f.factor, f.samples, f.correlation
                    ));
                }
            }
        }
        out
    }
}
