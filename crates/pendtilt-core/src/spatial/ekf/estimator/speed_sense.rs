//! The `speed` column: O's forward speed and rate as states while it is read, held at
//! zero without it, and checked for wheel slip against the accelerometer.
use super::ModelBased;
use crate::engine::{Cov, Gate, GaussianFilter, Rejected};
use crate::spatial::ekf::slip::longitudinal_accel;
use crate::spatial::ekf::state::{Error, State, ACC, N, V};
use crate::spatial::SpatialSample;
use crate::{Flags, Real};
use nalgebra::{SVector, Vector3};

/// Standard deviation of O's speed \[m/s\] and its rate \[m/s^2\] while no `speed` column
/// reads them: both held at zero (O not accelerating), with a variance small enough to
/// move nothing and large enough to keep the covariance positive definite (the UKF's
/// Cholesky factor).
pub(super) const HELD_TRAVEL_SD: f64 = 1e-6;

impl<T: Real, F: GaussianFilter<T, State<T>, N>> ModelBased<T, F> {
    /// After [`crate::spatial::ekf::SpeedSettings::timeout`] without a `speed` reading O's
    /// travel is held at zero and the slip detector starts again.
    pub(super) fn speed_timeout(&mut self, dt: T) {
        if let Some(e) = self.state.speed.since.as_mut() {
            *e += dt;
            if *e > self.settings.speed.timeout && self.state.speed.travelling {
                self.hold_travel();
                self.state.speed.slip.reset();
            }
        }
    }

    /// Holds O's speed and rate at zero (no `speed` reading for longer than
    /// [`crate::spatial::ekf::SpeedSettings::timeout`]): the state at zero, its
    /// variance at [`HELD_TRAVEL_SD`] and uncorrelated.
    fn hold_travel(&mut self) {
        let Some(f) = self.state.filter.as_mut() else {
            return;
        };
        let x = f.state().travel;
        let mut dx = Error::<T>::zeros();
        dx[V] = -x[0];
        dx[ACC] = -x[1];
        f.retract(&dx);
        let mut t = Cov::<T, N>::identity();
        t[(V, V)] = T::zero();
        t[(ACC, ACC)] = T::zero();
        f.transform(&t);
        for k in [V, ACC] {
            let mut v = Error::<T>::zeros();
            v[k] = T::lit(HELD_TRAVEL_SD);
            f.inflate(&v);
        }
        self.state.speed.travelling = false;
    }

    /// The `speed` column's reading after the prediction: checked for wheel slip against
    /// the accelerometer ([`Flags::SLIP`]: not used while it slips), then a measurement of
    /// O's speed; the first after none starts O's speed there, its rate unknown. `gyro`
    /// and `wd` are the drive's rate and angular acceleration.
    pub(super) fn sense_speed(
        &mut self,
        s: &SpatialSample<T>,
        dt: T,
        gyro: &Vector3<T>,
        wd: &Vector3<T>,
    ) -> Flags {
        let reading = s.speed.is_finite();
        if !self.speed_in_reach(s) {
            return Flags::empty();
        }
        if self.state.filter.is_none() {
            return Flags::empty();
        }
        let a = self.longitudinal_accel(s, gyro, wd);
        // The detector runs on every row, the last reading held between readings (a slower
        // speed signal): the accelerometer's vibration sampled on the speed's rows alone
        // would alias into its band (ride3d with the speed on one row in 20: 2,543 rows
        // falsely flagged).
        let speed = &mut self.state.speed;
        if speed.slip.update(speed.last, a, dt).slip {
            return Flags::SLIP;
        }
        if !reading {
            return Flags::empty();
        }
        if !self.state.speed.travelling {
            self.start_travel(s);
            return Flags::empty();
        }
        self.update_speed(s)
    }

    /// Takes a reading in and tells whether the speed is still followed: read now, or
    /// within the timeout of the last reading.
    fn speed_in_reach(&mut self, s: &SpatialSample<T>) -> bool {
        let speed = &mut self.state.speed;
        if s.speed.is_finite() {
            speed.since = Some(T::zero());
            speed.last = s.speed;
            true
        } else {
            speed
                .since
                .is_some_and(|e| e <= self.settings.speed.timeout)
        }
    }

    /// The accelerometer's reading along O's path less gravity and the lever arm (NaN
    /// without a reading), for the slip detector.
    fn longitudinal_accel(&self, s: &SpatialSample<T>, gyro: &Vector3<T>, wd: &Vector3<T>) -> T {
        let Some(f) = self.state.filter.as_ref() else {
            return T::nan();
        };
        if s.accel.iter().all(|v| v.is_finite()) {
            longitudinal_accel(
                &Vector3::new(s.accel[0], s.accel[1], s.accel[2]),
                &f.state().up(),
                self.settings.params.gravity,
                &(gyro - f.state().bias),
                wd,
                &self.coeffs.accel_from_centre,
            )
        } else {
            T::nan()
        }
    }

    /// The first reading after none: O's speed starts there, its rate unknown.
    fn start_travel(&mut self, s: &SpatialSample<T>) {
        let Some(f) = self.state.filter.as_mut() else {
            return;
        };
        let sp = &self.settings.speed;
        let mut dx = Error::<T>::zeros();
        dx[V] = s.speed - f.state().travel[0];
        f.retract(&dx);
        let mut v = Error::<T>::zeros();
        v[V] = sp.noise;
        f.inflate(&v);
        let mut v = Error::<T>::zeros();
        v[ACC] = sp.initial_rate;
        f.inflate(&v);
        self.state.speed.travelling = true;
    }

    /// The reading as a measurement of O's speed, through its gate; a run of
    /// [`crate::spatial::ekf::Settings::reacquire_after`] rejections re-acquires it.
    fn update_speed(&mut self, s: &SpatialSample<T>) -> Flags {
        let Some(f) = self.state.filter.as_mut() else {
            return Flags::empty();
        };
        let speed = &mut self.state.speed;
        let z = SVector::<T, 1>::new(s.speed);
        let gate = if speed.rejected >= self.settings.reacquire_after.max(1) {
            // Re-acquired as the encoders are: the speed's variance grows by the
            // innovation's square and the reading is applied ungated.
            let mut v = Error::<T>::zeros();
            v[V] = s.speed - f.state().travel[0];
            f.inflate(&v);
            Gate::off()
        } else {
            Gate {
                threshold: self.settings.innovation_gate,
                floor: T::zero(),
            }
        };
        match f.update(&self.coeffs.speed, &z, gate) {
            Ok(()) => {
                speed.rejected = 0;
                Flags::empty()
            }
            Err(e) => {
                if e == Rejected::Outlier {
                    speed.rejected = speed.rejected.saturating_add(1);
                }
                Flags::MEASUREMENT_SKIPPED
            }
        }
    }
}
