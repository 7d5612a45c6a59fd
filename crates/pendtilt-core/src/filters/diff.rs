//! Smoothing differentiators: a 4th-order low-pass whose states are the filtered signal and
//! its first three derivatives, so phi, phi' and phi'' come out of one filter, with one
//! delay, and no finite differences.
//!
//! # Why a smoothing differentiator, and the delay/noise trade-off
//! Algorithms 1-3 invert the pendulum's dynamics: `theta - phi ≈ a phi' + b phi''`. The
//! pendulum is a mechanical second-order low-pass (natural frequency `f_n`), and the
//! inversion undoes it, so any residual vibration in phi above `f_n` comes back amplified by
//! roughly `b (2 pi f)^2`: at 30 Hz with the default rig, 188 times. A raw second difference
//! of phi at 1 kHz is therefore useless under vibration. The differentiator low-passes phi
//! with cutoff `f_c` before differentiating:
//! - the higher `f_c`, the less delay (the DC group delay is `c1 / (c0 w_c)`, e.g. about
//!   `0.42 / f_c` seconds for the Butterworth response) but the more vibration gets through;
//! - the lower `f_c`, the smoother the estimate, and the more it lags the body.
//!
//! Because the pendulum itself attenuates vibration above `f_n`, the useful cutoff sits a
//! little above `f_n`. On simulated scooter rides (60 s, two seeds, engine harmonics and
//! broadband floor vibration; `cargo run --release -p pendtilt --example tuning_sweep`) the
//! Butterworth cutoff that minimised the RMS error was 1.0-1.3 `f_n` for Algorithms 1 and 2
//! (10 `f_n` was 3-5 times worse), while without vibration the error keeps falling as the
//! cutoff rises. The default, 1.3 `f_n` (2.8 Hz for the default rig, "near 3 Hz" as in
//! MODEL.md section 3), is the vibration optimum for the paper's scenario. It is therefore
//! [`Cutoff::TimesNatural`] rather than a fixed frequency: a stiffer pendulum gets a wider
//! filter.
//!
//! # Implementation
//! The filter is `H(s) = c0 / (s'^4 + c3 s'^3 + c2 s'^2 + c1 s' + c0)`, `s' = s / w_c`, in
//! companion form with states scaled by powers of `w_c` (well conditioned at any cutoff),
//! discretised exactly at each sample's actual time step with a first-order hold on the
//! input (`crate::linalg`); the matrices are recomputed only when the step changes.
use crate::linalg::{discretise, first_order_hold_inputs};
use crate::{PendulumParams, Real};
use nalgebra::{Matrix4, RowSVector, SMatrix, Vector4};

/// The shape of the 4th-order low-pass. All are normalised to -3 dB at the cutoff.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "snake_case")
)]
pub enum Response {
    /// Maximally flat magnitude: sharpest cut-off of the three, about 11 % step overshoot,
    /// DC delay `2.61 / w_c`.
    #[default]
    Butterworth,
    /// Maximally flat group delay: no ringing, the estimate is nearly the body tilt
    /// delayed by `2.11 / w_c`; softer cut-off.
    Bessel,
    /// Four equal real poles: no overshoot at all, DC delay `1.74 / w_c`, softest cut-off.
    CriticallyDamped,
}

impl Response {
    /// `[c0, c1, c2, c3]` of `s^4 + c3 s^3 + c2 s^2 + c1 s + c0`, -3 dB at `s = j`.
    pub fn coefficients(self) -> [f64; 4] {
        match self {
            // 2 (cos(pi/8) + cos(3 pi/8)), 2 + sqrt(2).
            Response::Butterworth => [
                1.0,
                2.613_125_929_752_753,
                3.414_213_562_373_095,
                2.613_125_929_752_753,
            ],
            // Bessel 105 / (s^4 + 10 s^3 + 45 s^2 + 105 s + 105), frequency-scaled by
            // 2.1139176749 to put -3 dB at 1 rad/s.
            Response::Bessel => [
                5.258_199_010_244_175,
                11.115_399_825_919_013,
                10.070_160_066_701_76,
                4.730_553_189_803_436_5,
            ],
            // (s + p)^4 with p = 1 / sqrt(2^(1/4) - 1).
            Response::CriticallyDamped => [
                27.933_481_823_911_53,
                48.601_961_352_677_67,
                31.711_281_047_297_48,
                9.195_836_891_013_887,
            ],
        }
    }

