//! The guard: an inclination reference from the gyro and the accelerometer alone that
//! resets the attitude when the filter leaves it, carries roll and pitch while the
//! pendulum is not used, and reads the gyro's bias at rest.
use super::covariance::loosen_roll_pitch;
use super::{wrap_pi, ModelBased};
use crate::engine::{Gate, GaussianFilter, Measurement};
use crate::spatial::ekf::measurement::{Accelerometer, RestBias, UpDirection};
use crate::spatial::ekf::process::Drive;
use crate::spatial::ekf::state::{Error, State, N, ROT};
use crate::spatial::mounting::lever_arm;
use crate::spatial::SpatialSample;
use crate::{Flags, Real};
use nalgebra::{SVector, UnitQuaternion, Vector3};

/// Standard deviation \[rad\] of the guard's reference as a measurement of the up
/// direction while the pendulum is not used: 1 deg, about VQF's RMS on BROAD's hand-held
/// trials (docs/real-motion.md).
const REFERENCE_SD: f64 = core::f64::consts::PI / 180.0;

/// The forcing factor ([`crate::spatial::ekf::Adaptation`]) at which the guard's reference
/// carries roll and pitch beside the pendulum with [`REFERENCE_SD`]; below it, with that
/// times sqrt(this / factor), and not at all beyond ten times.
const REFERENCE_FORCING: f64 = 100.0;

