//! A travelling vehicle's known acceleration (issue 15): the forward speed of the point O
//! (`[mounting] speed_at`, the `speed` column) and the gyro give O's acceleration in body
//! axes, `a_O = v' x_b + w_p x (v x_b)`: the longitudinal part from the speed's smoothed
//! derivative, the centripetal part from the rate `w_p` at which the path turns (the gyro
//! low-passed, so that the body's faster swings on its suspension are not taken for turns).
//!
//! [`Travel`] keeps the two filters per sample (inv3d and ekf3d/ukf3d alike; the latter
//! feed it the slip detector's speed, [`Travel::slipped_speed`]); the estimators that model
//! the pendulum's specific force add `a_O` and the lever arm from O
//! ([`super::mounting::lever_arm`]).
use super::ekf::slip::SpeedVerdict;
use crate::filters::diff::{Response, SmoothingDifferentiator};
use crate::filters::one_pole::{OnePole, OnePoleGain};
use crate::Real;
use nalgebra::Vector3;

/// Default of [`TravelSettings::speed_rate_hz`] \[Hz\]. Lower lags the braking (the lag
/// times the jerk is a longitudinal force the model misses; the Bessel filter's delay is
/// 0.17 s at 2 Hz, 67 ms at 5 Hz), higher lets the speed's noise through as a
/// longitudinal acceleration (a standing scooter's speed is noise alone). Measured
/// (ekf3d at its defaults, 120 s, seeds 1/2/3, deg RMS inclination / max roll or pitch
/// error): ride3d 2 Hz 0.340/0.483/0.514 (max 1.06/1.57/1.54), 3 Hz 0.305/0.453/0.477,
/// 5 Hz 0.285/0.432/0.451 (max 0.71/1.51/0.94); scooter3d 2 Hz 0.053/0.059/0.057, 5 Hz
/// 0.055/0.060/0.058.
pub const DEFAULT_SPEED_RATE_HZ: f64 = 5.0;

/// Default of [`TravelSettings::path_turn_hz`] \[Hz\]. Measured on ride3d (120 s, seeds
/// 1-3, ekf3d at its defaults): 0.5 Hz lags the turns (0.91 deg RMS on seed 1), the raw
/// gyro (no low-pass) takes the wobble for turns (1.14); 2 Hz gave 0.45, 1.14 and 0.76,
/// 3 Hz 0.48, 1.20 and 0.75.
pub const DEFAULT_PATH_TURN_HZ: f64 = 2.0;

/// How the speed and the gyro become O's acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TravelSettings<T> {
    /// Cutoff \[Hz\] of the smoothing differentiator (Bessel, 4th order) that takes O's
    /// longitudinal acceleration from the `speed` column. Default 5 Hz: see
    /// [`DEFAULT_SPEED_RATE_HZ`].
    pub speed_rate_hz: T,
    /// Cutoff \[Hz\] of the one-pole low-pass of the gyro that gives the rate at which the
    /// vehicle's path turns, for the centripetal acceleration `v w x x_b`: the body's
    /// faster rotations on its suspension (a yaw wobble of 0.3 deg at 1.5 Hz at 10 m/s is
    /// 0.5 m/s^2 across) do not turn its velocity. Default 2 Hz: see
    /// [`DEFAULT_PATH_TURN_HZ`].
    pub path_turn_hz: T,
}

impl<T: Real> Default for TravelSettings<T> {
    fn default() -> Self {
        Self {
            speed_rate_hz: T::lit(DEFAULT_SPEED_RATE_HZ),
            path_turn_hz: T::lit(DEFAULT_PATH_TURN_HZ),
        }
    }
}

impl<T: Real> TravelSettings<T> {
    /// The same settings in another scalar type.
    pub fn cast<U: Real>(&self) -> TravelSettings<U> {
        TravelSettings {
            speed_rate_hz: U::lit(self.speed_rate_hz.to_f64()),
            path_turn_hz: U::lit(self.path_turn_hz.to_f64()),
        }
    }
}

/// O's speed, its smoothed rate and the path's turn rate, sample by sample.
#[derive(Debug, Clone)]
pub struct Travel<T: Real> {
    speed_diff: SmoothingDifferentiator<T, 1>,
    path_gyro: OnePole<T, 3>,
    // The last speed reading, `None` when it was missing.
    speed: Option<T>,
}

impl<T: Real> Travel<T> {
    /// Nothing seen yet.
    pub fn new(settings: TravelSettings<T>) -> Self {
        Self {
            speed_diff: SmoothingDifferentiator::new(Response::Bessel, settings.speed_rate_hz),
            path_gyro: OnePole::new(OnePoleGain::from_hz(settings.path_turn_hz)),
            speed: None,
        }
    }