    /// DC group delay at cutoff `w_c` [rad/s]: `c1 / (c0 w_c)` seconds.
    pub fn dc_delay<T: Real>(self, w_c: T) -> T {
        let c = self.coefficients();
        T::lit(c[1] / c[0]) / w_c
    }
}

/// The differentiator's cutoff frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cutoff<T> {
    /// A fixed cutoff \[Hz\].
    Hz(T),
    /// A multiple of the pendulum's natural frequency `f_n = 1 / (2 pi sqrt(b))`.
    TimesNatural(T),
}

/// Settings of a [`SmoothingDifferentiator`] as the estimators take them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiffSettings<T> {
    /// Filter shape. Default [`Response::Butterworth`].
    pub response: Response,
    /// Cutoff. Default `TimesNatural(1.3)`: about 2.8 Hz for the default 2.19 Hz pendulum
    /// (see the module documentation for why).
    pub cutoff: Cutoff<T>,
}

impl<T: Real> Default for DiffSettings<T> {
    fn default() -> Self {
        Self {
            response: Response::Butterworth,
            cutoff: Cutoff::TimesNatural(T::lit(1.3)),
        }
    }
}

impl<T: Real> DiffSettings<T> {
    /// The cutoff in Hz for a pendulum with parameters `p`.
    pub fn cutoff_hz(&self, p: &PendulumParams<T>) -> T {
        match self.cutoff {
            Cutoff::Hz(f) => f,
            Cutoff::TimesNatural(k) => k * p.natural_frequency_hz(),
        }
    }
}

/// A filtered signal with its derivatives, all delayed alike by the low-pass.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Derivatives<T> {
    /// Low-passed signal.
    pub value: T,
    /// Its first time derivative [unit/s].
    pub d1: T,
    /// Its second time derivative [unit/s^2].
    pub d2: T,
}

/// A 4th-order low-pass with exact derivative outputs. See the module documentation.
///
/// `C` signals sampled at the same instants share one discretisation (the matrices depend
/// on the step only): Algorithms 2 and 3 run phi and the gyro through one `C = 2` filter,
/// so both carry the same delay and the step is checked once. `C = 1` (the default) has
/// the scalar API ([`Self::update`], [`Self::output`]).
#[derive(Debug, Clone)]
pub struct SmoothingDifferentiator<T: Real, const C: usize = 1> {
    w: T,
    a: Matrix4<T>,
    b: Vector4<T>,
    // Discretisation cached for `step`; the state matrix `m` is `E` (direct form) or
    // `E - I` (delta form), see `update_all`.
    step: T,
    m: Matrix4<T>,
    b0: Vector4<T>,
    b1: Vector4<T>,
    // One column per signal, z = [y, y'/w, y''/w^2, y'''/w^3]; and the previous inputs.
    z: SMatrix<T, 4, C>,
    u_prev: RowSVector<T, C>,
    started: bool,
}

/// A step is reused when it differs from the cached one by less than this fraction: the
/// filter's response changes by far less than its rounding.
const STEP_TOLERANCE: f64 = 1e-9;
/// ... or by less than this many ulps of the step itself: the rounding of a step computed
/// in `f64` and handed to an `f32` filter ([`crate::StepGate`]), not a new step.
const STEP_ULPS: f64 = 4.0;

impl<T: Real, const C: usize> SmoothingDifferentiator<T, C> {
    /// In a type coarser than 1e-10 (f32), the state advances in delta form,
    /// `z += (E - I) z + ...`, rather than `z = E z + ...`: E's diagonal is within w dt of
    /// 1, and rounded to f32 its poles move; `E - I` keeps its own precision. The same
    /// numbers in exact arithmetic; in f32 the derivatives come 3x closer to f64's (phi''
    /// 2e-5 -> 6e-6 relative), which the supervised Alg 3's refit needs over hours
    /// (docs/reliability.md section 6). f64 keeps the direct form: it gains nothing
    /// measurable there, and its outputs stay bit for bit those recorded (in f64 the delta
    /// form moved the planar estimators by 1.6e-15 rad, but ekf3d's maximum error on ship3d
    /// by 4.6e-8 rad).
    #[inline(always)]
    fn delta_form() -> bool {
        T::default_epsilon().to_f64() > 1e-10
    }

