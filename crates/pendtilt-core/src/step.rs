//! Time as a step. Stamps become a step `dt` once, at the edge ([`StepGate`]), in the
//! stamp's own precision (`f64` seconds, or a timer's tick count); estimators only ever see
//! `dt`, and each checks it with one [`StepClock`]. An `f32` estimator therefore never
//! subtracts two large, rounded stamps (an `f32` stamp after an hour resolves only 0.24 ms).
use crate::{Flags, Real};

/// A time stamp that can measure the time since an earlier one.
pub trait Stamp: Copy {
    /// Seconds from `earlier` to `self` when that is finite and positive, else `None`.
    fn since(self, earlier: Self) -> Option<f64>;
    /// Whether this stamp can start a log (finite).
    fn is_valid(self) -> bool;
}

impl Stamp for f64 {
    #[inline]
    fn since(self, earlier: Self) -> Option<f64> {
        let d = self - earlier;
        (self.is_finite() && d > 0.0).then_some(d)
    }
    #[inline]
    fn is_valid(self) -> bool {
        self.is_finite()
    }
}

/// A free-running microsecond counter that wraps (a `u32` timer: 71 minutes per turn);
/// the difference is taken modulo 2^32, so a wrap is a normal step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Micros(pub u32);

impl Stamp for Micros {
    #[inline]
    fn since(self, earlier: Self) -> Option<f64> {
        let d = self.0.wrapping_sub(earlier.0);
        (d != 0).then(|| f64::from(d) * 1e-6)
    }
    #[inline]
    fn is_valid(self) -> bool {
        true
    }
}

/// Turns time stamps into the step since the last accepted stamp (`Sample::dt`), once for
/// every estimator. A refused stamp (not finite, or not after the last accepted one)
/// becomes `dt = NaN`, which every estimator flags [`Flags::BAD_TIME_STEP`]; the next good
/// stamp's step then spans from the last accepted one. The first stamp gives `dt = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepGate<S> {
    last: Option<S>,
}

impl<S: Stamp> Default for StepGate<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Stamp> StepGate<S> {
    /// No stamp seen yet.
    pub fn new() -> Self {
        Self { last: None }
    }

    /// The step to `stamp` in seconds, in the estimators' type (see the type's docs).
    #[inline]
    pub fn step<T: Real>(&mut self, stamp: S) -> T {
        match self.last {
            None if stamp.is_valid() => {
                self.last = Some(stamp);
                T::zero()
            }
            None => T::nan(),
            Some(last) => match stamp.since(last) {
                Some(d) => {
                    self.last = Some(stamp);
                    T::lit(d)
                }
                None => T::nan(),
            },
        }
    }

    /// The last accepted stamp.
    pub fn last(&self) -> Option<S> {
        self.last
    }
}

/// An estimator's view of time: refuses a bad step, and lets an estimator that holds on a
/// sample (a missing input) carry that sample's step into the next one, so the next step
/// spans the gap.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepClock<T> {
    started: bool,
    pending: T,
}

impl<T: Real> StepClock<T> {
    /// Not started: the next accepted sample is the first.
    pub fn new() -> Self {
        Self {
            started: false,
            pending: T::zero(),
        }
    }

    /// Whether a sample has been accepted since the start (or [`Self::restart`]).
    #[inline]
    pub fn started(&self) -> bool {
        self.started
    }

    /// Offers a sample's `dt`: `Err(BAD_TIME_STEP)` when it is not usable (not finite, or
    /// not positive once started), `Ok(None)` for the first sample, else `Ok(Some(step))`,
    /// the time since the last accepted sample. Call [`Self::accept`] if the sample is used;
    /// otherwise its step is carried into the next one.
    #[inline]
    pub fn offer(&mut self, dt: T) -> Result<Option<T>, Flags> {
        if !dt.is_finite() || (self.started && !crate::real::is_positive(dt)) {
            return Err(Flags::BAD_TIME_STEP);
        }
        if !self.started {
            return Ok(None);
        }
        self.pending += dt;
        Ok(Some(self.pending))
    }

    /// The offered sample was used: the next step starts from it.
    #[inline]
    pub fn accept(&mut self) {
        self.started = true;
        self.pending = T::zero();
    }

    /// Forgets the start: the next accepted sample is the first again.
    #[inline]
    pub fn restart(&mut self) {
        *self = Self::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gate_turns_stamps_into_steps_and_refuses_bad_ones() {
        let mut g = StepGate::<f64>::new();
        assert!(g.step::<f64>(f64::NAN).is_nan());
        assert_eq!(g.step::<f64>(1.0), 0.0);
        assert_eq!(g.step::<f64>(1.25), 0.25);
        assert!(g.step::<f64>(1.25).is_nan());
        assert!(g.step::<f64>(1.0).is_nan());
        assert!(g.step::<f64>(f64::INFINITY).is_nan());
        // Spans from the last accepted stamp.
        assert_eq!(g.step::<f64>(1.75), 0.5);
    }

    #[test]
    fn an_f32_step_after_two_hours_is_exact_to_f32() {
        let mut g = StepGate::<f64>::new();
        let t0 = 7200.0;
        g.step::<f32>(t0);
        let dt: f32 = g.step(t0 + 1e-3);
        assert!((dt - 1e-3).abs() < 1e-9, "{dt}");
        // The same difference of f32 stamps is 2.3 % off (their spacing there is 0.49 ms).
        let naive = (t0 as f32 + 1e-3) - t0 as f32;
        assert!((naive - 1e-3).abs() > 2e-5, "{naive}");
    }

    #[test]
    fn microsecond_counter_wraps_without_a_bad_step() {
        let mut g = StepGate::<Micros>::new();
        g.step::<f32>(Micros(u32::MAX - 499));
        let dt: f32 = g.step(Micros(500));
        assert!((dt - 1e-3).abs() < 1e-9, "{dt}");
        assert!(g.step::<f32>(Micros(500)).is_nan());
    }

    #[test]
    fn clock_carries_a_held_sample_into_the_next_step() {
        let mut c = StepClock::<f64>::new();
        assert_eq!(c.offer(f64::NAN), Err(Flags::BAD_TIME_STEP));
        assert_eq!(c.offer(0.0), Ok(None));
        c.accept();
        assert_eq!(c.offer(0.0), Err(Flags::BAD_TIME_STEP));
        assert_eq!(c.offer(-1.0), Err(Flags::BAD_TIME_STEP));
        assert_eq!(c.offer(0.25), Ok(Some(0.25)));
        // held (not accepted): the next step spans both
        assert_eq!(c.offer(0.5), Ok(Some(0.75)));
        c.accept();
        assert_eq!(c.offer(0.5), Ok(Some(0.5)));
        c.restart();
        assert_eq!(c.offer(0.5), Ok(None));
    }
}
