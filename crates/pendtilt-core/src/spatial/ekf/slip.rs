//! Wheel-slip detection for the `speed` column.
//!
//! A wheel-speed sensor reads the wheel, not the vehicle: a wheel that spins when pulling
//! away reads above the vehicle's speed, one that locks when braking drops towards 0 while
//! the vehicle still moves. Its smoothed derivative then carries an acceleration the
//! vehicle does not have, and the pendulum's model takes it for a tilt (a 1 m/s^2 error is
//! 6 deg of apparent pitch).
//!
//! The accelerometer sees the vehicle's longitudinal acceleration too: O's acceleration
//! along body x is `f_x - g u_x` at O (`u` the up direction in body axes, from the filter's
//! attitude; `f` the accelerometer's reading carried from the accelerometer to O by the
//! lever arm `wd x r + w x (w x r)`, as the process model predicts it). The detector runs
//! the speed and that acceleration through one smoothing differentiator (Bessel, 4th order,
//! [`SlipSettings::hz`]), so that the speed's smoothed derivative and the acceleration's
//! low-passed value carry the same delay and the engine's and the road's vibration is cut
//! alike, and compares them:
//! - they disagree by more than [`SlipSettings::gate`], or the speed's derivative is beyond
//!   [`SlipSettings::impossible`] (no vehicle brakes or pulls away at 1.5 g): slip;
//! - while slipping, the speed reading is not used: a carried speed `v_c` integrates the
//!   accelerometer's longitudinal acceleration instead (between slips `v_c` follows the
//!   reading as a complementary filter with crossover [`SlipSettings::follow_hz`], so that
//!   it starts from the vehicle's speed, not the slipping wheel's);
//! - the slip ends when the reading agrees with `v_c` (within
//!   [`SlipSettings::speed_tolerance`] plus [`SlipSettings::drift`] times the slip's
//!   length: `v_c` drifts with the accelerometer's bias and the attitude's error) and the
//!   derivatives agree within half the gate, for [`SlipSettings::hold`] on end; or after
//!   [`SlipSettings::timeout`].
//!
//! ekf3d/ukf3d skip the speed measurement while the wheel slips: O's speed and its rate are
//! states of the filter, carried through the slip by the pendulum against the gyro.
//!
//! Without an accelerometer reading only the derivative bound detects slip, and `v_c` is
//! held.
use crate::filters::diff::{Response, SmoothingDifferentiator};
use crate::filters::one_pole::OnePoleGain;
use crate::spatial::mounting::lever_arm;
use crate::Real;
use nalgebra::Vector3;

pub use super::settings::SlipSettings;

/// The longitudinal acceleration of O (along body x) the accelerometer gives: its reading
/// `accel` carried to O (`accel_from_centre = accel_at - speed_at`, the lever arm at the
/// bias-corrected rate `w` and the angular acceleration `wd`), less gravity's component
/// `g u_x` along body x for the up direction `u` \[m/s^2\].
#[inline]
pub fn longitudinal_accel<T: Real>(
    accel: &Vector3<T>,
    up: &Vector3<T>,
    gravity: T,
    w: &Vector3<T>,
    wd: &Vector3<T>,
    accel_from_centre: &Vector3<T>,
) -> T {
    accel[0] - lever_arm(w, wd, accel_from_centre)[0] - gravity * up[0]
}

/// What the detector makes of one speed reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedVerdict<T> {
    /// The speed to use \[m/s\]: the reading, or, while slipping, the carried speed.
    pub speed: T,
    /// The wheel slips: the reading is not used.
    pub slip: bool,
}

/// The slip detector (see the module documentation). No allocation; f32 or f64.
#[derive(Debug, Clone)]
pub struct SlipDetector<T: Real> {
    settings: SlipSettings<T>,
    // Signal 0: the speed reading; 1: the accelerometer's longitudinal acceleration.
    diff: SmoothingDifferentiator<T, 2>,
    // The carried speed and the last longitudinal acceleration it was carried with.
    carried: T,
    // The gain that pulls `carried` towards the reading between slips (follow_hz).
    follow: OnePoleGain<T>,
    accel: T,
    slipping: bool,
    // How long the reading has agreed (while slipping) or how long the slip lasts [s].
    agree_for: T,
    slip_for: T,
    // The last |speed's derivative - accelerometer's acceleration| [m/s^2].
    disagreement: T,
    // Time since the start [s]: the filter settles (from a constant speed and a constant
    // acceleration, which disagree) for WARM_UP delays before it is trusted.
    running: T,
}