    /// A differentiator with the given response and cutoff \[Hz\]. A cutoff that is not
    /// finite and positive is replaced by 1 Hz (never a panic); check before if it matters.
    pub fn new(response: Response, cutoff_hz: T) -> Self {
        let f = if cutoff_hz.is_finite() && cutoff_hz > T::zero() {
            cutoff_hz
        } else {
            T::one()
        };
        let w = T::two_pi() * f;
        let c = response.coefficients();
        #[rustfmt::skip]
        let a = Matrix4::new(
            T::zero(), T::one(), T::zero(), T::zero(),
            T::zero(), T::zero(), T::one(), T::zero(),
            T::zero(), T::zero(), T::zero(), T::one(),
            T::lit(-c[0]), T::lit(-c[1]), T::lit(-c[2]), T::lit(-c[3]),
        ) * w;
        let b = Vector4::new(T::zero(), T::zero(), T::zero(), T::lit(c[0]) * w);
        Self {
            w,
            a,
            b,
            step: T::zero(),
            m: if Self::delta_form() {
                Matrix4::zeros()
            } else {
                Matrix4::identity()
            },
            b0: Vector4::zeros(),
            b1: Vector4::zeros(),
            z: SMatrix::zeros(),
            u_prev: RowSVector::zeros(),
            started: false,
        }
    }

    /// The cutoff [rad/s].
    pub fn cutoff_rad_s(&self) -> T {
        self.w
    }

    /// True once the filter has seen an input.
    pub fn is_started(&self) -> bool {
        self.started
    }

    /// Forgets the state.
    pub fn reset(&mut self) {
        self.started = false;
        self.z = SMatrix::zeros();
    }

    /// Starts (or restarts) every signal at rest on its input: values `u`, derivatives zero.
    pub fn start_all(&mut self, u: [T; C]) {
        for (i, &v) in u.iter().enumerate() {
            self.restart_signal(i, v);
        }
        self.started = true;
    }

    /// Restarts signal `i` alone at rest on `u` (a signal that begins later than the
    /// others). An index out of range is ignored.
    pub fn restart_signal(&mut self, i: usize, u: T) {
        if i < C {
            self.z
                .set_column(i, &Vector4::new(u, T::zero(), T::zero(), T::zero()));
            self.u_prev[i] = u;
        }
    }

    /// Advances every signal by `dt` seconds to the new inputs `u` (step changes within the
    /// rounding of `dt` reuse the cached discretisation). The first call starts at rest on
    /// `u`. Inputs must be finite
    /// and `dt > 0` (the estimators check both); a step that cannot be discretised leaves
    /// the state unchanged.
    #[inline]
    pub fn update_all(&mut self, u: [T; C], dt: T) {
        if !self.started {
            self.start_all(u);
            return;
        }
        let tol = T::lit(STEP_TOLERANCE).max(T::lit(STEP_ULPS) * T::default_epsilon()) * self.step;
        if (dt - self.step).abs() > tol && !self.rediscretise(dt) {
            return;
        }
        let u = RowSVector::from_row_slice(&u);
        if Self::delta_form() {
            self.z += self.m * self.z + self.b0 * self.u_prev + self.b1 * u;
        } else {
            self.z = self.m * self.z + self.b0 * self.u_prev + self.b1 * u;
        }
        self.u_prev = u;
    }

    /// The current outputs of signal `i` (zeros for an index out of range).
    #[inline]
    pub fn signal(&self, i: usize) -> Derivatives<T> {
        if i >= C {
            return Derivatives::default();
        }
        Derivatives {
            value: self.z[(0, i)],
            d1: self.z[(1, i)] * self.w,
            d2: self.z[(2, i)] * self.w * self.w,
        }
    }

