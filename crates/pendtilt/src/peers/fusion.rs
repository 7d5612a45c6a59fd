//! A Fusion-style complementary IMU filter (column `fusion3d`), the design of x-io
//! Technologies' Fusion AHRS (Madgwick's revised AHRS, his thesis chapter 7), written here
//! from its documentation: the gyro integrates an attitude quaternion, and the
//! accelerometer's disagreement with the estimated up direction, `a_hat x up_est`, is fed
//! back into the rate with a gain. Around that:
//!
//! - **start-up ramp**: the gain starts at [`FusionSettings::startup_gain`] and falls
//!   linearly to [`FusionSettings::gain`] over [`FusionSettings::startup_period`], so the
//!   first seconds converge fast; rejection is off meanwhile;
//! - **acceleration rejection**: a reading whose direction is more than
//!   [`FusionSettings::accel_rejection`] from the estimated up is not used (the step is
//!   flagged `measurement_skipped` by the wrapper);
//! - **acceleration recovery**: a trigger counts time rejected up and time accepted down
//!   nine times as fast, within `[0, recovery_period]`; once it passes
//!   [`FusionSettings::recovery_period`] (rejection most of the time for that long) every
//!   reading is used until the trigger is back at zero, so a wrong estimate cannot lock
//!   itself out;
//! - **angular-rate recovery**: a gyro reading beyond 98 % of
//!   [`FusionSettings::gyro_range`] cannot be integrated faithfully: the filter keeps its
//!   attitude and starts the ramp again.
//!
//! Why here and not in the no_std core: it is a peer, a filter users would run instead of
//! a pendulum, kept beside the other peers so that it shares their one wrapper
//! ([`super::spatial::Imu6`]: start at the first accelerometer reading, the gyro's recent
//! mean through a missing reading, the flags) and is compared on the same terms; pendtilt's
//! own estimators are the core's. It needs nothing beyond `f64` arithmetic, so moving it to
//! the core later is a copy.
//!
//! Units are SI (rad/s, m/s^2, s); the accelerometer's scale does not matter (only its
//! direction is used).
use super::spatial::ImuFilter;

/// The filter's settings (SI units). [`Default`] gives Fusion's documented recommendations
/// in SI: gain 0.5, acceleration rejection 10 deg, recovery trigger period 5 s, start-up
/// gain 10 ramped over 3 s, no gyro range (the rig does not give one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FusionSettings {
    /// Accelerometer feedback gain \[1/s\]: a tilt error decays at this rate (0.5: about
    /// 2 s). Fusion's recommended 0.5.
    pub gain: f64,
    /// The gain at the start, ramped down linearly to `gain` \[1/s\]. Default 10.
    pub startup_gain: f64,
    /// How long the ramp lasts \[s\]. Default 3.
    pub startup_period: f64,
    /// A reading further than this from the estimated up direction is ignored \[rad\];
    /// `f64::INFINITY` never ignores one (Fusion's 0); from 90 deg on, only a reading more
    /// than 90 deg away is ignored. Default 10 deg.
    pub accel_rejection: f64,
    /// Acceleration recovery trigger period \[s\] (see the module documentation). Default 5.
    pub recovery_period: f64,
    /// Gyro measurement range \[rad/s\]: a reading beyond 98 % of it restarts the ramp;
    /// `f64::INFINITY` turns the check off. Default off.
    pub gyro_range: f64,
}

/// [`FusionSettings::gain`]'s default \[1/s\].
pub const FUSION_GAIN: f64 = 0.5;

impl Default for FusionSettings {
    fn default() -> Self {
        Self {
            gain: FUSION_GAIN,
            startup_gain: 10.0,
            startup_period: 3.0,
            accel_rejection: 10f64.to_radians(),
            recovery_period: 5.0,
            gyro_range: f64::INFINITY,
        }
    }
}

