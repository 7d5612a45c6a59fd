//! Starts and restarts: the first start with the pendulum hanging still, the gaps that
//! are not bridged, the gyro bias kept over them, and a filter that became non-finite.
use super::covariance::HEADING_VARIANCE;
use super::speed_sense::HELD_TRAVEL_SD;
use super::ModelBased;
use crate::engine::{Cov, GaussianFilter};
use crate::spatial::attitude::roll_pitch_from_up;
use crate::spatial::ekf::state::{State, A, ACC, B, BIAS, N, P, R, ROT, V};
use crate::spatial::{Attitude, SpatialSample};
use crate::{Flags, Real};
use nalgebra::{UnitQuaternion, Vector2, Vector3, Vector4};

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// The gaps before sample `s` (step `dt`): a gap in the rows or in the gravity
    /// reference's readings longer than [`crate::spatial::ekf::Settings::max_gap`] is not
    /// bridged: the filter and the guard's reference start again, the gyro bias kept.
    /// Returns the estimate when the filter (re)starts on this sample or is waiting for a
    /// reading to start on.
    pub(super) fn gaps(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        have_phi: bool,
    ) -> Option<Attitude<T>> {
        if let Some(e) = self.state.since_phi.as_mut() {
            *e += s.dt;
        }
        let max_gap = self.settings.max_gap;
        // imu3d: the gyro carries the attitude over missing accelerometer readings, as in
        // any IMU filter; only a gap of both sensors is not bridged (restarting after 0.1 s
        // without the accelerometer took a moving scooter's acceleration for tilt: 43 deg).
        let coasted = have_phi
            && self.state.since_phi.is_some_and(|e| e > max_gap)
            && (self.settings.use_encoders || self.state.gyro.held_for > max_gap);
        if self.state.filter.is_some() && (dt > max_gap || coasted) {
            self.keep_bias();
            self.state.filter = None;
            // Its attitude is as stale as the filter's: both start again.
            self.state.guard.reset();
        }
        if have_phi {
            self.state.since_phi = Some(T::zero());
        }
        if self.state.filter.is_some() {
            return None;
        }
        Some(if have_phi {
            self.start(s)
        } else {
            self.hold(Flags::INITIALISING | Flags::SAMPLE_MISSING)
        })
    }

    /// Keeps the running filter's gyro bias for the next start, its variances grown by the
    /// bias walk over the time since the last encoder reading.
    pub(super) fn keep_bias(&mut self) {
        let walk = self.settings.sensors.gyro_bias_walk;
        let grow = walk * walk * self.state.since_phi.unwrap_or(T::zero());
        if let Some(f) = self.state.filter.as_ref() {
            let p = f.covariance();
            let var = Vector3::from_fn(|k, _| p[(BIAS + k, BIAS + k)] + grow);
            self.state.kept_bias = Some((f.state().bias, var));
        }
    }

    /// The last estimate with `flags`.
    pub(super) fn hold(&self, flags: Flags) -> Attitude<T> {
        Attitude {
            flags,
            ..self.state.last
        }
    }

    /// Starts with the pendulum hanging still at the sample's encoder angles (imu3d: at
    /// the accelerometer's roll and pitch).
    fn start(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        let phi = if self.settings.use_encoders {
            s.phi
        } else {
            let f = s.accel;
            let (roll, pitch) = roll_pitch_from_up(f);
            [roll, pitch]
        };
        // The guard's reference once it has settled (a restart in motion: the pendulum
        // need not hang still), else the pendulum hanging still.
        let (roll, pitch) = if self.reference_settled() {
            let u = self.state.guard.reference.up();
            roll_pitch_from_up([u[0], u[1], u[2]])
        } else {
            (phi[0], phi[1])
        };
        let w = self.state.gyro.reading.unwrap_or_else(Vector3::zeros);
        let (a, b) = (-phi[0], -phi[1]);
        let (sa, ca) = a.sin_cos();
        let (sb, cb) = b.sin_cos();
        // Hanging still: the pendulum's rates about its own x and y axes are zero.
        let u3 = -sa * w[1] + ca * w[2];
        let kept = self.state.kept_bias.take();
        let x = State {
            q: UnitQuaternion::from_euler_angles(roll, pitch, T::zero()),
            bias: kept.map_or_else(Vector3::zeros, |k| k.0),
            joints: Vector4::new(a, b, sb * u3 / cb, T::zero()),
            travel: Vector2::zeros(),
        };
        let p = self.start_covariance(kept);
        let run = &mut self.state;
        run.speed.travelling = false;
        run.speed.rejected = 0;
        run.speed.since = None;
        run.filter = Some(F::start(x, p));
        run.rejected = 0;
        run.since_start = T::zero();
        run.clock.accept();
        run.last = Attitude {
            roll,
            pitch,
            flags: Flags::INITIALISING,
        };
        run.last
    }

    /// The covariance at a start: roll and pitch at the settings' initial angle, the
    /// heading at its bound ([`HEADING_VARIANCE`]), the gyro bias at the sensor's or as
    /// `kept`, the joints at the encoders', O's travel held.
    fn start_covariance(&self, kept: Option<(Vector3<T>, Vector3<T>)>) -> Cov<T, N> {
        let st = &self.settings;
        let mut p = Cov::<T, N>::zeros();
        let ang = st.initial_angle * st.initial_angle;
        p[(ROT, ROT)] = ang;
        p[(ROT + 1, ROT + 1)] = ang;
        // The heading is unknown, but only its bounded variance is useful (see
        // HEADING_VARIANCE).
        p[(ROT + 2, ROT + 2)] = T::lit(HEADING_VARIANCE);
        let b0 = st.sensors.gyro_bias;
        for k in 0..3 {
            p[(BIAS + k, BIAS + k)] = kept.map_or(b0 * b0 + T::lit(1e-12), |kept| kept.1[k]);
        }
        p[(A, A)] = self.coeffs.encoders.r;
        p[(B, B)] = self.coeffs.encoders.r;
        p[(P, P)] = ang;
        p[(R, R)] = ang;
        let held = T::lit(HELD_TRAVEL_SD * HELD_TRAVEL_SD);
        p[(V, V)] = held;
        p[(ACC, ACC)] = held;
        p
    }

    /// The estimate after the sensors: roll and pitch from the filter's up direction, or,
    /// if the prediction failed (not `ok`) or the filter became non-finite, the last
    /// estimate and a start at the next sample.
    pub(super) fn finish(&mut self, ok: bool, flags: Flags) -> Attitude<T> {
        let finite = self.state.filter.as_ref().is_some_and(|f| {
            let p = f.covariance();
            crate::engine::ErrorState::is_finite(f.state())
                && (0..N).fold(T::zero(), |acc, i| acc + p[(i, i)]).is_finite()
        });
        if !ok || !finite {
            self.state.filter = None;
            return self.hold(flags | Flags::INITIALISING);
        }
        let x = self.state.filter.as_ref().map(|f| *f.state());
        if let Some(x) = x {
            let u = x.up();
            let (roll, pitch) = roll_pitch_from_up([u[0], u[1], u[2]]);
            self.state.last = Attitude { roll, pitch, flags };
        }
        self.state.last
    }
}
