//! The gravity references as measurements: the encoders (the joint angles) and the
//! accelerometer, through their gates, with the forcing's adaptation they drive.
use super::covariance::uncorrelate;
use super::{wrap_pi, ModelBased};
use crate::adaptation::SETTLE_SECONDS;
use crate::engine::{Gate, GaussianFilter, Measurement, Rejected};
use crate::spatial::ekf::measurement::Accelerometer;
use crate::spatial::ekf::process::Drive;
use crate::spatial::ekf::state::{State, A, B, N, P, R};
use crate::spatial::mounting::lever_arm;
use crate::spatial::SpatialSample;
use crate::{Flags, Real};
use nalgebra::{SVector, Vector3, Vector4};

/// Standard deviation \[rad/s\] of the pendulum's joint rates when the joint states start
/// again after the pendulum left its range: a pendulum that tumbled may still swing at a
/// few radians a second.
const JOINT_RATE_SD: f64 = 3.0;

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// The encoders through their gate. A reading is taken to the turn nearest the joint
    /// angle the filter predicts (a pendulum that spun past +-180 deg). Beyond
    /// [`crate::spatial::ekf::Settings::pendulum_range`], or after
    /// [`crate::spatial::ekf::Settings::reacquire_after`] rejections in a row, the pendulum
    /// is out of its model: the reading is not used, and the next one in range starts the
    /// joint states again at the reading, their rates unknown, the attitude left as it was
    /// ([`Flags::PENDULUM_UNUSED`]). The innovations that pass drive the forcing's
    /// adaptation ([`crate::spatial::ekf::Adaptation`]).
    pub(super) fn sense_encoders(&mut self, z: &SVector<T, 2>, dt: T) -> Flags {
        let st = self.settings;
        let encoders = self.coeffs.encoders;
        let Some(filter) = self.state.filter.as_mut() else {
            return Flags::empty();
        };
        self.state.since_used += dt;
        let pred = encoders.predict(filter.state());
        let z = SVector::<T, 2>::from_fn(|i, _| pred[i] + wrap_pi(z[i] - pred[i]));
        if z[1].abs() > st.pendulum_range {
            self.state.out_of_range = true;
            return Flags::PENDULUM_UNUSED | Flags::MEASUREMENT_SKIPPED;
        }
        if self.state.out_of_range || self.state.rejected >= st.reacquire_after.max(1) {
            self.restart_joints(&z);
            self.state.out_of_range = false;
            self.state.rejected = 0;
            self.state.since_used = T::zero();
            return Flags::PENDULUM_UNUSED;
        }
        let p = filter.covariance();
        let nis = (0..2).fold(T::zero(), |acc, i| {
            let (k, y) = ([A, B][i], z[i] - pred[i]);
            acc + y * y / (p[(k, k)] + encoders.r)
        }) * T::lit(0.5);
        let gate = Gate {
            threshold: st.innovation_gate,
            floor: T::zero(),
        };
        let flags = match filter.update(&encoders, &z, gate) {
            Ok(()) => {
                self.state.rejected = 0;
                Flags::empty()
            }
            Err(Rejected::Outlier) => {
                self.state.rejected = self.state.rejected.saturating_add(1);
                Flags::MEASUREMENT_SKIPPED
            }
            Err(_) => Flags::MEASUREMENT_SKIPPED,
        };
        // A reading the gate rejects counts as the gate's size at most: one wrong reading
        // (a glitch) moves the mean by little, a run of them (a model that no longer
        // fits) as much as it should.
        self.adapt(nis.min(st.innovation_gate));
        flags
    }

    /// One step of the forcing's adaptation
    /// ([`crate::adaptation::ForcingAdaptation::step`]) on the encoders' normalised
    /// innovation squared `nis` (per axis, before the update).
    fn adapt(&mut self, nis: T) {
        let dt = core::mem::replace(&mut self.state.since_used, T::zero());
        // Not while the gyro is held or its bias kept after a hold, nor while the filter
        // settles after a start: those innovations are the filter's, not the motion's.
        let settling =
            self.state.since_start < T::lit(SETTLE_SECONDS) || self.state.gyro.held_bias.is_some();
        if !settling {
            self.state.forcing.step(&self.settings.adaptation, nis, dt);
        }
    }

    /// Starts the joint states again at the reading `z` (a, b), their rates unknown and
    /// uncorrelated with the rest; the attitude, the bias and O's travel keep their
    /// estimates and covariance.
    pub(super) fn restart_joints(&mut self, z: &SVector<T, 2>) {
        let Some(f) = self.state.filter.as_ref() else {
            return;
        };
        let mut x = *f.state();
        let mut p = *f.covariance();
        x.joints = Vector4::new(z[0], z[1], T::zero(), T::zero());
        uncorrelate(&mut p, |i| (A..=R).contains(&i));
        let rate = T::lit(JOINT_RATE_SD);
        p[(A, A)] = self.coeffs.encoders.r;
        p[(B, B)] = self.coeffs.encoders.r;
        p[(P, P)] = rate * rate;
        p[(R, R)] = rate * rate;
        self.state.filter = Some(F::start(x, p));
    }

    /// The accelerometer as a measurement of the up direction (and of O's acceleration
    /// while travelling), through its gate. Its variance is the sensor's white noise over
    /// the sample and the vibration's; for imu3d, where it replaces the encoders, also the
    /// body's unmodelled acceleration: the forcing's density over the sample, times the
    /// adapted factor, whose adaptation its innovations drive as the encoders' do in
    /// ekf3d. A missing reading (not `accel_ok`) is skipped.
    pub(super) fn sense_accel(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        drive: &Drive<T>,
        accel_ok: bool,
    ) -> Flags {
        let st = self.settings;
        let acc = self.accelerometer(dt, drive);
        let Some(filter) = self.state.filter.as_mut() else {
            return Flags::empty();
        };
        if !accel_ok {
            return Flags::MEASUREMENT_SKIPPED;
        }
        let z = Vector3::new(s.accel[0], s.accel[1], s.accel[2]);
        let nis = if st.use_encoders {
            T::zero()
        } else {
            // Per axis, before the update, as the encoders' in ekf3d.
            let x = filter.state();
            let (y, hm) = (z - acc.predict(x), acc.jacobian(x));
            let sv = hm * filter.covariance() * hm.transpose();
            (0..3).fold(T::zero(), |m, i| m + y[i] * y[i] / (sv[(i, i)] + acc.r)) / T::lit(3.0)
        };
        let gate = Gate {
            threshold: st.innovation_gate,
            floor: T::zero(),
        };
        let flags = match filter.update(&acc, &z, gate) {
            Ok(()) => Flags::empty(),
            Err(_) => Flags::MEASUREMENT_SKIPPED,
        };
        if !st.use_encoders {
            self.state.since_used += dt;
            self.adapt(nis.min(st.innovation_gate));
        }
        flags
    }

    /// The accelerometer's measurement model over a sample of `dt` (see
    /// [`Self::sense_accel`]); its lever arm from O at the filter's bias-corrected rate.
    fn accelerometer(&self, dt: T, drive: &Drive<T>) -> Accelerometer<T> {
        let st = &self.settings;
        let d = st.sensors.accel_density;
        let vib = st.environment.vibration_rms;
        let h = dt.max(T::lit(1e-6));
        let motion = if st.use_encoders {
            T::zero()
        } else {
            let q = st.environment.vibration_density;
            q * q * self.state.forcing.factor() / h
        };
        let bias = self
            .state
            .filter
            .as_ref()
            .map_or(Vector3::zeros(), |f| f.state().bias);
        let w = drive.gyro - bias;
        Accelerometer {
            gravity: st.params.gravity,
            per_speed: drive.centre_accel_per_speed(&w),
            lever: lever_arm(&w, &drive.angular_accel, &self.coeffs.accel_from_centre),
            r: d * d / h + vib * vib + motion,
        }
    }
}