/// The filter's state; build it with [`Fusion::new`] (the [`super::spatial::Imu6`] wrapper
/// drives it).
#[derive(Debug, Clone)]
pub struct Fusion {
    settings: FusionSettings,
    /// Attitude quaternion `[w, x, y, z]`, world <- body.
    q: [f64; 4],
    /// The gain of this step (ramped during start-up).
    ramped: f64,
    startup: bool,
    /// Acceleration recovery trigger \[s\], in `[0, recovery_period]`.
    trigger: f64,
    /// The trigger's current threshold \[s\]: `recovery_period`, or 0 while recovering.
    timeout: f64,
}

/// Hamilton product `a b`.
fn mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

impl Fusion {
    /// A filter at roll and pitch \[rad\] (zero yaw), at the start of its ramp.
    pub fn new(settings: FusionSettings, roll: f64, pitch: f64) -> Self {
        // q = q_y(pitch) q_x(roll): R = Ry(pitch) Rx(roll), MODEL.md 7.1's angles at yaw 0.
        let (sr, cr) = (roll / 2.0).sin_cos();
        let (sp, cp) = (pitch / 2.0).sin_cos();
        let q = mul([cp, 0.0, sp, 0.0], [cr, sr, 0.0, 0.0]);
        let mut f = Self {
            settings,
            q,
            ramped: settings.startup_gain,
            startup: true,
            trigger: 0.0,
            timeout: settings.recovery_period,
        };
        f.restart_ramp();
        f
    }

    /// The settings it runs with.
    pub fn settings(&self) -> &FusionSettings {
        &self.settings
    }

    /// The attitude quaternion `[w, x, y, z]` (world <- body).
    pub fn quaternion(&self) -> [f64; 4] {
        self.q
    }

    /// Whether the start-up ramp is still running.
    pub fn starting(&self) -> bool {
        self.startup
    }

    /// Whether acceleration recovery is active (every reading used).
    pub fn recovering(&self) -> bool {
        self.timeout == 0.0
    }

    /// Starts the ramp again, keeping the attitude.
    fn restart_ramp(&mut self) {
        let s = &self.settings;
        self.startup = s.startup_gain > s.gain && s.startup_period > 0.0;
        self.ramped = if self.startup { s.startup_gain } else { s.gain };
        self.trigger = 0.0;
        self.timeout = s.recovery_period;
    }

    /// Moves the start-up ramp on by `dt`.
    fn ramp(&mut self, dt: f64) {
        if !self.startup {
            return;
        }
        let s = &self.settings;
        self.ramped -= (s.startup_gain - s.gain) / s.startup_period * dt;
        if self.ramped <= s.gain {
            self.ramped = s.gain;
            self.startup = false;
        }
    }

    /// The feedback `a_hat x up_est` for reading `a`, and whether it is used. Beyond 90 deg
    /// it is `2 (a_hat x up_est) / |a_hat x up_est|`, as Fusion's: its feedback is computed
    /// against half the gravity direction and normalised to unit length beyond 90 deg, so
    /// there it is twice the largest feedback below (and an upside-down estimate still turns
    /// the right way); such a reading is never within a rejection threshold (Fusion compares
    /// the half feedback's squared length, then 1, with `(sin(threshold) / 2)^2 <= 1/4`).
    fn feedback(&mut self, a: [f64; 3], dt: f64) -> Option<[f64; 3]> {
        let n = norm(a);
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let a = a.map(|x| x / n);
        let up = self.up();
        let mut e = cross(a, up);
        let opposed = dot(a, up) < 0.0;
        if opposed {
            let m = norm(e);
            let unit = if m > 0.0 {
                e.map(|x| x / m)
            } else {
                // Exactly upside down: any horizontal axis turns it back.
                let h = if up[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                let c = cross(h, up);
                let m = norm(c);
                c.map(|x| x / m)
            };
            e = unit.map(|x| 2.0 * x);
        }
        let s = &self.settings;
        // |a x up| = sin(angle): compare with sin(threshold). Rejection off (infinite,
        // Fusion's 0) takes every reading; a threshold of 90 deg or more every reading
        // that is not opposed.
        let off = s.accel_rejection.is_infinite();
        let within = off
            || (!opposed
                && (s.accel_rejection >= core::f64::consts::FRAC_PI_2
                    || norm(e) <= s.accel_rejection.sin()));
        let accepted = self.startup || within;
        if accepted {
            self.trigger -= 9.0 * dt;
        } else {
            self.trigger += dt;
        }
        // Recovery: rejected most of the time for a whole period, so use every reading
        // until the trigger has run down again.
        let used = if self.trigger > self.timeout {
            self.timeout = 0.0;
            true
        } else {
            self.timeout = s.recovery_period;
            accepted
        };
        self.trigger = self.trigger.clamp(0.0, s.recovery_period);
        used.then_some(e)
    }
}

impl ImuFilter for Fusion {
    type Params = FusionSettings;