/// Filter delays (`2.11 / w_c`) after a start before the detector decides anything: the
/// Bessel filter's step response has settled to 1 % by then.
const WARM_UP: f64 = 5.0;

impl<T: Real> SlipDetector<T> {
    /// A detector with `settings`.
    pub fn new(settings: SlipSettings<T>) -> Self {
        Self {
            diff: SmoothingDifferentiator::new(Response::Bessel, settings.hz),
            settings,
            carried: T::zero(),
            follow: OnePoleGain::from_hz(settings.follow_hz),
            accel: T::zero(),
            slipping: false,
            agree_for: T::zero(),
            slip_for: T::zero(),
            running: T::zero(),
            disagreement: T::zero(),
        }
    }

    /// Forgets the past (a new start, or the speed column went missing). Nothing changes
    /// before the first reading starts the filter, so a detector not started is as new:
    /// a log without speed resets it on every row, and this keeps that free.
    pub fn reset(&mut self) {
        if self.diff.is_started() {
            *self = Self::new(self.settings);
        }
    }

    /// Whether the wheel slips now.
    pub fn is_slipping(&self) -> bool {
        self.slipping
    }

    /// How far the speed's smoothed derivative and the accelerometer's low-passed
    /// longitudinal acceleration disagree now \[m/s^2\] (0 before the filter settles or
    /// without an accelerometer): what [`SlipSettings::gate`] bounds.
    pub fn disagreement(&self) -> T {
        self.disagreement
    }

    /// The carried speed \[m/s\].
    pub fn carried(&self) -> T {
        self.carried
    }

