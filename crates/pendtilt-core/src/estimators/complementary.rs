//! A complementary filter, the peer most users would pick instead of a pendulum: the gyro
//! integrated for the fast part, the accelerometer angle (Eq 1) for the slow part,
//!
//! ```text
//! theta_k = alpha (theta_{k-1} + G_k dt) + (1 - alpha) atan2(ax, ay),   alpha = tau / (tau + dt)
//! ```
//!
//! a first-order high-pass on the gyro angle and a low-pass on the accelerometer angle
//! that add up to one, crossing over at `1 / (2 pi tau)`. Optionally ax and ay are
//! low-passed before atan2 (atan2 of raw samples rectifies vibration into a bias,
//! MODEL.md section 4).
use super::equations::accel_angle;
use super::input_hold::{InputHold, Step};
use crate::filters::biquad::LowPass2;
use crate::{Estimate, Estimator, Flags, Real, Sample};

/// Settings of [`Complementary`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplementarySettings<T> {
    /// Crossover time constant tau \[s\]. Default 0.75 s: the gain search
    /// (`pendtilt::peers::tune::search_peer_gains`) on the simulated scooter ride (60 s,
    /// seed 1, l12 = 0.2 m) found 0.754 s best, RMS error 0.81 deg (2 s gave 1.87 deg).
    pub time_constant: T,
    /// Cutoff \[Hz\] of a 2nd-order Butterworth low-pass on ax and ay before atan2.
    /// Default `Some(5 Hz)`: well below the engine vibration, well above the crossover.
    pub accel_prefilter_hz: Option<T>,
}

impl<T: Real> Default for ComplementarySettings<T> {
    fn default() -> Self {
        Self {
            time_constant: T::lit(0.75),
            accel_prefilter_hz: Some(T::lit(5.0)),
        }
    }
}

/// The complementary filter as a streaming estimator (column `complementary`).
///
/// Starts at the accelerometer angle of the first sample with both axes. For the first
/// tau seconds the crossover time constant is the time since the start, so that the
/// estimate is the mean of the accelerometer angle over that time (each reading carried
/// forward by the gyro) rather than one vibrating reading forgotten at the rate 1 / tau:
/// after a restart this put the filter within 0.05 deg of a run that never stopped
/// sooner (see `docs/reliability.md` section 7b). A missing gyro is replaced by its
/// recent mean ([`super::input_hold::MISSING_RATE_TAU`], [`Flags::SAMPLE_MISSING`]), and
/// the angle held through the gap is corrected once the gyro is back
/// ([`super::input_hold::InputHold::bridged`]); a missing accelerometer integrates the gyro alone ([`Flags::MEASUREMENT_SKIPPED`]).
///
/// After a long gap ([`Estimator::resume`]) it keeps its steady offset: a gyro bias `b`
/// holds the filter `b tau` from the accelerometer angle, which a gap cannot change but
/// the start-up mean builds up only to half by its end. The offset is the mean of the
/// gyro-carried angle less the accelerometer angle over the last [`OFFSET_WINDOW`] in
/// steady state; during the restart's start-up the accelerometer angle is read shifted by
/// the part of it the mean has not yet built up, `offset (1 - t / tau)`, so the filter
/// leaves its start-up in its steady state. A first start is unchanged.
#[derive(Debug, Clone)]
pub struct Complementary<T: Real> {
    settings: ComplementarySettings<T>,
    coeffs: Coefficients<T>,
    state: State<T>,
}

/// What the settings give once, so that the per-sample path and `reset` read them
/// rather than derive them again.
#[derive(Debug, Clone, Copy)]
struct Coefficients<T> {
    /// The crossover time constant, negative ones taken as 0.
    tau: T,
    /// The rate at which the filter forgets an angle error, `1 / tau` (0 for `tau = 0`):
    /// how much of a gap's error is left when its correction comes.
    forget_rate: T,
    /// The prefilter's settling time \[s\] (0 without it).
    settle: T,
}

impl<T: Real> Coefficients<T> {
    fn new(settings: &ComplementarySettings<T>) -> Self {
        let tau = settings.time_constant.max(T::zero());
        // The Butterworth's start from one reading decays as exp(-omega_c t / sqrt 2):
        // to 1 % in 4 sqrt(2) / omega_c (0.18 s at 5 Hz).
        let settle = match settings.accel_prefilter_hz {
            Some(f) if f > T::zero() => {
                T::lit(4.0 * core::f64::consts::SQRT_2 / core::f64::consts::TAU) / f
            }
            _ => T::zero(),
        };
        Self {
            tau,
            forget_rate: if tau > T::zero() {
                T::one() / tau
            } else {
                T::zero()
            },
            settle,
        }
    }
}

