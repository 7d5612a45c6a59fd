//! The sensors of the pendulum estimator: each is a measurement model
//! ([`super::measurement`]) plus what the estimator does around it, so that
//! [`super::ModelBased`] applies them all by one loop: where the reading comes from in a
//! sample, which flags a missing reading raises, its innovation gate, and along which
//! directions the covariance grows when it is re-acquired after a run of outliers.
use super::measurement::{Accelerometer, Encoder, Gyro};
use super::model::{State, BIAS, N, OMEGA, PHI, THETA};
use crate::engine::{Gate, Measurement};
use crate::{Flags, Real, Sample};
use nalgebra::{SVector, Vector1, Vector2};

/// A sensor of [`super::ModelBased`] with `M` values per reading.
pub trait Sensor<T: Real, const M: usize>: Measurement<T, State<T>, N, M> {
    /// The flags of a sample without this reading.
    const MISSING: Flags;

    /// This sample's reading, given the state predicted for it, with any flags it raises;
    /// `None` if the sample lacks it.
    fn reading(&self, s: &Sample<T>, x: &State<T>) -> Option<(SVector<T, M>, Flags)>;

    /// The gate for the settings' threshold ([`super::ModelSettings::innovation_gate`]).
    #[inline]
    fn gate(&self, threshold: T) -> Gate<T> {
        Gate {
            threshold,
            floor: T::zero(),
        }
    }

    /// The directions `v` of the `v v^T` added to the covariance when this sensor is
    /// re-acquired, from the sample and the state at that moment (see
    /// [`super::ModelBased`]).
    fn inflation(&self, s: &Sample<T>, x: &State<T>) -> [State<T>; 2];
}

/// `x` wrapped into (-pi, pi].
#[inline]
pub(crate) fn wrap<T: Real>(x: T) -> T {
    if x.abs() > T::pi() {
        x.sin().atan2(x.cos())
    } else {
        x
    }
}

impl<T: Real> Sensor<T, 1> for Gyro<T> {
    const MISSING: Flags = Flags::SAMPLE_MISSING.union(Flags::MEASUREMENT_SKIPPED);

    #[inline]
    fn reading(&self, s: &Sample<T>, _x: &State<T>) -> Option<(Vector1<T>, Flags)> {
        s.gyro
            .is_finite()
            .then(|| (Vector1::new(s.gyro), Flags::empty()))
    }

    #[inline]
    fn gate(&self, threshold: T) -> Gate<T> {
        Gate {
            threshold,
            floor: self.gate_floor,
        }
    }

    /// A rate (`y` on theta') and, apart, an offset (`y` on the bias).
    fn inflation(&self, s: &Sample<T>, x: &State<T>) -> [State<T>; 2] {
        let y = s.gyro - x[OMEGA] - x[BIAS];
        let mut rate = State::<T>::zeros();
        rate[OMEGA] = y;
        let mut offset = State::<T>::zeros();
        offset[BIAS] = y;
        [rate, offset]
    }
}

impl<T: Real> Sensor<T, 1> for Encoder<T> {
    const MISSING: Flags = Flags::SAMPLE_MISSING.union(Flags::MEASUREMENT_SKIPPED);

    /// phi taken within half a turn of the prediction ([`Flags::ENCODER_WRAPPED`] if it
    /// moved).
    #[inline]
    fn reading(&self, s: &Sample<T>, x: &State<T>) -> Option<(Vector1<T>, Flags)> {
        if !s.phi.is_finite() {
            return None;
        }
        let pred = x[PHI];
        let z = pred + wrap(s.phi - pred);
        let flags = if (z - s.phi).abs() > T::lit(1e-9) {
            Flags::ENCODER_WRAPPED
        } else {
            Flags::empty()
        };
        Some((Vector1::new(z), flags))
    }

    /// `y` on theta and on phi together: a tilt step that leaves the pendulum where it
    /// hangs (an encoder re-zero reads exactly so; inflating phi and phi' apart, a
    /// pendulum swing, sent the nonlinear model spinning after a 2.5 rad step).
    fn inflation(&self, s: &Sample<T>, x: &State<T>) -> [State<T>; 2] {
        let y = wrap(s.phi - x[PHI]);
        let mut tilt = State::<T>::zeros();
        tilt[THETA] = y;
        tilt[PHI] = y;
        [tilt, State::<T>::zeros()]
    }
}

impl<T: Real> Sensor<T, 2> for Accelerometer<T> {
    const MISSING: Flags = Flags::MEASUREMENT_SKIPPED;

    #[inline]
    fn reading(&self, s: &Sample<T>, _x: &State<T>) -> Option<(Vector2<T>, Flags)> {
        (s.ax.is_finite() && s.ay.is_finite()).then(|| (Vector2::new(s.ax, s.ay), Flags::empty()))
    }

    /// `|y| / g` on theta.
    fn inflation(&self, s: &Sample<T>, x: &State<T>) -> [State<T>; 2] {
        let p = self.predict(x);
        let (ex, ey) = (s.ax - p[0], s.ay - p[1]);
        let mut tilt = State::<T>::zeros();
        tilt[THETA] = (ex * ex + ey * ey).sqrt() / self.gravity;
        [tilt, State::<T>::zeros()]
    }
}
