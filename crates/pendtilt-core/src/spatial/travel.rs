//! A travelling vehicle's known acceleration: the forward speed of the point O
//! (`[mounting] speed_at`, the `speed` column) and the gyro give O's acceleration in body
//! axes, `a_O = v' x_b + w_p x (v x_b)`: the longitudinal part from the speed's smoothed
//! derivative, the centripetal part from the rate `w_p` at which the path turns and pitches
//! ([`PathRate`]: the gyro's z as read, its y low-passed, so that the body's pitching on its
//! suspension is not taken for a change of grade).
//!
//! [`Travel`] keeps the two filters per sample for inv3d, which inverts without a state;
//! ekf3d/ukf3d carry O's speed and rate as states and take only [`PathRate`] from here.
//! The estimators that model the pendulum's specific force add `a_O` and the lever arm
//! from O ([`super::mounting::lever_arm`]).
use crate::filters::diff::{Response, SmoothingDifferentiator};
use crate::filters::one_pole::OnePoleGain;
use crate::Real;
use nalgebra::Vector3;

/// Default of [`TravelSettings::speed_rate_hz`] \[Hz\] (inv3d sets its own, 1 Hz; ekf3d
/// carries the speed and its rate as states, `super::ekf::SpeedSettings`). Lower lags
/// the braking (the lag times the jerk is a longitudinal force the model misses; the
/// Bessel filter's delay is 0.17 s at 2 Hz, 67 ms at 5 Hz), higher lets the speed's
/// noise through as a longitudinal acceleration (a standing scooter's speed is noise
/// alone). Measured when ekf3d used it (at its defaults, 120 s, seeds 1/2/3, deg RMS
/// inclination / max roll or pitch error): ride3d 2 Hz 0.340/0.483/0.514 (max
/// 1.06/1.57/1.54), 5 Hz 0.285/0.432/0.451 (max 0.71/1.51/0.94); scooter3d 2 Hz
/// 0.053/0.059/0.057, 5 Hz 0.055/0.060/0.058.
pub const DEFAULT_SPEED_RATE_HZ: f64 = 5.0;

/// Default of [`PathSettings::path_turn_hz`] \[Hz\]: infinite, the gyro's z as read.
/// A vehicle's path turns with its body about O (a wheel that rolls does not slide
/// sideways), so the body's yaw rate is the path's; a low-pass lags the turns, and the lag
/// times the turn's rate of change times the speed is a lateral force the model misses
/// (80 ms at 2 Hz: 0.35 m/s^2, 2 deg, turning in at 0.44 rad/s/s and 10 m/s). Measured
/// on ride3d (ekf3d at its defaults, 120 s, seeds 1/2/3, deg RMS inclination / max roll
/// or pitch error; pitch at [`DEFAULT_PATH_PITCH_HZ`]): 10 Hz 0.178/0.222/0.298
/// (max 0.55/1.15/0.68), 20 Hz 0.175/0.217/0.295 (0.59/1.06/0.68), as read
/// 0.175/0.213/0.294 (0.63/0.98/0.67). ride3d's yaw wobble (0.3 deg at 1.5 Hz per 10
/// m/s, about O) then enters as a turn, at 1.5 Hz: the filter averages it out.
pub const DEFAULT_PATH_TURN_HZ: f64 = f64::INFINITY;

/// Default of [`PathSettings::path_pitch_hz`] \[Hz\]. The path pitches only as the road's
/// grade changes (slowly); the body's pitching on its suspension (0.4 deg at 1.6 Hz per
/// 10 m/s on ride3d) does not turn its velocity, but times the speed it would be a
/// vertical force of 1 m/s^2 at 15 m/s. Measured on ride3d (as above, turns as read):
/// 0.2 Hz 0.181/0.214/0.297, 0.5 Hz 0.175/0.213/0.294, 1 Hz 0.173/0.224/0.313 (pitch
/// RMS of seed 3 0.257, 0.254, 0.274); with both axes at the former 2 Hz, pitch on seed
/// 3 was 0.35.
pub const DEFAULT_PATH_PITCH_HZ: f64 = 0.5;

/// How the speed and the gyro become O's acceleration (inv3d's: ekf3d estimates the
/// speed's rate, and takes only the path's rate from here, [`PathSettings`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TravelSettings<T> {
    /// Cutoff \[Hz\] of the smoothing differentiator (Bessel, 4th order) that takes O's
    /// longitudinal acceleration from the `speed` column. Default 5 Hz: see
    /// [`DEFAULT_SPEED_RATE_HZ`].
    pub speed_rate_hz: T,
    /// The path's turn and pitch rates. Default: [`PathSettings::default`].
    pub path: PathSettings<T>,
}

/// How the gyro gives the rate at which the vehicle's path turns and pitches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSettings<T> {
    /// Cutoff \[Hz\] of the one-pole low-pass of the gyro's z that gives the rate at which
    /// the vehicle's path turns, for the centripetal acceleration `v w_z` across. Default
    /// infinite (the gyro as read): see [`DEFAULT_PATH_TURN_HZ`].
    pub path_turn_hz: T,
    /// Cutoff \[Hz\] of the one-pole low-pass of the gyro's y that gives the rate at which
    /// the path pitches, for `-v w_y` along z: the body's pitching on its suspension does
    /// not turn its velocity. Default 0.5 Hz: see [`DEFAULT_PATH_PITCH_HZ`].
    pub path_pitch_hz: T,
}

impl<T: Real> Default for TravelSettings<T> {
    fn default() -> Self {
        Self {
            speed_rate_hz: T::lit(DEFAULT_SPEED_RATE_HZ),
            path: PathSettings::default(),
        }
    }
}

