//! Hold-and-flag input gating for the gyro + accelerometer estimators (the complementary
//! filter here, the planar `ahrs` wrappers of the std crate's `peers`), which shared the
//! same preamble: a sample whose time is not finite or does not advance is refused
//! ([`Flags::BAD_TIME_STEP`], the caller holds its output); a missing gyro reading is
//! replaced by the recent mean of the good ones ([`MISSING_RATE_TAU`],
//! [`Flags::SAMPLE_MISSING`]); the time step runs from the last accepted sample. Once the
//! gyro is back, the angle the hold integrated through the gap is corrected
//! ([`InputHold::bridged`], the angle turned through the gap fitted to the readings on both
//! sides by [`super::gap_fit`]).
use super::gap_fit::{turned_through, Tail, Trail, FIT_MIN_BEFORE, FIT_WINDOW};
use crate::{Flags, Real, Sample, StepClock};

/// Time constant \[s\] of the gyro mean that stands in for a missing reading. The last
/// reading would carry one sample of the body's angular vibration through the gap (the
/// scooter's 40 Hz, 0.25 rad/s): integrated over 100 missing samples of the simulated
/// scooter rides (seeds 1, 3, 6, 200 gaps), the angle was off by 1.06-1.09 deg RMS with the
/// last reading, 0.43-0.59 deg with a 25 ms mean and 0.52-0.74 deg with a 50 ms one (a
/// longer mean lags the manoeuvres).
pub const MISSING_RATE_TAU: f64 = 0.025;

/// How long after a gap in the gyro its readings are taken in before the bridge over it
/// is handed out ([`GapBridge::take`], [`InputHold::bridged`]) \[s\]: the fit's window
/// ([`super::gap_fit::FIT_WINDOW`], 0.42 s).
pub const BRIDGE_WINDOW: f64 = FIT_WINDOW;

/// A gap in the gyro: held, then averaged after it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Gap<T> {
    /// The mean held through it \[rad/s\].
    held: T,
    /// Its length: the held steps \[s\].
    length: T,
    /// Time since its end \[s\]; zero while it lasts.
    since: T,
    /// Sums of `w g dt` and `w dt` over the readings after it, `w = exp(-t / tau)` (the
    /// simpler rule's mean after it).
    sum: T,
    weight: T,
    /// The readings before it and after it, for the fit over it ([`super::gap_fit`]).
    before: Trail<T>,
    after: Tail<T>,
}

/// The bridge over a gap in a rate (one gyro axis) that was held at the recent mean of its
/// readings: once [`BRIDGE_WINDOW`] of readings have come after the gap, the angle the
/// hold integrated wrong through it ([`GapBridge::take`]). One per gyro axis: the planar
/// [`InputHold`], and the 3-D peers of the std crate axis by axis (there the three
/// corrections form a small rotation vector in body axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GapBridge<T> {
    /// A reading has come since the start: a gap before it holds nothing read.
    seen: bool,
    /// The gap being held or averaged after.
    gap: Option<Gap<T>>,
    /// A correction found and not yet taken: (angle \[rad\], age \[s\]).
    pending: Option<(T, T)>,
    /// The readings since the start or the last gap, for the fit over the next one.
    trail: Trail<T>,
}

impl<T: Real> Default for GapBridge<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> GapBridge<T> {
    /// No gap yet.
    pub fn new() -> Self {
        Self {
            seen: false,
            gap: None,
            pending: None,
            trail: Trail::new(),
        }
    }

