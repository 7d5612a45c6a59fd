//! Planar use of the `ahrs` crate's IMU filters (gyro + accelerometer, no magnetometer).
//!
//! The tilt plane is the sensor's y-z plane and the tilt axis its x axis: the body's
//! `(ax, ay)` go to the sensor's `(y, z)`, the gyro to `x`. A rotation `theta` about x
//! then reads `(0, g sin theta, g cos theta)`, exactly MODEL.md section 1's
//! `(ax, ay) = (g sin theta, g cos theta)` at rest, and the tilt is the quaternion's roll.
//! The filters are started at the accelerometer angle of the first sample and their
//! sample period follows each sample's actual step. A missing gyro reading is replaced by
//! the gyro's recent mean ([`MISSING_RATE_TAU`], the core's input hold); Mahony's angle
//! held through the gap is corrected once the gyro is back
//! ([`InputHold::bridged`](pendtilt_core::estimators::input_hold::InputHold::bridged)).
//! One missing accelerometer reading is the last one held; a longer gap integrates the
//! gyro alone.
//!
//! A first start is left as the published filters have it (they start at the first
//! accelerometer angle). A start-up gain ramp for Mahony on a first start (`kp = max(kp,
//! 1 / t)` for the first 1 / kp seconds) changed what gain suits a short log (the gain
//! search found kp = 0.08 instead of 0.45 on a 15 s ride), so it is not used there.
//!
//! After a long gap ([`Estimator::resume`]) Mahony starts again as a running mean and
//! keeps its steady offset (see [`Planar`]); Madgwick, whose normalised step moves the
//! tilt at 2 beta (135 deg/s at its gain) whatever the error, starts afresh.

use ahrs::Ahrs;
use nalgebra_ahrs::{UnitQuaternion, Vector3};
use pendtilt_core::estimators::equations::accel_angle;
pub use pendtilt_core::estimators::input_hold::MISSING_RATE_TAU;
use pendtilt_core::estimators::input_hold::{InputHold, Step};
use pendtilt_core::{Estimate, Estimator, Flags, Sample};

use super::steady::SteadyFit;

/// The part of an `ahrs` filter the planar wrapper needs.
pub trait PlanarAhrs: Ahrs<f64> {
    /// Sets the step of the next update \[s\].
    fn set_period(&mut self, dt: f64);
    /// The orientation.
    fn attitude(&self) -> UnitQuaternion<f64>;
    /// The gain by which a tilt error decays \[1/s\], where the filter has one (Mahony's
    /// kp); `None` for a filter whose correction is not proportional (Madgwick's).
    fn gain_mut(&mut self) -> Option<&mut f64> {
        None
    }
}

impl PlanarAhrs for ahrs::Madgwick<f64> {
    fn set_period(&mut self, dt: f64) {
        *self.sample_period_mut() = dt;
    }
    fn attitude(&self) -> UnitQuaternion<f64> {
        self.quat()
    }
}

impl PlanarAhrs for ahrs::Mahony<f64> {
    fn set_period(&mut self, dt: f64) {
        *self.sample_period_mut() = dt;
    }
    fn attitude(&self) -> UnitQuaternion<f64> {
        self.quat()
    }
    fn gain_mut(&mut self) -> Option<&mut f64> {
        Some(self.kp_mut())
    }
}

/// The quaternion of a rotation `theta` about the sensor's x axis.
pub fn tilt_quaternion(theta: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(theta, 0.0, 0.0)
}

/// The tilt of an orientation: its roll about the sensor's x axis.
pub fn tilt_of(q: &UnitQuaternion<f64>) -> f64 {
    q.euler_angles().0
}