impl<T: Real> Default for PathSettings<T> {
    fn default() -> Self {
        Self {
            path_turn_hz: T::lit(DEFAULT_PATH_TURN_HZ),
            path_pitch_hz: T::lit(DEFAULT_PATH_PITCH_HZ),
        }
    }
}

impl<T: Real> TravelSettings<T> {
    /// The same settings in another scalar type.
    pub fn cast<U: Real>(&self) -> TravelSettings<U> {
        TravelSettings {
            speed_rate_hz: U::lit(self.speed_rate_hz.to_f64()),
            path: self.path.cast(),
        }
    }
}

impl<T: Real> PathSettings<T> {
    /// The same settings in another scalar type.
    pub fn cast<U: Real>(&self) -> PathSettings<U> {
        PathSettings {
            path_turn_hz: U::lit(self.path_turn_hz.to_f64()),
            path_pitch_hz: U::lit(self.path_pitch_hz.to_f64()),
        }
    }
}

/// The rate at which the vehicle's path turns, from the gyro: its y low-passed at
/// [`PathSettings::path_pitch_hz`], its z at [`PathSettings::path_turn_hz`] (x, which
/// O's acceleration does not use, as read). Bias not removed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathRate<T: Real> {
    pitch: OnePoleGain<T>,
    turn: OnePoleGain<T>,
    rate: Option<Vector3<T>>,
}

impl<T: Real> PathRate<T> {
    /// Nothing seen yet.
    pub fn new(settings: &PathSettings<T>) -> Self {
        Self {
            pitch: OnePoleGain::from_hz(settings.path_pitch_hz),
            turn: OnePoleGain::from_hz(settings.path_turn_hz),
            rate: None,
        }
    }

    /// Takes a gyro reading `dt` after the last (the first one starts the low-passes).
    /// An infinite cutoff has gain 1 (`exp(-inf) = 0`): the reading as it is.
    #[inline]
    pub fn update(&mut self, g: &Vector3<T>, dt: T) {
        if self.rate.is_some() && dt <= T::zero() {
            // No time has passed (and inf * 0 is no gain).
            return;
        }
        let k = Vector3::new(T::one(), self.pitch.gain(dt), self.turn.gain(dt));
        self.rate = Some(self.rate.map_or(*g, |m| m + (g - m).component_mul(&k)));
    }

    /// The path's rate \[rad/s\], once a reading was seen.
    #[inline]
    pub fn rate(&self) -> Option<Vector3<T>> {
        self.rate
    }

    /// Forgets the readings (the cached gains stay: they depend on the step only).
    pub fn reset(&mut self) {
        self.rate = None;
    }
}

/// O's speed, its smoothed rate and the path's turn rate, sample by sample.
#[derive(Debug, Clone)]
pub struct Travel<T: Real> {
    speed_diff: SmoothingDifferentiator<T, 1>,
    path: PathRate<T>,
    // The last speed reading, `None` when it was missing.
    speed: Option<T>,
}

impl<T: Real> Travel<T> {
    /// Nothing seen yet.
    pub fn new(settings: TravelSettings<T>) -> Self {
        Self {
            speed_diff: SmoothingDifferentiator::new(Response::Bessel, settings.speed_rate_hz),
            path: PathRate::new(&settings.path),
            speed: None,
        }
    }

    /// Takes a gyro reading `dt` after the last (the first one starts the low-pass).
    #[inline]
    pub fn gyro(&mut self, g: &Vector3<T>, dt: T) {
        self.path.update(g, dt);
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

    /// The path's rate ([`PathRate`]), once a reading was seen.
    pub fn path_gyro(&self) -> Option<Vector3<T>> {
        self.path.rate()
    }

    /// O's acceleration in body axes, `v' x_b + w_p x (v x_b)`, with `w_p` the path's turn
    /// rate ([`PathRate`], less `bias`).
    pub fn centre_accel(&self, bias: &Vector3<T>) -> Vector3<T> {
        let wp = self.path_gyro().unwrap_or_else(Vector3::zeros) - bias;
        let v = self.forward_speed();
        Vector3::new(self.speed_rate(), wp[2] * v, -wp[1] * v)
    }

    /// Forgets every reading.
    pub fn reset(&mut self) {
        self.speed_diff.reset();
        self.path.reset();
        self.speed = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The path's rate: a turn (z) as the gyro reads it, from the first sample; the body's
    /// pitching on its suspension (y, 1.6 Hz) cut to a third by the 0.5 Hz low-pass
    /// (`1 / sqrt(1 + (1.6 / 0.5)^2)` = 0.30), a steady pitch rate (a grade's change) kept.
    #[test]
    fn turns_pass_and_the_suspensions_pitch_is_cut() {
        let mut p = PathRate::<f64>::new(&PathSettings::default());
        let dt = 1e-3;
        let (f, amp) = (1.6, 0.05);
        let mut peak: f64 = 0.0;
        for k in 0..20_000 {
            let t = k as f64 * dt;
            let z = if k < 10 { 0.0 } else { 0.44 };
            let y = 0.02 + amp * (core::f64::consts::TAU * f * t).sin();
            p.update(&Vector3::new(0.1, y, z), if k == 0 { 0.0 } else { dt });
            let r = p.rate().unwrap();
            assert_eq!(r[2], z);
            assert_eq!(r[0], 0.1);
            if t > 15.0 {
                peak = peak.max((r[1] - 0.02).abs());
            }
        }
        let want = amp / (1.0f64 + (f / 0.5) * (f / 0.5)).sqrt();
        assert!((peak - want).abs() < 0.02 * want, "{peak} vs {want}");
        p.reset();
        assert!(p.rate().is_none());
    }

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