    /// The correction \[rad\] to add to the angle integrated through the last gap, once
    /// [`BRIDGE_WINDOW`] of readings have come after it (zero otherwise, and after it was
    /// taken once).
    ///
    /// Through the gap the hold integrated the mean of the readings before it, `m_b`. The
    /// angle the rate turned through the gap is fitted to the readings on both sides
    /// ([`super::gap_fit`]: a cubic through the integrated rate before and after, which
    /// follows the manoeuvre's curve); the correction is that
    /// angle less `L m_b`. On 100 missing readings of the simulated scooter3d rides (seeds
    /// 1-3, 246 gaps) the angle through the gap was off by 0.012 deg RMS (at most 0.037)
    /// with the fit, 0.043 (at most 0.106) with the line between 25 ms means of the rate
    /// on either side that it replaced; on the planar scooter rides, whose 40 Hz vibration
    /// is 20 times stronger, 0.084 deg against 0.083, the same.
    ///
    /// Where a side holds too little for the fit (less than [`super::gap_fit::FIT_MIN_BEFORE`]
    /// of readings before the gap, or a next gap within [`BRIDGE_WINDOW`] after it), the rate
    /// is taken as that line: the readings after the gap are averaged with weights mirroring
    /// the mean before it into `m_a`, and the line's integral over a gap of length `L` is
    /// `L (m_b + m_a) / 2` whatever the means' time constant.
    ///
    /// `gain` \[1/s\] is the rate at which the estimator forgets an angle error (Mahony's
    /// `kp`, a complementary filter's `1 / tau`; zero for none): it has already forgotten
    /// part of the error the hold made since it was made, so the correction is that much
    /// smaller (`exp(-gain age)`, `age` from the correction's centroid in the gap).
    pub fn take(&mut self, gain: T) -> T {
        match self.pending.take() {
            Some((angle, age)) => angle * (-gain.max(T::zero()) * age).exp(),
            None => T::zero(),
        }
    }

    /// One sample of the rate: `reading` \[rad/s\] (not finite: missing, and `mean`, the
    /// recent mean of the readings ([`MISSING_RATE_TAU`]), stood in for it) after a step of
    /// `dt` \[s\] (`None` on the first sample). A gap counts from the first reading on.
    pub fn offer(&mut self, reading: T, mean: T, dt: Option<T>) {
        match dt {
            Some(dt) if self.seen && reading.is_finite() => self.reading(reading, dt),
            Some(dt) if self.seen => self.held(mean, dt),
            _ => {}
        }
        self.seen |= reading.is_finite();
    }

    /// Whether a reading has come since the start.
    pub fn seen(&self) -> bool {
        self.seen
    }

    /// A held step of `dt`: `mean` stood in for the missing rate.
    fn held(&mut self, mean: T, dt: T) {
        match &mut self.gap {
            Some(g) if g.since == T::zero() => g.length += dt,
            _ => {
                // A new gap, or one in the readings after the last: close that with what
                // came so far.
                self.close_gap();
                self.gap = Some(Gap {
                    held: mean,
                    length: dt,
                    since: T::zero(),
                    sum: T::zero(),
                    weight: T::zero(),
                    before: self.trail,
                    after: Tail::new(),
                });
                self.trail = Trail::new();
            }
        }
    }

    /// A good reading `g` after a step of `dt`: averaged after the gap, if one was held.
    fn reading(&mut self, g: T, dt: T) {
        self.trail.push(g, dt);
        let Some(gap) = &mut self.gap else {
            return;
        };
        gap.after.push(g, dt);
        let tau = T::lit(MISSING_RATE_TAU);
        let w = (-(gap.since + dt * T::lit(0.5)) / tau).exp() * dt;
        gap.sum += w * g;
        gap.weight += w;
        gap.since += dt;
        if gap.since >= T::lit(BRIDGE_WINDOW) {
            self.close_gap();
        }
    }

    /// Turns the gap into the correction [`GapBridge::take`] hands out.
    fn close_gap(&mut self) {
        let Some(gap) = self.gap.take() else {
            return;
        };
        if gap.weight <= T::zero() {
            return;
        }
        let (l, c) = (gap.length, T::lit(MISSING_RATE_TAU));
        let two = T::lit(2.0);
        let fitted = (gap.after.since() >= T::lit(BRIDGE_WINDOW)
            && gap.before.weight() >= T::lit(FIT_MIN_BEFORE))
        .then(|| turned_through(&gap.before, &gap.after, l))
        .flatten();
        let angle = match fitted {
            Some(turned) => T::lit(turned) - gap.held * l,
            // Too little on a side for the fit (a gap soon after the start or after
            // another, or one cut short by the next): the line between the means.
            None => l * (gap.sum / gap.weight - gap.held) / two,
        };
        // The correction grows along the gap as the line less the held mean, as `u + c` at
        // `u` from its start: its centroid lies `l (l / 3 + c / 2) / (l / 2 + c)` in.
        let centroid = l * (l / T::lit(3.0) + c / two) / (l / two + c);
        let age = gap.since + l - centroid;
        if angle.is_finite() && age.is_finite() {
            self.pending = Some((angle, age));
        }
    }
}