/// An `ahrs` filter run in the tilt plane as an [`Estimator`]. `make(theta0)` builds the
/// filter started at `theta0`.
///
/// A filter with a proportional gain `k` ([`PlanarAhrs::gain_mut`], Mahony) is restarted
/// after a long gap ([`Estimator::resume`]) as the complementary filter is: for its first
/// `1 / k` seconds the gain is `1 / t`, so the tilt is the mean of the accelerometer angle
/// so far (carried by the gyro) rather than one vibrating reading forgotten at `k`; and it
/// keeps its steady offset, the gyro bias over `k`, which a gap cannot change: its tilt
/// less the accelerometer angle, fitted through the start's transient
/// ([`SteadyFit`]), by which the accelerometer angle is read shifted while the mean has
/// not built it up (`offset (1 - k t)`).
#[derive(Debug, Clone)]
pub struct Planar<F> {
    make: fn(f64, &[f64; 2]) -> F,
    gains: [f64; 2],
    filter: Option<F>,
    input: InputHold<f64>,
    last: f64,
    /// Time since the filter started \[s\].
    elapsed: f64,
    /// The tilt less the accelerometer angle, fitted for its steady value.
    fit: SteadyFit<1>,
    /// After a restart: the offset kept \[rad\].
    kept: Option<f64>,
    /// The last accelerometer reading, and whether it stands in for a missing one now.
    last_accel: Option<(f64, f64)>,
    held: bool,
}

impl<F: PlanarAhrs> Planar<F> {
    /// A wrapper building its filter with `make(theta0, gains)` on the first usable sample.
    pub fn new(make: fn(f64, &[f64; 2]) -> F, gains: [f64; 2]) -> Self {
        Self {
            make,
            gains,
            filter: None,
            input: InputHold::new(),
            last: f64::NAN,
            elapsed: 0.0,
            fit: SteadyFit::default(),
            kept: None,
            last_accel: None,
            held: false,
        }
    }

    /// The gains it was built with.
    pub fn gains(&self) -> [f64; 2] {
        self.gains
    }
}

impl<F: PlanarAhrs> Planar<F> {
    /// The accelerometer reading to use, and whether there is one. One missing reading is
    /// the last one held: Madgwick's step is the same whenever the reading stays on the
    /// same side of its tilt, so a run that skipped it joins the fault-free run again,
    /// where one step skipped kept it 2 beta dt (0.14 deg) away for seconds. Longer gaps
    /// integrate the gyro alone: Madgwick would race to a stale reading at 135 deg/s.
    #[inline]
    fn accel_reading(&mut self, s: &Sample<f64>) -> (bool, Sample<f64>) {
        let read_ok = s.ax.is_finite() && s.ay.is_finite() && (s.ax != 0.0 || s.ay != 0.0);
        match (read_ok, self.last_accel) {
            (true, _) => {
                self.last_accel = Some((s.ax, s.ay));
                self.held = false;
                (true, *s)
            }
            (false, Some((ax, ay))) if !self.held && self.filter.is_some() => {
                self.held = true;
                (true, Sample { ax, ay, ..*s })
            }
            _ => (false, *s),
        }
    }

    /// The first sample (of the log, or after a restart): the filter built at the
    /// accelerometer's angle (with the kept steady offset, after a restart).
    fn start(&mut self, s: &Sample<f64>, accel_ok: bool, flags: Flags) -> Estimate<f64> {
        if !accel_ok {
            return Estimate {
                theta: f64::NAN,
                flags: flags | Flags::INITIALISING | Flags::SAMPLE_MISSING,
            };
        }
        let mut th = accel_angle(s.ax, s.ay);
        let mut f = (self.make)(th, &self.gains);
        match self.kept {
            // A restart, in its steady offset from the start.
            Some(kept) if f.gain_mut().is_some() => {
                th += kept;
                f = (self.make)(th, &self.gains);
            }
            _ => self.kept = None,
        }
        self.filter = Some(f);
        self.elapsed = 0.0;
        self.input.started();
        self.last = th;
        Estimate {
            theta: th,
            flags: flags | Flags::INITIALISING,
        }
    }
}

impl<F: PlanarAhrs> Estimator for Planar<F> {
    type Input = Sample<f64>;
    type Output = Estimate<f64>;