    // Rare (the step changed): out of line, so the per-sample path stays small enough to
    // inline.
    #[cold]
    #[inline(never)]
    fn rediscretise(&mut self, dt: T) -> bool {
        match discretise(&self.a, dt) {
            Some(d) => {
                let (b0, b1) = first_order_hold_inputs(&d, &self.b, dt);
                // E = I + A F exactly (F the integral of e^{As}): E - I without the
                // cancellation of subtracting I.
                self.m = if Self::delta_form() {
                    self.a * d.f
                } else {
                    d.e
                };
                self.b0 = b0;
                self.b1 = b1;
                self.step = dt;
                true
            }
            None => false,
        }
    }
}

impl<T: Real> SmoothingDifferentiator<T, 1> {
    /// Starts (or restarts) at rest on `u`: value `u`, derivatives zero.
    pub fn start(&mut self, u: T) {
        self.start_all([u]);
    }

    /// Advances by `dt` seconds to the new input `u` and returns the outputs. The first call
    /// starts at rest on `u`. `u` must be finite and `dt > 0` (the estimators check both);
    /// a step that cannot be discretised leaves the state unchanged.
    #[inline]
    pub fn update(&mut self, u: T, dt: T) -> Derivatives<T> {
        self.update_all([u], dt);
        self.output()
    }