    /// None: its own start-up ramp averages the first readings (with the wrapper's mean
    /// of 1 s before it, the 10 s gap of tests/faults3d/ left it 11.3 deg from the
    /// fault-free run 2 s on, against 9.9 without).
    fn restart_average(&self) -> f64 {
        0.0
    }

    fn step(&mut self, gyro: [f64; 3], accel: Option<[f64; 3]>, dt: f64) -> bool {
        let range = 0.98 * self.settings.gyro_range;
        if gyro.iter().any(|w| w.abs() > range) {
            self.restart_ramp();
        }
        self.ramp(dt);
        let fb = accel.and_then(|a| self.feedback(a, dt));
        let k = fb.map_or(0.0, |_| self.ramped);
        let e = fb.unwrap_or([0.0; 3]);
        // q' = q (0, w / 2): one Euler step, then back to unit length.
        let w: [f64; 3] = core::array::from_fn(|i| gyro[i] + k * e[i]);
        let d = mul(
            self.q,
            [0.0, w[0] * dt / 2.0, w[1] * dt / 2.0, w[2] * dt / 2.0],
        );
        let q: [f64; 4] = core::array::from_fn(|i| self.q[i] + d[i]);
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.0 && n.is_finite() {
            self.q = q.map(|x| x / n);
        }
        fb.is_some()
    }