/// What [`InputHold::begin`] makes of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step<T> {
    /// The time is not finite or not after the last accepted sample: do nothing with it,
    /// return the previous estimate flagged [`Flags::BAD_TIME_STEP`].
    BadTime,
    /// No sample accepted yet: start on this one if its other inputs allow, and then call
    /// [`InputHold::started`].
    First {
        /// The gyro reading, or the recent mean of the good ones.
        gyro: T,
        /// [`Flags::SAMPLE_MISSING`] if the gyro was missing.
        flags: Flags,
    },
    /// A later sample, already accepted.
    Next {
        /// Time since the last accepted sample \[s\], positive.
        dt: T,
        /// The gyro reading, or the recent mean of the good ones.
        gyro: T,
        /// [`Flags::SAMPLE_MISSING`] if the gyro was missing.
        flags: Flags,
    },
}

/// The time and gyro state behind [`Step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputHold<T> {
    clock: StepClock<T>,
    /// The gyro's recent mean [rad/s] ([`MISSING_RATE_TAU`]); zero before any reading.
    mean_gyro: T,
    /// What the hold integrated wrong through the last gap, once the readings after it tell.
    bridge: GapBridge<T>,
}

impl<T: Real> Default for InputHold<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> InputHold<T> {
    /// Nothing accepted yet; a gyro missing before any good reading is taken as zero.
    pub fn new() -> Self {
        Self {
            clock: StepClock::new(),
            mean_gyro: T::zero(),
            bridge: GapBridge::new(),
        }
    }

    /// Gates sample `s` (see [`Step`]).
    #[inline]
    pub fn begin(&mut self, s: &Sample<T>) -> Step<T> {
        let Ok(step) = self.clock.offer(s.dt) else {
            return Step::BadTime;
        };
        let mut flags = Flags::empty();
        let seen = self.bridge.seen();
        self.bridge.offer(s.gyro, self.mean_gyro, step);
        let gyro = if s.gyro.is_finite() {
            let a = match step {
                Some(dt) if seen => (dt / T::lit(MISSING_RATE_TAU)).min(T::one()),
                _ => T::one(),
            };
            self.mean_gyro = self.mean_gyro + a * (s.gyro - self.mean_gyro);
            s.gyro
        } else {
            flags |= Flags::SAMPLE_MISSING;
            self.mean_gyro
        };
        match step {
            None => Step::First { gyro, flags },
            Some(dt) => {
                self.clock.accept();
                Step::Next { dt, gyro, flags }
            }
        }
    }

    /// The correction \[rad\] to add to the angle integrated through the last gap in the
    /// gyro, once [`BRIDGE_WINDOW`] of readings have come after it, less what an estimator
    /// forgetting an angle error at `gain` \[1/s\] forgot of it since ([`GapBridge::take`]);
    /// zero otherwise, and after it was taken once.
    pub fn bridged(&mut self, gain: T) -> T {
        self.bridge.take(gain)
    }