/// Everything a run changes: what `reset` starts again and `resume` keeps part of.
#[derive(Debug, Clone)]
struct State<T: Real> {
    lx: LowPass2<T>,
    ly: LowPass2<T>,
    input: InputHold<T>,
    theta: T,
    /// Time since the start \[s\] (the start-up time constant, up to tau).
    elapsed: T,
    /// Mean of the gyro-carried angle less the accelerometer angle in steady state.
    offset: SteadyOffset<T>,
    /// The offset kept through a restart \[rad\] (0 on a first start).
    kept: T,
    /// How much of the prefilter's settling time is left since the start \[s\].
    settling: T,
}

impl<T: Real> State<T> {
    fn new(settings: &ComplementarySettings<T>, coeffs: &Coefficients<T>) -> Self {
        let f = settings.accel_prefilter_hz.unwrap_or(T::one());
        Self {
            lx: LowPass2::new(f),
            ly: LowPass2::new(f),
            input: InputHold::new(),
            theta: T::nan(),
            elapsed: T::zero(),
            offset: SteadyOffset::new(),
            kept: T::zero(),
            settling: coeffs.settle,
        }
    }

    /// Back to the state before the first sample; the low-passes keep their design.
    fn reset(&mut self, coeffs: &Coefficients<T>) {
        self.lx.reset();
        self.ly.reset();
        self.input = InputHold::new();
        self.theta = T::nan();
        self.elapsed = T::zero();
        self.offset = SteadyOffset::new();
        self.kept = T::zero();
        self.settling = coeffs.settle;
    }
}

/// The running mean of a filter's tilt less the accelerometer angle in steady state, over
/// the last [`OFFSET_WINDOW`]: the offset a gyro bias holds the filter at, which a restart
/// keeps (the complementary filter's, and Mahony's in the std crate's planar peers).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SteadyOffset<T> {
    mean: T,
    /// How long it has been averaged \[s\], up to [`OFFSET_WINDOW`].
    time: T,
}

impl<T: Real> SteadyOffset<T> {
    /// Nothing averaged yet.
    pub fn new() -> Self {
        Self {
            mean: T::zero(),
            time: T::zero(),
        }
    }

    /// Averages in `d` \[rad\] (the tilt less the accelerometer angle, taken within half a
    /// turn) over a step of `dt` \[s\].
    pub fn update(&mut self, d: T, dt: T) {
        let d = if d.abs() > T::pi() {
            d.sin().atan2(d.cos())
        } else {
            d
        };
        self.time = (self.time + dt).min(T::lit(OFFSET_WINDOW));
        if self.time > T::zero() {
            self.mean += (d - self.mean) * dt / self.time;
        }
    }

    /// The mean \[rad\], once anything was averaged.
    pub fn value(&self) -> Option<T> {
        (self.time > T::zero()).then_some(self.mean)
    }
}

/// How long \[s\] the steady offset kept through a restart is averaged over: long enough
/// that the accelerometer's errors from vibration and manoeuvres average out, short against
/// the gyro bias's drift. 5, 10 and 20 s gave the same recoveries on the restarts of
/// `tests/plausibility/` (their gaps start 5-8 s into the ride, so the mean covers at
/// most 7 s there).
pub const OFFSET_WINDOW: f64 = 10.0;