    fn update(&mut self, s: &Sample<f64>) -> Estimate<f64> {
        let (accel_ok, s) = self.accel_reading(s);
        let s = &s;
        let (dt, gyro, mut flags) = match self.input.begin(s) {
            Step::BadTime => {
                return Estimate {
                    theta: self.last,
                    flags: Flags::BAD_TIME_STEP,
                }
            }
            Step::First { flags, .. } => return self.start(s, accel_ok, flags),
            Step::Next { dt, gyro, flags } => (dt, gyro, flags),
        };
        let Some(f) = self.filter.as_mut() else {
            return Estimate {
                theta: self.last,
                flags: Flags::INITIALISING,
            };
        };
        f.set_period(dt);
        // The angle a gap in the gyro held wrong, once the readings after it tell, turned
        // in with this step, less what the gain forgot since. Madgwick forgets an angle
        // error at 2 beta (135 deg/s) whatever it is: it has none left to correct.
        let bridge = match f.gain_mut() {
            Some(_) => self.input.bridged(self.gains[0]),
            None => 0.0,
        };
        let gyro = gyro + bridge / dt;
        let g = Vector3::new(gyro, 0.0, 0.0);
        let gain = self.gains[0];
        let restarting = self.kept.is_some() && self.elapsed * gain < 1.0;
        self.elapsed += dt;
        if accel_ok {
            let (mut ax, mut ay) = (s.ax, s.ay);
            if let (Some(kept), Some(k)) = (self.kept, f.gain_mut()) {
                if restarting {
                    // The running mean, the accelerometer angle shifted by the
                    // part of the kept offset it has not built up.
                    *k = gain.max(1.0 / (self.elapsed + dt));
                    let (sn, cs) = (kept * (1.0 - self.elapsed * gain).max(0.0)).sin_cos();
                    (ax, ay) = (ax * cs + ay * sn, ay * cs - ax * sn);
                } else {
                    *k = gain;
                }
            }
            let a = Vector3::new(0.0, ax, ay);
            if f.update_imu(&g, &a).is_err() {
                flags |= Flags::MEASUREMENT_SKIPPED;
            }
            if !restarting && !self.held && f.gain_mut().is_some() {
                let mut d = tilt_of(&f.attitude()) - accel_angle(s.ax, s.ay);
                if d.abs() > core::f64::consts::PI {
                    d = d.sin().atan2(d.cos());
                }
                self.fit.add([d], dt, gain);
            }
        } else {
            f.update_gyro(&g);
            flags |= Flags::MEASUREMENT_SKIPPED;
        }
        let th = tilt_of(&f.attitude());
        if th.is_finite() {
            self.last = th;
        } else {
            // Never seen with finite input; start again rather than output NaN forever.
            self.filter = Some((self.make)(self.last, &self.gains));
        }
        Estimate {
            theta: self.last,
            flags,
        }
    }

    fn reset(&mut self) {
        *self = Self::new(self.make, self.gains);
    }

    /// Starts again on the next usable sample, keeping the steady offset (see [`Planar`]).
    fn resume(&mut self) {
        let steady = self.fit.steady(self.gains[0]).map(|c| c[0]);
        let kept = Some(steady.or(self.kept).unwrap_or(0.0));
        self.reset();
        self.kept = kept;
    }
}

/// Gain of [`madgwick`] (`beta` [rad/s]) found by the gain search
/// ([`super::tune::search_peer_gains`], 20 golden steps in [1e-4, 100]) on the simulated
/// scooter ride (60 s, seed 1, l12 = 0.2 m): 1.18, RMS error 1.15 deg. Small gains let
/// the 0.5 deg/s gyro bias, which Madgwick's IMU filter does not estimate, pull the tilt
/// away (0.003 gave 38 deg).
pub const MADGWICK_BETA: f64 = 1.18;
/// Gains of [`mahony`] (`kp` [1/s], `ki` [1/s^2]) found by the same search: kp = 0.45
/// (RMS error 3.0 deg); no ki in [1e-6 kp, kp] did better than ki = 0.
pub const MAHONY_GAINS: [f64; 2] = [0.45, 0.0];