    /// The current outputs.
    #[inline]
    pub fn output(&self) -> Derivatives<T> {
        self.signal(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// |H(j w_c)| for the normalised polynomial.
    fn gain_at(resp: Response, w: f64) -> f64 {
        let c = resp.coefficients();
        // s = j w: s^2 = -w^2, s^3 = -j w^3, s^4 = w^4
        let re = w.powi(4) - c[2] * w * w + c[0];
        let im = -c[3] * w.powi(3) + c[1] * w;
        c[0] / (re * re + im * im).sqrt()
    }

    #[test]
    fn every_response_is_minus_3db_at_cutoff() {
        for r in [
            Response::Butterworth,
            Response::Bessel,
            Response::CriticallyDamped,
        ] {
            assert!((gain_at(r, 1.0) - 0.5f64.sqrt()).abs() < 1e-12, "{r:?}");
            assert!((gain_at(r, 1e-6) - 1.0).abs() < 1e-9, "{r:?}");
        }
    }

    /// Runs the filter on `x(t)` at `rate` for `secs` and returns the last outputs.
    fn run(
        d: &mut SmoothingDifferentiator<f64>,
        x: impl Fn(f64) -> f64,
        rate: f64,
        secs: f64,
    ) -> (f64, Derivatives<f64>) {
        let n = (secs * rate) as usize;
        let mut out = Derivatives::default();
        let mut t = 0.0;
        for k in 0..=n {
            t = k as f64 / rate;
            out = d.update(x(t), 1.0 / rate);
        }
        (t, out)
    }

    #[test]
    fn a_ramp_is_differentiated_exactly_after_the_delay() {
        // For u = v t the output settles to v (t - tau), tau = c1 / (c0 w): d1 = v, d2 = 0.
        for r in [
            Response::Butterworth,
            Response::Bessel,
            Response::CriticallyDamped,
        ] {
            let mut d = SmoothingDifferentiator::new(r, 3.0);
            let v = 0.2;
            let (t, out) = run(&mut d, |t| v * t, 1000.0, 10.0);
            let tau = r.dc_delay(2.0 * core::f64::consts::PI * 3.0);
            assert!((out.d1 - v).abs() < 1e-9, "{r:?} d1 {}", out.d1);
            assert!(out.d2.abs() < 1e-8, "{r:?} d2 {}", out.d2);
            assert!((out.value - v * (t - tau)).abs() < 1e-9, "{r:?}");
        }
    }

    #[test]
    fn a_parabola_gives_its_second_derivative() {
        // u = q t^2: d2 → 2 q exactly once transients die (polynomial input of degree 2).
        let mut d = SmoothingDifferentiator::new(Response::Butterworth, 4.0);
        let q = 0.3;
        let (_, out) = run(&mut d, |t| q * t * t, 500.0, 8.0);
        assert!((out.d2 - 2.0 * q).abs() < 1e-7, "d2 {}", out.d2);
    }

    #[test]
    fn a_slow_sine_is_differentiated_and_fast_vibration_is_rejected() {
        let w0 = 2.0 * core::f64::consts::PI * 0.2; // 0.2 Hz motion, well below 5 Hz cutoff
        let mut d = SmoothingDifferentiator::new(Response::Butterworth, 5.0);
        let tau = Response::Butterworth.dc_delay(2.0 * core::f64::consts::PI * 5.0);
        let rate = 1000.0;
        let mut worst: f64 = 0.0;
        for k in 0..20_000 {
            let t = k as f64 / rate;
            // Slow motion plus 40 Hz vibration of equal amplitude.
            let u = (w0 * t).sin() + (2.0 * core::f64::consts::PI * 40.0 * t).sin();
            let o = d.update(u, 1.0 / rate);
            if t > 5.0 {
                let want = w0 * w0 * -(w0 * (t - tau)).sin();
                worst = worst.max((o.d2 - want).abs());
            }
        }
        // 40 Hz seen through a 4th-order 5 Hz low-pass is attenuated by (40/5)^4 = 4096,
        // then differentiated twice ((2 pi 40)^2 = 63165): residual ~15, vs the raw 63165.
        // The slow part's own phase error (delay is not exactly constant) is ~1e-4.
        assert!(worst < 20.0, "worst {worst}");
    }

    #[test]
    fn jittered_steps_give_the_same_result_as_uniform_ones_on_a_ramp() {
        let mut d = SmoothingDifferentiator::<f64>::new(Response::Bessel, 3.0);
        let mut t = 0.0;
        let mut out = Derivatives::default();
        for k in 0..20_000 {
            let dt = if k % 3 == 0 { 0.0013 } else { 0.0008 };
            t += dt;
            out = d.update(0.5 * t, dt);
        }
        assert!((out.d1 - 0.5).abs() < 1e-9);
    }

    #[test]
    fn f32_tracks_f64() {
        let mut d64 = SmoothingDifferentiator::<f64>::new(Response::Butterworth, 3.5);
        let mut d32 = SmoothingDifferentiator::<f32>::new(Response::Butterworth, 3.5);
        let mut worst: f64 = 0.0;
        for k in 0..5000 {
            let t = k as f64 * 1e-3;
            let u: f64 = 0.2 * (3.0 * t).sin();
            let a = d64.update(u, 1e-3);
            let b = d32.update(u as f32, 1e-3);
            worst = worst.max((a.d2 - b.d2 as f64).abs());
        }
        assert!(worst < 1e-3, "worst {worst}");
    }

    #[test]
    fn two_signals_match_two_single_filters_and_a_late_signal_starts_at_rest() {
        let mut pair = SmoothingDifferentiator::<f64, 2>::new(Response::Butterworth, 3.0);
        let mut a = SmoothingDifferentiator::<f64>::new(Response::Butterworth, 3.0);
        let mut b = SmoothingDifferentiator::<f64>::new(Response::Butterworth, 3.0);
        let mut t = 0.0f64;
        for k in 0..3000 {
            let dt = if k % 5 == 0 { 1.2e-3 } else { 1e-3 };
            t += dt;
            let (u, v) = ((2.0 * t).sin(), 0.3 * t * t);
            if k == 0 {
                // Signal 1 has no input yet: it joins later.
                pair.update_all([u, 0.0], dt);
                a.update(u, dt);
                continue;
            }
            if k == 1 {
                pair.restart_signal(1, v);
                b.start(v);
            }
            pair.update_all([u, v], dt);
            let (x, y) = (a.update(u, dt), b.update(v, dt));
            assert!((pair.signal(0).d2 - x.d2).abs() < 1e-9, "k {k}");
            assert!((pair.signal(1).d1 - y.d1).abs() < 1e-9, "k {k}");
            assert!((pair.signal(1).value - y.value).abs() < 1e-12, "k {k}");
        }
        // Late start at rest: no step transient, so the parabola's d2 is 0.6 at the end.
        assert!((pair.signal(1).d2 - 0.6).abs() < 1e-6);
        assert_eq!(pair.signal(2), Derivatives::default());
    }
}