    /// The estimator started on the sample just gated: later steps run from it.
    pub fn started(&mut self) {
        self.clock.accept();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(dt: f64, gyro: f64) -> Sample<f64> {
        Sample {
            dt,
            phi: f64::NAN,
            gyro,
            ax: 0.0,
            ay: 9.8,
        }
    }

    #[test]
    fn first_then_steps_with_the_gyro_held_and_bad_times_refused() {
        let mut h = InputHold::<f64>::new();
        // Not started: the time is not taken, so the next sample is First again.
        assert_eq!(
            h.begin(&s(0.0, f64::NAN)),
            Step::First {
                gyro: 0.0,
                flags: Flags::SAMPLE_MISSING
            }
        );
        assert_eq!(
            h.begin(&s(0.5, 0.3)),
            Step::First {
                gyro: 0.3,
                flags: Flags::empty()
            }
        );
        h.started();
        assert_eq!(h.begin(&s(0.0, 0.0)), Step::BadTime);
        assert_eq!(h.begin(&s(-0.1, 0.0)), Step::BadTime);
        assert_eq!(h.begin(&s(f64::NAN, 0.0)), Step::BadTime);
        assert_eq!(
            h.begin(&s(0.25, f64::NAN)),
            Step::Next {
                dt: 0.25,
                gyro: 0.3,
                flags: Flags::SAMPLE_MISSING
            }
        );
        assert_eq!(
            h.begin(&s(0.25, -0.1)),
            Step::Next {
                dt: 0.25,
                gyro: -0.1,
                flags: Flags::empty()
            }
        );
    }

    #[test]
    fn a_missing_gyro_is_the_recent_mean_not_the_last_vibrating_reading() {
        let mut h = InputHold::<f64>::new();
        h.begin(&s(0.0, 1.0));
        h.started();
        // A 250 Hz square wave around 0.2 rad/s at 1 kHz: the last reading is 1.2 or -0.8.
        for k in 1..200 {
            let g = if (k / 2) % 2 == 0 { 1.2 } else { -0.8 };
            h.begin(&s(1e-3, g));
        }
        let Step::Next { gyro, flags, .. } = h.begin(&s(1e-3, f64::NAN)) else {
            panic!("a step");
        };
        assert!(flags.contains(Flags::SAMPLE_MISSING));
        // The 25 ms mean leaves about 1 / (2 pi 250 Hz 25 ms) = 2.5 % of the square wave.
        assert!((gyro - 0.2).abs() < 0.05, "{gyro}");
    }

    /// The rate ramps through a 100 ms gap: the hold integrates the mean before it, the
    /// bridge adds what the ramp turned beyond that, once [`BRIDGE_WINDOW`] of readings
    /// follow.
    #[test]
    fn a_ramp_through_a_gap_is_integrated_by_the_bridge() {
        let dt = 1e-3;
        let rate = |k: usize| 0.1 + 2.0 * k as f64 * dt; // 2 rad/s^2
        let mut h = InputHold::<f64>::new();
        h.begin(&s(0.0, rate(0)));
        h.started();
        let (mut held, mut truth) = (0.0, 0.0);
        let mut bridge = 0.0;
        for k in 1..1700 {
            let missing = (1000..1100).contains(&k);
            let Step::Next { gyro, .. } = h.begin(&s(dt, if missing { f64::NAN } else { rate(k) }))
            else {
                panic!("a step");
            };
            if k >= 1000 {
                held += gyro * dt;
                truth += rate(k) * dt;
            }
            let b = h.bridged(0.0);
            if b != 0.0 {
                // Handed out once, BRIDGE_WINDOW after the gap's end.
                assert_eq!(k, 1100 + (BRIDGE_WINDOW / dt).round() as usize - 1);
                assert_eq!(h.bridged(0.0), 0.0);
            }
            bridge += b;
        }
        // The hold is off by the ramp's rise over the gap and the mean's lag, (tau + L / 2)
        // 2 rad/s^2 L = 15 mrad; the bridge's cubic in angle holds a ramp in rate exactly.
        let off = truth - held;
        assert!(
            (off - 2.0 * (MISSING_RATE_TAU + 0.05) * 0.1).abs() < 1e-3,
            "{off}"
        );
        assert!((truth - held - bridge).abs() < 1e-9, "{bridge} for {off}");
    }

    /// An estimator that forgets an angle error at `gain` takes less of the correction,
    /// the more the older it is; and a gap before any good reading is not bridged.
    #[test]
    fn the_bridge_is_forgotten_at_the_gain_and_needs_a_reading_before_the_gap() {
        let run = |gain: f64, first_good: usize| {
            let mut h = InputHold::<f64>::new();
            h.begin(&s(0.0, f64::NAN));
            h.started();
            let mut total = 0.0;
            for k in 1..700 {
                let g = if k < first_good || (100..150).contains(&k) {
                    f64::NAN
                } else if k < 100 {
                    0.0
                } else {
                    1.0
                };
                h.begin(&s(1e-3, g));
                total += h.bridged(gain);
            }
            total
        };
        // 50 ms held at 0 where the rate is 1 rad/s after: half of it is the line's.
        let full = run(0.0, 1);
        assert!((full - 0.025).abs() < 1e-3, "{full}");
        let k = 2.0;
        let part = run(k, 1);
        // Its age lies between the window and the window plus the gap.
        assert!(part < full * (-k * BRIDGE_WINDOW).exp() + 1e-12, "{part}");
        assert!(part > full * (-k * (BRIDGE_WINDOW + 0.05)).exp(), "{part}");
        // Missing from the start until the gap: nothing was held from a reading.
        assert_eq!(run(0.0, 150), 0.0);
    }
}