impl<T: Real> Complementary<T> {
    /// A new estimator.
    pub fn new(settings: ComplementarySettings<T>) -> Self {
        let coeffs = Coefficients::new(&settings);
        Self {
            state: State::new(&settings, &coeffs),
            coeffs,
            settings,
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &ComplementarySettings<T> {
        &self.settings
    }

    fn accel(&mut self, s: &Sample<T>, dt: T) -> Option<T> {
        if !(s.ax.is_finite() && s.ay.is_finite()) {
            return None;
        }
        let st = &mut self.state;
        let a = match self.settings.accel_prefilter_hz {
            Some(_) => accel_angle(st.lx.update(s.ax, dt), st.ly.update(s.ay, dt)),
            None => accel_angle(s.ax, s.ay),
        };
        if !a.is_finite() {
            // The prefilter overflowed on an input near the type's largest value: restart it.
            st.lx.reset();
            st.ly.reset();
            return None;
        }
        Some(a)
    }

    /// Starts on the first accelerometer angle; after a restart, in its steady offset
    /// from the start.
    #[inline]
    fn start(&mut self, s: &Sample<T>, flags: Flags) -> Estimate<T> {
        match self.accel(s, T::one()) {
            Some(a) => {
                let st = &mut self.state;
                st.theta = a + st.kept;
                st.elapsed = T::zero();
                st.input.started();
                Estimate {
                    theta: st.theta,
                    flags: flags | Flags::INITIALISING,
                }
            }
            None => Estimate {
                theta: T::nan(),
                flags: flags | Flags::INITIALISING | Flags::SAMPLE_MISSING,
            },
        }
    }

    /// The angle carried by the gyro over `dt`, with the correction of the angle a gap in
    /// the gyro held wrong, once the readings after it tell.
    #[inline]
    fn predict(&mut self, gyro: T, dt: T, flags: &mut Flags) -> T {
        let st = &mut self.state;
        let predicted = st.theta + gyro * dt + st.input.bridged(self.coeffs.forget_rate);
        if !predicted.is_finite() {
            // A rate near the type's largest value over a long step overflows (found by
            // fuzzing): do not integrate it, keep the angle, flag the gyro.
            *flags |= Flags::SATURATED;
            return st.theta;
        }
        predicted
    }

    /// The gyro's angle `predicted` blended with the accelerometer angle `a`: followed
    /// while the prefilter settles, then with the start-up time constant (the kept offset
    /// read in during a restart), then with tau (the steady offset averaged).
    #[inline]
    fn blend(&mut self, predicted: T, a: T, dt: T, flags: &mut Flags) -> T {
        // Blend on the circle: the accelerometer angle taken within half a turn.
        let mut d = a - predicted;
        if d.abs() > T::pi() {
            d = d.sin().atan2(d.cos());
        }
        let (c, st) = (&self.coeffs, &mut self.state);
        if st.settling > T::zero() {
            // The prefilter still carries its first reading: follow it.
            st.settling -= dt;
            *flags |= Flags::INITIALISING;
            return a + st.kept;
        }
        let steady = st.elapsed >= c.tau;
        st.elapsed += dt;
        let tau = c.tau.min(st.elapsed);
        let alpha = tau / (tau + dt);
        if steady {
            st.offset.update(-d, dt);
        } else if st.kept != T::zero() && c.tau > T::zero() {
            // Restarting: the part of the kept offset the mean has not built up.
            d += st.kept * (T::one() - st.elapsed / c.tau).max(T::zero());
        }
        predicted + (T::one() - alpha) * d
    }
}

impl<T: Real> Estimator for Complementary<T> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        let (dt, gyro, mut flags) = match self.state.input.begin(s) {
            Step::BadTime => {
                return Estimate {
                    theta: self.state.theta,
                    flags: Flags::BAD_TIME_STEP,
                }
            }
            Step::First { flags, .. } => return self.start(s, flags),
            Step::Next { dt, gyro, flags } => (dt, gyro, flags),
        };
        let predicted = self.predict(gyro, dt, &mut flags);
        self.state.theta = match self.accel(s, dt) {
            Some(a) => self.blend(predicted, a, dt, &mut flags),
            None => {
                flags |= Flags::MEASUREMENT_SKIPPED;
                predicted
            }
        };
        let theta = &mut self.state.theta;
        if theta.abs() > T::pi() {
            *theta = theta.sin().atan2(theta.cos());
        }
        Estimate {
            theta: self.state.theta,
            flags,
        }
    }

    fn reset(&mut self) {
        self.state.reset(&self.coeffs);
    }