/// Standard deviation \[rad/s\] of the gyro's bias read at rest: 0.01 deg/s.
const REST_BIAS_SD: f64 = 0.01 * core::f64::consts::PI / 180.0;

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// The guard: the inclination reference takes the sample (the accelerometer less the
    /// acceleration the filter knows of: O's travel and the lever arm from O), and when the
    /// filter's up direction has left the reference's by more than
    /// [`crate::spatial::ekf::Settings::guard_angle`], the attitude is turned onto it
    /// ([`Self::reset_onto_reference`]).
    pub(super) fn guard(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        drive: &Drive<T>,
        have_phi: bool,
        accel_ok: bool,
    ) -> Flags {
        let st = self.settings;
        let Some(f) = self.state.filter.as_ref() else {
            return Flags::empty();
        };
        let x = *f.state();
        let w = drive.gyro - x.bias;
        let acc = Accelerometer {
            gravity: st.params.gravity,
            per_speed: drive.centre_accel_per_speed(&w),
            lever: lever_arm(&w, &drive.angular_accel, &self.coeffs.accel_from_centre),
            r: T::one(),
        };
        // O's travel only while a `speed` column reads it: a filter that lost its way would
        // otherwise lead the reference astray with it.
        let known = if self.state.speed.travelling {
            acc.predict(&x) - x.up() * st.params.gravity
        } else {
            acc.lever
        };
        let z = Vector3::new(s.accel[0], s.accel[1], s.accel[2]) - known;
        // A missing reading: the gyro carries the reference over it.
        let z = accel_ok.then_some(z);
        // While the gyro is held the reference cannot follow the body: it waits, then takes
        // the filter's inclination (the encoders carried it) and guards again from there.
        // Without the encoders nothing carried the filter better than the reference: it
        // runs on the held rate as the filter does (taking the filter's inclination after
        // one missing gyro reading left imu3d 0.07 deg worse for 20 s, tests/faults3d).
        let guard = &mut self.state.guard;
        if self.state.gyro.held_for > T::zero() && st.use_encoders {
            guard.held = true;
            return Flags::empty();
        }
        if core::mem::replace(&mut guard.held, false) {
            guard.reference.align_up(&x.up());
        }
        // The gyro as read: the filter's bias estimate is what the guard guards against.
        guard.reference.update(&drive.gyro, z.as_ref(), dt);
        if self.state.gyro.held_bias.is_some() {
            return Flags::empty();
        }
        guard.age += dt;
        // The reference needs a few time constants to settle on its start.
        if !(self.reference_settled() && have_phi) {
            return Flags::empty();
        }
        let (u, r) = (x.up(), self.state.guard.reference.up());
        if u.angle(&r) <= st.guard_angle {
            return Flags::empty();
        }
        self.reset_onto_reference(s, &r, &u)
    }

    /// The attitude turned from up direction `u` onto the reference's `r` (the smallest
    /// turn: the heading kept), its roll and pitch loosened to the guard's angle and
    /// uncorrelated, and the joint states started again at the encoders' reading.
    fn reset_onto_reference(
        &mut self,
        s: &SpatialSample<T>,
        r: &Vector3<T>,
        u: &Vector3<T>,
    ) -> Flags {
        let st = self.settings;
        let Some(turn) = UnitQuaternion::rotation_between(r, u) else {
            return Flags::empty();
        };
        let mut dx = Error::<T>::zeros();
        dx.fixed_rows_mut::<3>(ROT).copy_from(&turn.scaled_axis());
        let Some(f) = self.state.filter.as_mut() else {
            return Flags::empty();
        };
        f.retract(&dx);
        let x = *f.state();
        let mut p = *f.covariance();
        loosen_roll_pitch(&mut p, st.guard_angle);
        self.state.filter = Some(F::start(x, p));
        if st.use_encoders {
            let z = SVector::<T, 2>::new(-s.phi[0], -s.phi[1]);
            let pred = self.coeffs.encoders.predict(&x);
            let z = SVector::<T, 2>::from_fn(|i, _| pred[i] + wrap_pi(z[i] - pred[i]));
            self.restart_joints(&z);
        }
        self.state.rejected = 0;
        Flags::RESET
    }

    /// Whether the guard's reference has run long enough to be trusted (two of its time
    /// constants).
    pub(super) fn reference_settled(&self) -> bool {
        self.settings.guard_angle.is_finite()
            && self.state.guard.reference.is_started()
            && self.state.guard.age > self.settings.guard_tau * T::lit(2.0)
    }

    /// While the pendulum is not used, the guard's reference carries roll and pitch: its up
    /// direction as a measurement of the attitude, standard deviation
    /// [`REFERENCE_SD`] (what it keeps to on BROAD's hand-held motion), as VQF would.
    pub(super) fn sense_reference(&mut self, unused: bool, dt: T) {
        if !(self.reference_settled() && dt > T::zero()) {
            return;
        }
        let Some(filter) = self.state.filter.as_mut() else {
            return;
        };
        let sd = if unused {
            T::lit(REFERENCE_SD)
        } else {
            T::lit(REFERENCE_SD)
                * (T::lit(REFERENCE_FORCING) / self.state.forcing.factor())
                    .sqrt()
                    .max(T::one())
        };
        if sd > T::lit(10.0 * REFERENCE_SD) {
            return;
        }
        // Beside the pendulum, the reference's error is correlated over its time constant:
        // each sample carries dt / tau of an independent reading's information. Without the
        // pendulum, it carries roll and pitch alone, as in an IMU filter.
        let r = if unused {
            sd * sd
        } else {
            sd * sd * self.settings.guard_tau / dt
        };
        let up = UpDirection { r };
        let _ = filter.update(&up, &self.state.guard.reference.up(), Gate::off());
    }

    /// While the guard's rest detection says the body rests, the gyro's low-pass is its
    /// bias on every axis, the vertical one too (which the pendulum cannot see at rest, and
    /// which hand-held motion would otherwise drive to several deg/s as the model's
    /// mismatch): a measurement of the bias, standard deviation [`REST_BIAS_SD`], its
    /// error correlated over the rest filter's time constant.
    pub(super) fn sense_rest(&mut self, dt: T) {
        let on = self.settings.guard_angle.is_finite();
        if !(on && self.state.guard.reference.is_resting() && dt > T::zero()) {
            return;
        }
        let Some(filter) = self.state.filter.as_mut() else {
            return;
        };
        let sd = T::lit(REST_BIAS_SD);
        let m = RestBias {
            r: sd * sd * T::lit(crate::spatial::imu::REST_TAU) / dt,
        };
        let _ = filter.update(&m, &self.state.guard.reference.bias(), Gate::off());
    }
}