    /// Takes a gyro reading `dt` after the last (the first one starts the low-pass).
    #[inline]
    pub fn gyro(&mut self, g: &Vector3<T>, dt: T) {
        self.path_gyro.update(g, dt);
    }

    /// Takes a speed reading `dt` after the last; a missing one (`NaN`) counts as a
    /// vehicle at rest, not accelerating, and leaves the derivative where it was.
    pub fn speed(&mut self, v: T, dt: T) {
        if !v.is_finite() {
            self.no_speed();
            return;
        }
        self.differentiate(v, dt);
    }

    /// The speed `v` (finite) `dt` after the last into the derivative (the first one, or
    /// one with no step, starts it).
    fn differentiate(&mut self, v: T, dt: T) {
        if dt > T::zero() && self.speed_diff.is_started() {
            self.speed_diff.update(v, dt);
        } else {
            self.speed_diff.start(v);
        }
        self.speed = Some(v);
    }

    /// Takes the slip detector's verdict on a speed reading `dt` after the last: its speed
    /// (the reading, or the carried one while the wheel slips) is differentiated, and the
    /// switches of source are not taken for accelerations: a slip's end shifts the
    /// derivative's level by the verdict's jump, a slip's start restarts it on the
    /// accelerometer's rate ([`super::ekf::slip`]).
    pub fn slipped_speed(&mut self, v: &SpeedVerdict<T>, dt: T) {
        self.speed_diff.shift_signal(0, v.jump);
        if let Some(rate) = v.restart.filter(|_| self.speed_diff.is_started()) {
            self.speed_diff.restart_signal_on_ramp(0, v.speed, rate);
            self.speed = Some(v.speed);
        } else {
            self.differentiate(v.speed, dt);
        }
    }

    /// Takes the lack of a speed reading: the vehicle counts as at rest, not accelerating,
    /// and the derivative stays where it was.
    pub fn no_speed(&mut self) {
        self.speed = None;
    }

    /// The last speed reading \[m/s\] (0 when it was missing).
    pub fn forward_speed(&self) -> T {
        self.speed.unwrap_or(T::zero())
    }

    /// The speed's smoothed rate \[m/s^2\] (0 when the last reading was missing).
    pub fn speed_rate(&self) -> T {
        self.speed
            .map_or(T::zero(), |_| self.speed_diff.output().d1)
    }

    /// The low-passed gyro, once a reading was seen.
    pub fn path_gyro(&self) -> Option<Vector3<T>> {
        self.path_gyro.value()
    }

    /// O's acceleration in body axes, `v' x_b + w_p x (v x_b)`, with `w_p` the path's turn
    /// rate (the low-passed gyro, less `bias`).
    pub fn centre_accel(&self, bias: &Vector3<T>) -> Vector3<T> {
        let wp = self.path_gyro().unwrap_or_else(Vector3::zeros) - bias;
        let v = self.forward_speed();
        Vector3::new(self.speed_rate(), wp[2] * v, -wp[1] * v)
    }

    /// Forgets every reading.
    pub fn reset(&mut self) {
        self.speed_diff.reset();
        self.path_gyro.reset();
        self.speed = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A steady turn at 10 m/s and 0.2 rad/s about z is 2 m/s^2 towards the inside (+y for
    /// a left turn), and a speed rising at 1.5 m/s^2 is 1.5 m/s^2 along x once the
    /// differentiator has settled; a missing speed is a vehicle at rest.
    #[test]
    fn a_steady_turn_and_a_steady_acceleration() {
        let mut t = Travel::<f64>::new(TravelSettings::default());
        let dt = 1e-3;
        let w = Vector3::new(0.0, 0.0, 0.2);
        for k in 0..5000 {
            let step = if k == 0 { 0.0 } else { dt };
            t.gyro(&w, step);
            t.speed(10.0 + 1.5 * k as f64 * dt, step);
        }
        let a = t.centre_accel(&Vector3::zeros());
        let v = 10.0 + 1.5 * 4999.0 * dt;
        assert!((a[0] - 1.5).abs() < 1e-6, "{a}");
        assert!((a[1] - 0.2 * v).abs() < 1e-9, "{a}");
        assert!(a[2].abs() < 1e-12, "{a}");
        // A bias of the whole rate leaves no turn.
        assert!(t.centre_accel(&w)[1].abs() < 1e-12);
        t.speed(f64::NAN, dt);
        assert_eq!(t.forward_speed(), 0.0);
        assert_eq!(t.centre_accel(&Vector3::zeros()), Vector3::zeros());
    }
}
