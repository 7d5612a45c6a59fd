//! The streaming spatial estimator around a Gaussian filter of the engine: time steps,
//! start-up, missing readings, gaps, and the sensors with their innovation gates.
//!
//! Kept apart as VQF keeps them: the [`Settings`], the coefficients computed from them
//! and from the step length (`coefficients`), and the state carried from one sample to
//! the next (`run_state`). One concern per module: the gyro's holds and clips
//! (`gyro_hold`), the encoders and the accelerometer (`sensors`), the `speed` column
//! (`speed_sense`), the guard's reference (`guard`), starts and gaps (`restart`), and
//! the covariance's bounds (`covariance`).
mod coefficients;
mod covariance;
mod guard;
mod gyro_hold;
mod restart;
mod run_state;
mod sensors;
mod speed_sense;
#[cfg(test)]
mod tests;

use self::coefficients::Coefficients;
use self::covariance::bound_heading;
use self::run_state::RunState;
use super::process::Drive;
use super::settings::Settings;
use super::slip::SlipDetector;
use super::state::{State, N};
use crate::engine::{substeps, Cov, GaussianFilter};
use crate::spatial::{Attitude, SpatialSample};
use crate::{Estimator, Flags, Real};
use nalgebra::{SVector, UnitQuaternion, Vector3};

/// `x` wrapped to (-pi, pi].
fn wrap_pi<T: Real>(x: T) -> T {
    let tau = T::lit(core::f64::consts::TAU);
    let pi = T::lit(core::f64::consts::PI);
    let v = x - tau * ((x + pi) / tau).floor();
    if v <= -pi {
        v + tau
    } else {
        v
    }
}