/// Madgwick's filter from the `ahrs` crate, gain `beta`, in the tilt plane
/// (column `madgwick`).
pub fn madgwick(beta: f64) -> Planar<ahrs::Madgwick<f64>> {
    Planar::new(
        |th, g| ahrs::Madgwick::new_with_quat(1e-3, g[0], tilt_quaternion(th)),
        [beta, 0.0],
    )
}

/// Mahony's filter from the `ahrs` crate, gains `kp`, `ki`, in the tilt plane
/// (column `mahony`).
pub fn mahony(kp: f64, ki: f64) -> Planar<ahrs::Mahony<f64>> {
    Planar::new(
        |th, g| ahrs::Mahony::new_with_quat(1e-3, g[0], g[1], tilt_quaternion(th)),
        [kp, ki],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendtilt_core::PlanarEstimator;

    fn s(dt: f64, gyro: f64, th: f64) -> Sample<f64> {
        Sample {
            dt,
            phi: f64::NAN,
            gyro,
            ax: 9.81 * th.sin(),
            ay: 9.81 * th.cos(),
        }
    }

    #[test]
    fn quaternion_tilt_round_trip() {
        for th in [-1.0, -0.2, 0.0, 0.3, 1.2] {
            assert!((tilt_of(&tilt_quaternion(th)) - th).abs() < 1e-12);
        }
    }

    /// A gyro bias b holds Mahony asin(b / kp) above a still tilt (kp sin(error) = b).
    /// After a restart it starts there and stays there through its running mean (the
    /// offset kept); started afresh it starts on the accelerometer. Madgwick, with no
    /// proportional gain, starts afresh either way.
    #[test]
    fn a_restarted_mahony_keeps_its_steady_offset() {
        let (b, th, kp): (f64, f64, f64) = (0.005, 0.2, 0.45);
        let steady = (b / kp).asin();
        let mut m = mahony(kp, 0.0);
        let mut e = m.update(&s(0.0, b, th));
        for _ in 0..60_000 {
            e = m.update(&s(1e-3, b, th));
        }
        assert!((e.theta - th - steady).abs() < 1e-6, "{}", e.theta - th);
        let mut fresh = m.clone();
        Estimator::resume(&mut m);
        Estimator::reset(&mut fresh);
        let mut worst: f64 = 0.0;
        for k in 0..5000 {
            let dt = if k == 0 { 0.0 } else { 1e-3 };
            worst = worst.max((m.update(&s(dt, b, th)).theta - th - steady).abs());
            let f = fresh.update(&s(dt, b, th));
            if k == 0 {
                assert!((f.theta - th).abs() < 1e-12);
            }
        }
        assert!(worst < 0.02 * steady, "{worst} against {steady}");

        let mut g = madgwick(MADGWICK_BETA);
        for k in 0..5000 {
            g.update(&s(if k == 0 { 0.0 } else { 1e-3 }, b, th));
        }
        Estimator::resume(&mut g);
        let first = g.update(&s(0.0, b, th + 0.1));
        assert!((first.theta - th - 0.1).abs() < 1e-12, "{first:?}");
    }

    #[test]
    fn both_follow_the_gyro_sign_and_settle_on_the_accelerometer() {
        for mut e in [
            Box::new(madgwick(0.05)) as Box<dyn PlanarEstimator<f64>>,
            // ki / kp sets how fast Mahony's integral unwinds: 0.1 /s here.
            Box::new(mahony(1.0, 0.1)),
        ] {
            // Rotate at +0.5 rad/s for 1 s with a consistent accelerometer: +0.5 rad.
            e.update(&s(0.0, 0.5, 0.0));
            let mut last = 0.0;
            for k in 1..=1000 {
                let t = k as f64 * 1e-3;
                last = e.update(&s(1e-3, 0.5, 0.5 * t)).theta;
            }
            assert!((last - 0.5).abs() < 5e-3, "{last}");
            // Then held at 0.2 by the accelerometer with a still gyro: converges there.
            for _ in 1001..=60_000 {
                last = e.update(&s(1e-3, 0.0, 0.2)).theta;
            }
            assert!((last - 0.2).abs() < 1e-3, "{last}");
        }
    }
}