    /// Takes the speed reading `speed` (finite) and, when known (finite), the
    /// accelerometer's longitudinal acceleration of O `accel` ([`longitudinal_accel`]),
    /// `dt` after the last call (0 on the first).
    pub fn update(&mut self, speed: T, accel: T, dt: T) -> SpeedVerdict<T> {
        let st = self.settings;
        let have_accel = accel.is_finite();
        let a = if have_accel { accel } else { T::zero() };
        let pass = SpeedVerdict { speed, slip: false };
        if !st.enabled {
            return pass;
        }
        if dt > T::zero() && self.diff.is_started() {
            self.diff.update_all([speed, a], dt);
        } else {
            self.diff.start_all([speed, a]);
            self.carried = speed;
            self.accel = a;
            return pass;
        }
        // The carried speed: trapezoidal in the acceleration; pulled towards the reading
        // between slips.
        let a_used = if have_accel { a } else { T::zero() };
        self.carried += (a_used + self.accel) * dt / T::lit(2.0);
        self.accel = a_used;
        let rate = self.diff.signal(0).d1;
        let from_accel = self.diff.signal(1).value;
        let disagree = (rate - from_accel).abs();
        let impossible = rate.abs() > st.impossible;
        self.running += dt;
        let settled =
            self.running >= T::lit(WARM_UP) * Response::Bessel.dc_delay(self.diff.cutoff_rad_s());
        self.disagreement = if settled && have_accel {
            disagree
        } else {
            T::zero()
        };
        let tripped = settled && (impossible || (have_accel && disagree > st.gate));
        if self.slipping {
            self.slip_for += dt;
            let tolerance = st.speed_tolerance + st.drift * self.slip_for;
            let level = (speed - self.carried).abs() <= tolerance;
            let rates = !have_accel || disagree <= st.gate / T::lit(2.0);
            let agrees = level && rates && !impossible;
            self.agree_for = if agrees {
                self.agree_for + dt
            } else {
                T::zero()
            };
            if self.agree_for >= st.hold || self.slip_for >= st.timeout {
                self.slipping = false;
                self.carried = speed;
                return pass;
            }
            return SpeedVerdict {
                speed: self.carried,
                slip: true,
            };
        }
        if tripped {
            self.slipping = true;
            self.slip_for = T::zero();
            self.agree_for = T::zero();
            return SpeedVerdict {
                speed: self.carried,
                slip: true,
            };
        }
        self.carried += (speed - self.carried) * self.follow.gain(dt);
        pass
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(
        d: &mut SlipDetector<f64>,
        secs: f64,
        t0: f64,
        f: impl Fn(f64) -> (f64, f64),
    ) -> std::vec::Vec<(f64, SpeedVerdict<f64>)> {
        let dt = 1e-3;
        (0..(secs / dt) as usize)
            .map(|k| {
                let t = t0 + k as f64 * dt;
                let (v, a) = f(t);
                (t, d.update(v, a, if t == 0.0 { 0.0 } else { dt }))
            })
            .collect()
    }

    /// A vehicle accelerating at 2 m/s^2 with the accelerometer agreeing: never slip, the
    /// reading passed through.
    #[test]
    fn agreeing_speed_and_acceleration_are_not_slip() {
        let mut d = SlipDetector::new(SlipSettings::default());
        let out = run(&mut d, 5.0, 0.0, |t| (3.0 + 2.0 * t, 2.0));
        for (t, v) in out {
            assert!(!v.slip, "{t}");
            assert_eq!(v.speed, 3.0 + 2.0 * t);
        }
    }

    /// A wheel locking at 1 s (the reading to 0 in 0.1 s) while the vehicle brakes at
    /// 3 m/s^2 from 10 m/s: slip within 50 ms; the speed given is the carried one, the
    /// vehicle's (to a few cm/s); the reading comes back at 2-2.1 s and the slip ends within
    /// 0.5 s.
    #[test]
    fn a_locked_wheel_is_slip_and_the_speed_is_carried() {
        let mut d = SlipDetector::new(SlipSettings::default());
        let truth = |t: f64| 10.0 - 3.0 * t;
        let reading = |t: f64| {
            let e = ((t - 1.0) / 0.1).clamp(0.0, 1.0) * (1.0 - ((t - 2.0) / 0.1).clamp(0.0, 1.0));
            (1.0 - e) * truth(t)
        };
        let out = run(&mut d, 3.0, 0.0, |t| (reading(t), -3.0));
        let first = out.iter().find(|(_, v)| v.slip).unwrap().0;
        assert!((1.0..1.05).contains(&first), "{first}");
        let last = out.iter().rev().find(|(_, v)| v.slip).unwrap().0;
        // The filter's transient of the reading's return (5 Hz) settles, then the hold.
        assert!((2.1..2.1 + 0.5).contains(&last), "{last}");
        for (t, v) in &out {
            if v.slip {
                assert!((v.speed - truth(*t)).abs() < 0.05, "{t}: {v:?}");
            }
        }
    }

    /// A speed derivative beyond 1.5 g is slip without an accelerometer.
    #[test]
    fn an_impossible_derivative_is_slip_without_the_accelerometer() {
        let mut d = SlipDetector::new(SlipSettings::default());
        let out = run(&mut d, 2.0, 0.0, |t| {
            (
                if t < 1.0 {
                    5.0
                } else {
                    5.0 + 40.0 * (t - 1.0).min(0.1)
                },
                f64::NAN,
            )
        });
        let first = out.iter().find(|(_, v)| v.slip).unwrap().0;
        assert!((1.0..1.06).contains(&first), "{first}");
        // The carried speed is held at the vehicle's 5 m/s.
        assert!(out
            .iter()
            .filter(|(_, v)| v.slip)
            .all(|(_, v)| (v.speed - 5.0).abs() < 0.3));
    }

    /// Disabled, the reading passes through whatever it does.
    #[test]
    fn disabled_passes_the_reading() {
        let mut d = SlipDetector::new(SlipSettings {
            enabled: false,
            ..SlipSettings::default()
        });
        let out = run(&mut d, 1.0, 0.0, |t| (if t < 0.5 { 5.0 } else { 0.0 }, 0.0));
        assert!(out
            .iter()
            .all(|(t, v)| !v.slip && v.speed == if *t < 0.5 { 5.0 } else { 0.0 }));
    }
}