/// The model-based spatial estimator (`ekf3d` over the EKF, `ukf3d` over the UKF).
///
/// Per sample: predict over `dt` with the gyro (split into steps of at most
/// [`Settings::max_step`]; a missing gyro reading is replaced by the low-passed gyro and
/// the attitude's process noise grows by the angular vibration it may miss), then update
/// with the encoders, the `speed` column (unless the wheel slips) and, if enabled, the
/// accelerometer, each through its innovation gate. Between `speed` readings (a slower
/// speed signal, or a short loss) O's speed and rate are carried by the filter; after
/// [`super::SpeedSettings::timeout`] without one, or before the first, both are held at
/// zero; the first reading after that starts them at the reading, with the rate unknown
/// ([`super::SpeedSettings::initial_rate`]).
/// The first sample with both encoder readings starts the filter with the pendulum
/// hanging still: roll = phi_x, pitch = phi_y, yaw 0. After a gap longer than
/// [`Settings::max_gap`], or if the filter becomes non-finite, it starts again the same
/// way, but a restart after a gap (or [`Estimator::resume`]) keeps the gyro bias, its
/// variance grown by the bias walk over the gap: a gap cannot change it more. A run of
/// [`Settings::reacquire_after`] rejected encoder readings re-acquires them: the
/// covariance grows along a tilt step of the innovation's size that leaves the pendulum
/// hanging where it is (roll with -a, pitch with -b), and the reading is applied ungated.
#[derive(Debug, Clone)]
pub struct ModelBased<T: Real, F> {
    settings: Settings<T>,
    coeffs: Coefficients<T>,
    state: RunState<T, F>,
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// A new estimator.
    pub fn new(settings: Settings<T>) -> Self {
        let state = RunState::new(&settings);
        Self {
            coeffs: Coefficients::new(&settings, &state.gyro.diff),
            settings,
            state,
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &Settings<T> {
        &self.settings
    }

    /// The filter's state (attitude, gyro bias, joints), once started.
    pub fn state(&self) -> Option<&State<T>> {
        self.state.filter.as_ref().map(|f| f.state())
    }

    /// The wheel-slip detector (whether it slips, the speed it carries).
    pub fn slip_detector(&self) -> &SlipDetector<T> {
        &self.state.speed.slip
    }

    /// The error covariance, once started.
    pub fn covariance(&self) -> Option<&Cov<T, N>> {
        self.state.filter.as_ref().map(|f| f.covariance())
    }

    /// The attitude quaternion (world <- body; yaw is unobserved and only integrated),
    /// once started.
    pub fn quaternion(&self) -> Option<UnitQuaternion<T>> {
        self.state().map(|x| x.q)
    }

    /// The factor on the pendulum's forcing variance the adaptation has reached (1: the
    /// floor, [`crate::ekf::Environment::vibration_density`]).
    pub fn forcing_factor(&self) -> T {
        self.state.forcing.factor()
    }

    /// Whether the sample carries the gravity reference the filter starts on and whose
    /// gaps restart it: the encoders, or for imu3d the accelerometer.
    fn has_gravity_reference(&self, s: &SpatialSample<T>) -> bool {
        if self.settings.use_encoders {
            s.phi.iter().all(|v| v.is_finite())
        } else {
            s.accel.iter().all(|v| v.is_finite())
        }
    }

    /// What drives the step: the gyro `gyro` (bridged where missing), the angular
    /// acceleration, the path's and the slow rates, and the filter's z bias.
    fn drive(&self, gyro: Vector3<T>, angular_accel: Vector3<T>) -> Drive<T> {
        let st = &self.state;
        Drive {
            gyro,
            angular_accel,
            path_gyro: st.gyro.path.rate().unwrap_or(gyro),
            slow_gyro: st.gyro.smooth.value().unwrap_or(gyro),
            z_bias: st.filter.as_ref().map_or(T::zero(), |f| f.state().bias[2]),
        }
    }

    /// Predicts over `dt` with `drive`, adding `extra[k]` to the variance of the rotation
    /// about body axis `k` over the interval (a held or a clipped gyro); `false` if the
    /// filter could not propagate.
    fn predict(&mut self, dt: T, drive: &Drive<T>, extra: &Vector3<T>) -> bool {
        let (n, h) = substeps(dt, self.settings.max_step);
        let travelling = self.state.speed.travelling;
        self.coeffs.noise.refresh(&self.coeffs.model, h, travelling);
        let with_extra;
        // Nothing to add (the usual case: a gyro reading within its range and the forcing
        // at its floor) leaves the cached noise as it is, uncopied.
        let forcing = self.state.forcing.factor();
        let q = if extra.iter().all(|e| *e == T::zero()) && forcing == T::one() {
            self.coeffs.noise.plain()
        } else {
            with_extra = self.coeffs.noise.with(forcing, &(extra / T::lit(n as f64)));
            &with_extra
        };
        let Some(filter) = self.state.filter.as_mut() else {
            return false;
        };
        let mut ok = true;
        for _ in 0..n {
            ok &= filter.predict(&self.coeffs.model, drive, h, q);
        }
        ok
    }

    /// The measurements after the prediction, in their order: the gravity reference (the
    /// encoders, or imu3d's accelerometer) with the guard's reference beside it, the
    /// `speed` column, ekf3d's optional accelerometer, the guard, and the rest bias.
    fn sense(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        drive: &Drive<T>,
        have_phi: bool,
        accel_ok: bool,
    ) -> Flags {
        let mut flags = Flags::empty();
        if !have_phi {
            flags |= Flags::SAMPLE_MISSING;
        } else if self.settings.use_encoders {
            // The joint angles the encoders read (MODEL.md 7.2).
            let z = SVector::<T, 2>::new(-s.phi[0], -s.phi[1]);
            let used = self.sense_encoders(&z, dt);
            flags |= used;
            self.sense_reference(used.contains(Flags::PENDULUM_UNUSED), dt);
            self.hold_bias();
        } else {
            flags |= self.sense_accel(s, dt, drive, accel_ok);
            self.sense_reference(false, dt);
            self.hold_bias();
        }
        flags |= self.sense_speed(s, dt, &drive.gyro, &drive.angular_accel);
        if self.settings.use_accel && self.settings.use_encoders {
            flags |= self.sense_accel(s, dt, drive, accel_ok);
        }
        flags |= self.guard(s, dt, drive, have_phi, accel_ok);
        self.sense_rest(dt);
        flags
    }
}

impl<T: Real, F: GaussianFilter<T, State<T>, N>> Estimator for ModelBased<T, F> {
    type Input = SpatialSample<T>;
    type Output = Attitude<T>;

    fn update(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        let Ok(step) = self.state.clock.offer(s.dt) else {
            return self.hold(Flags::BAD_TIME_STEP);
        };
        let dt = step.unwrap_or(T::zero());
        let have_phi = self.has_gravity_reference(s);
        let gyro_ok = self.read_gyro(s, dt);
        if let Some(started) = self.gaps(s, dt, have_phi) {
            return started;
        }
        let gyro = self.bridged_gyro(s, gyro_ok);
        self.track_held_bias(gyro_ok, dt);
        let (mut flags, extra) = self.rate_uncertainty(s, dt, gyro_ok);
        let angular_accel = self.angular_accel(gyro_ok);
        self.speed_timeout(dt);
        let drive = self.drive(gyro, angular_accel);
        self.state.since_start += dt;
        let accel_ok = s.accel.iter().all(|v| v.is_finite());
        let ok = self.predict(dt, &drive, &extra);
        if let Some(f) = self.state.filter.as_mut() {
            bound_heading(f);
        }
        self.state.clock.accept();
        flags |= self.sense(s, dt, &drive, have_phi, accel_ok);
        self.finish(ok, flags)
    }

    fn reset(&mut self) {
        self.state.reset();
    }

    /// Forgets everything but the gyro bias (see the type's documentation).
    fn resume(&mut self) {
        self.keep_bias();
        let kept = self.state.kept_bias;
        self.reset();
        self.state.kept_bias = kept;
    }
}