    fn up(&self) -> [f64; 3] {
        // The third row of R(q): R^T e_z.
        let [w, x, y, z] = self.q;
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            w * w - x * x - y * y + z * z,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendtilt_core::spatial::attitude::{inclination_between, up_from_roll_pitch};

    #[test]
    fn starts_at_the_roll_and_pitch_it_is_given() {
        for (r, p) in [(0.3, -0.2), (-1.2, 0.7), (0.0, 0.0)] {
            let f = Fusion::new(FusionSettings::default(), r, p);
            let e = inclination_between(f.up(), up_from_roll_pitch(r, p));
            assert!(e < 1e-14, "{r} {p}: {e}");
        }
    }

    /// Gyro only: a turn of 0.5 rad about body x then 0.3 rad about body y (ideal rates,
    /// 1 ms steps) ends at the composed rotation q_x(0.5) q_y(0.3), whose up is known.
    #[test]
    fn gyro_integration_follows_a_known_rotation() {
        let mut f = Fusion::new(FusionSettings::default(), 0.0, 0.0);
        for _ in 0..1000 {
            f.step([0.5, 0.0, 0.0], None, 1e-3);
        }
        for _ in 0..1000 {
            f.step([0.0, 0.3, 0.0], None, 1e-3);
        }
        let (s1, c1) = 0.25f64.sin_cos();
        let (s2, c2) = 0.15f64.sin_cos();
        let want = mul([c1, s1, 0.0, 0.0], [c2, 0.0, s2, 0.0]);
        let dq = f
            .quaternion()
            .into_iter()
            .zip(want)
            .map(|(a, b)| (a - b).abs());
        assert!(dq.fold(0.0, f64::max) < 1e-6, "{:?}", f.quaternion());
    }

    /// From a 20 deg wrong start the ramp brings it to a still accelerometer's tilt within
    /// the start-up period; afterwards a 1 s disturbance 30 deg off is rejected, and one
    /// that lasts beyond the recovery period is taken.
    #[test]
    fn ramp_rejection_and_recovery() {
        let s = FusionSettings::default();
        let (r, p) = (0.3, -0.2);
        let a = up_from_roll_pitch(r, p).map(|v| v * 9.81);
        let mut f = Fusion::new(s, r + 0.35, p);
        for _ in 0..3000 {
            f.step([0.0; 3], Some(a), 1e-3);
        }
        assert!(!f.starting());
        let e = inclination_between(f.up(), up_from_roll_pitch(r, p));
        assert!(e < 1e-5, "{e}");
        let off = up_from_roll_pitch(r + 0.52, p).map(|v| v * 9.81);
        let mut skipped = 0;
        for _ in 0..1000 {
            skipped += usize::from(!f.step([0.0; 3], Some(off), 1e-3));
        }
        assert_eq!(skipped, 1000);
        let e = inclination_between(f.up(), up_from_roll_pitch(r, p));
        assert!(e < 1e-5, "{e}");
        // Rejected for 5 s in all: recovery takes the reading and follows it.
        for _ in 0..14_000 {
            f.step([0.0; 3], Some(off), 1e-3);
        }
        let e = inclination_between(f.up(), up_from_roll_pitch(r + 0.52, p));
        assert!(e < 0.01, "{e}");
    }

    /// Beyond 90 deg Fusion's feedback is a unit vector against half the gravity direction,
    /// twice the largest feedback below 90 deg: from a reading 150 deg away the first step
    /// (1 ms, gain 10 at the start of the ramp, no gyro) turns the estimate by 2 x 10 x 1 ms
    /// = 0.02 rad, from one 60 deg away by 10 x sin(60 deg) x 1 ms = 0.0087 rad. After the
    /// start-up, an opposed reading is rejected even at a 90 deg threshold, and taken
    /// with rejection off.
    #[test]
    fn beyond_90_deg_the_feedback_is_fusions_unit_vector_at_twice_the_gain() {
        let turned = |deg: f64| {
            let mut f = Fusion::new(FusionSettings::default(), 0.0, 0.0);
            let before = f.up();
            f.step(
                [0.0; 3],
                Some(up_from_roll_pitch(deg.to_radians(), 0.0)),
                1e-3,
            );
            inclination_between(before, f.up())
        };
        // The ramp has moved on by one step before the feedback (Fusion's order).
        let gain = 10.0 - 9.5 / 3.0 * 1e-3;
        assert!(
            (turned(150.0) - 2.0 * gain * 1e-3).abs() < 1e-6,
            "{}",
            turned(150.0)
        );
        let sixty = gain * 60f64.to_radians().sin() * 1e-3;
        assert!((turned(60.0) - sixty).abs() < 1e-6, "{}", turned(60.0));
        let after_startup = |rejection: f64| {
            let s = FusionSettings {
                accel_rejection: rejection,
                ..FusionSettings::default()
            };
            let mut f = Fusion::new(s, 0.0, 0.0);
            for _ in 0..3100 {
                f.step([0.0; 3], Some([0.0, 0.0, 1.0]), 1e-3);
            }
            assert!(!f.starting());
            f.step([0.0; 3], Some(up_from_roll_pitch(2.6, 0.0)), 1e-3)
        };
        assert!(!after_startup(90f64.to_radians()));
        assert!(after_startup(f64::INFINITY));
    }

    #[test]
    fn a_gyro_beyond_its_range_restarts_the_ramp_and_keeps_the_attitude() {
        let s = FusionSettings {
            gyro_range: 10.0,
            ..FusionSettings::default()
        };
        let mut f = Fusion::new(s, 0.1, 0.0);
        for _ in 0..4000 {
            f.step([0.0; 3], None, 1e-3);
        }
        assert!(!f.starting());
        let before = f.up();
        f.step([9.9, 0.0, 0.0], None, 1e-6);
        assert!(f.starting());
        assert!(inclination_between(before, f.up()) < 1e-4);
    }
}