    /// Starts again on the next reading, keeping the steady offset (see the type's
    /// documentation).
    fn resume(&mut self) {
        let kept = self.state.offset.value().unwrap_or(self.state.kept);
        self.reset();
        self.state.kept = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(dt: f64, gyro: f64, angle: f64) -> Sample<f64> {
        Sample {
            dt,
            phi: f64::NAN,
            gyro,
            ax: 9.81 * angle.sin(),
            ay: 9.81 * angle.cos(),
        }
    }

    #[test]
    fn one_step_by_hand() {
        let mut c = Complementary::new(ComplementarySettings {
            time_constant: 0.99,
            accel_prefilter_hz: None,
        });
        let e0 = c.update(&sample(0.0, 0.0, 0.1));
        assert!((e0.theta - 0.1).abs() < 1e-15 && e0.flags.contains(Flags::INITIALISING));
        // Start-up: 0.01 s in, the time constant is 0.01 s, alpha = 0.5:
        // 0.5 (0.1 + 0.5 * 0.01) + 0.5 * 0.2 = 0.1525.
        let mut t = c.clone();
        let e1 = t.update(&sample(0.01, 0.5, 0.2));
        assert!((e1.theta - 0.1525).abs() < 1e-12, "{}", e1.theta);
        // 0.02 s in, gyro still: alpha = 2 / 3, the mean of the three readings so far.
        let e2 = t.update(&sample(0.01, 0.0, 0.2));
        assert!(
            (e2.theta - (2.0 * 0.1525 + 0.2) / 3.0).abs() < 1e-12,
            "{}",
            e2.theta
        );
        // Once 0.99 s in: dt = 0.01, alpha = 0.99: 0.99 (0.1 + 0.5 * 0.01) + 0.01 * 0.2.
        for _ in 0..99 {
            c.update(&sample(0.01, 0.0, 0.1));
        }
        let e = c.update(&sample(0.01, 0.5, 0.2));
        assert!((e.theta - 0.10595).abs() < 1e-12, "{}", e.theta);
    }

    #[test]
    fn converges_to_the_accelerometer_and_follows_the_gyro() {
        let mut c = Complementary::new(ComplementarySettings::<f64>::default());
        c.update(&sample(0.0, 0.0, 0.0));
        // Held at 0.3 rad with a still gyro: converges to 0.3 within a few tau.
        let mut e = c.update(&sample(1e-3, 0.0, 0.3));
        for _ in 2..20_000 {
            e = c.update(&sample(1e-3, 0.0, 0.3));
        }
        assert!((e.theta - 0.3).abs() < 1e-4, "{}", e.theta);
        // A fast rotation with the accelerometer lying: the gyro wins in the short term.
        for _ in 1..=100 {
            e = c.update(&sample(1e-3, 1.0, 0.3));
        }
        assert!((e.theta - 0.4).abs() < 0.01, "{}", e.theta);
    }

    #[test]
    fn missing_accel_integrates_the_gyro_and_bad_time_holds() {
        let mut c = Complementary::new(ComplementarySettings::<f64>::default());
        c.update(&sample(0.0, 0.0, 0.0));
        let mut s = sample(0.1, 2.0, 0.0);
        s.ax = f64::NAN;
        let e = c.update(&s);
        assert!(e.flags.contains(Flags::MEASUREMENT_SKIPPED));
        assert!((e.theta - 0.2).abs() < 1e-12);
        let e2 = c.update(&sample(f64::NAN, 0.0, 0.0));
        assert!(e2.flags.contains(Flags::BAD_TIME_STEP) && e2.theta == e.theta);
    }

    /// A gyro bias b holds the filter b tau above a still tilt. After a restart it starts
    /// there and stays there through its start-up (the offset kept); started afresh it
    /// starts on the accelerometer and builds the offset up over tau.
    #[test]
    fn a_restart_keeps_the_steady_offset_of_the_gyro_bias() {
        let (b, th, tau) = (0.01, 0.2, 0.75);
        let settings = ComplementarySettings {
            time_constant: tau,
            accel_prefilter_hz: None,
        };
        let mut c = Complementary::new(settings);
        let mut e = c.update(&sample(0.0, b, th));
        for _ in 0..20_000 {
            e = c.update(&sample(1e-3, b, th));
        }
        // Steady: theta = alpha (theta + b dt) + (1 - alpha) th, so theta - th = b tau.
        let steady = b * tau;
        assert!((e.theta - th - steady).abs() < 1e-9, "{}", e.theta - th);
        let mut fresh = c.clone();
        Estimator::resume(&mut c);
        Estimator::reset(&mut fresh);
        let mut worst: f64 = 0.0;
        for k in 0..3000 {
            let dt = if k == 0 { 0.0 } else { 1e-3 };
            let r = c.update(&sample(dt, b, th));
            worst = worst.max((r.theta - th - steady).abs());
            let f = fresh.update(&sample(dt, b, th));
            if k == 0 {
                assert_eq!(f.theta, th);
            }
        }
        // Within 2 % (the continuous-time construction, run at 1 ms steps).
        assert!(worst < 0.02 * steady, "{worst}");
    }

    /// The prefilter starts from one reading: the filter follows the prefiltered angle
    /// (flagged initialising) for its settling time, 4 sqrt(2) / (2 pi 5 Hz) = 0.18 s,
    /// before its running mean starts.
    #[test]
    fn the_mean_starts_once_the_prefilter_has_settled() {
        let mut c = Complementary::new(ComplementarySettings::<f64>::default());
        c.update(&sample(0.0, 0.0, 0.1));
        let mut k_settled = None;
        for k in 1..400 {
            let e = c.update(&sample(1e-3, 0.0, 0.1));
            if !e.flags.contains(Flags::INITIALISING) && k_settled.is_none() {
                k_settled = Some(k);
            }
        }
        // 180 steps of 1 ms, one more for the rounding of the sum.
        assert!(matches!(k_settled, Some(181..=182)), "{k_settled:?}");
    }

    #[test]
    fn overflowing_gyro_step_is_not_integrated() {
        let mut c = Complementary::<f32>::new(ComplementarySettings::default());
        let s = |dt: f32, gyro: f32| Sample {
            dt,
            phi: 0.0,
            gyro,
            ax: 0.0,
            ay: 9.8,
        };
        c.update(&s(0.0, 0.0));
        let e = c.update(&s(1e6, 3e38));
        assert!(
            e.theta.is_finite() && e.flags.contains(Flags::SATURATED),
            "{e:?}"
        );
        let e = c.update(&s(1.0, 0.0));
        assert!(e.theta.is_finite(), "{e:?}");
    }
}
