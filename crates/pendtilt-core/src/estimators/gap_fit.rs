//! The angle a rate turned through a gap in its readings, fitted to the readings on both
//! sides (used by [`super::input_hold::GapBridge`]).
//!
//! The fit is made on the *integrated* rate, the angle `A(t)`, not on the rate: a body's
//! angular vibration is a large oscillation of the rate but a small one of the angle (a
//! 31.5 Hz engine's 2.4 deg/s is 0.012 deg), so a smooth curve through the angle on either
//! side of the gap averages it out, where the means of the rate keep a part of it. The
//! angle is known on each side only up to its own constant (`A` is zero at the last reading
//! before the gap and again, in its own count, at the end of the gap): the fit is a cubic
//! `p(t)` through both sides with the unknown jump `D` between the two counts, by least
//! squares with weights `exp(-|t - edge| / FIT_TAU)` falling away from the gap on each side,
//!
//! ```text
//! before (t <= 0):   A(t)     = p(t)
//! after  (t >= L):   A_L(t)   = p(t) - D,        D = the angle turned through the gap
//! ```
//!
//! The cubic follows the manoeuvre (a rate that curves through the gap), the weights'
//! window averages the vibration, and whatever part of the vibration's angle falls at the
//! gap's two edges is read off the fit's residuals there, so `D` includes it.
//!
//! Measured on 100 missing readings (1 kHz) at 41 positions of the simulated scooter3d
//! rides (seeds 1-3, gyro_x and gyro_y, 246 gaps): the angle through the gap was off by
//! 0.0124 deg RMS (at most 0.037) with this fit, 0.0433 deg (at most 0.106) with the line
//! between the 25 ms means of the rate on either side; on the planar scooter ride (seeds
//! 1, 3, 6, 123 gaps), whose 40 Hz vibration is 20 times stronger and whose manoeuvres are
//! faster, 0.084 deg (at most 0.29) against 0.083 (0.27): so strong a tone is in part
//! followed by the cubic (on a pure 40 Hz tone of 0.25 rad/s the line does better, 0.7
//! against 1.2 mrad at worst).
//!
//! All sums are kept as moments (`sum w u^k`, `sum w A u^k`, `u = t / FIT_TAU`), so the
//! fit needs no storage of readings: before a gap they are carried about the latest reading,
//! after it about the gap's end.
use crate::Real;
use nalgebra::{Matrix5, Vector5};

/// Time constant \[s\] of the fit's weights on either side of a gap. Over 0.025, 0.030 and
/// 0.035 s on the rides above: 0.0178, 0.0137 and 0.0124 deg RMS on scooter3d, 0.114,
/// 0.091 and 0.084 on the planar scooter; 0.04 and 0.05 s with windows of 9 and 5
/// constants gave 0.0117 and 0.0100 on scooter3d but 0.081 and 0.069 only when both sides
/// were cut at the same length, which the recursive sum before a gap cannot do.
pub const FIT_TAU: f64 = 0.035;

/// How long \[s\] after a gap its readings are taken into the fit: 12 [`FIT_TAU`], by
/// which their weights are 6e-6 and the fit's cubic moments (`u^6 exp(-u)`) have all but
/// 2 % of the weight they have on the endless side before the gap (a shorter window,
/// unlike the other side's, biased the fit: 0.0180 deg RMS at 6 constants).
pub const FIT_WINDOW: f64 = 12.0 * FIT_TAU;

/// The weight \[in units of `FIT_TAU`\] of readings before a gap the fit needs: 4
/// constants' worth (`1 - exp(-4)`). With less (a gap soon after the start or after
/// another gap) the cubic is poorly held on that side and the caller takes its simpler rule.
pub const FIT_MIN_BEFORE: f64 = 0.98;

/// Binomial coefficients up to 6.
const BINOMIAL: [[f64; 7]; 7] = [
    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 3.0, 3.0, 1.0, 0.0, 0.0, 0.0],
    [1.0, 4.0, 6.0, 4.0, 1.0, 0.0, 0.0],
    [1.0, 5.0, 10.0, 10.0, 5.0, 1.0, 0.0],
    [1.0, 6.0, 15.0, 20.0, 15.0, 6.0, 1.0],
];

/// `sum_j C(k, j) s^(k - j) m_j` for every `k`: the moments `m_k = sum w u^k` about a point
/// moved to `u - s`.
fn shifted<T: Real, const N: usize>(m: &[T; N], s: T) -> [T; N] {
    core::array::from_fn(|k| {
        let mut sum = T::zero();
        let mut power = T::one();
        for j in (0..=k).rev() {
            sum += T::lit(BINOMIAL[k][j]) * power * m[j];
            power *= s;
        }
        sum
    })
}

/// The readings before a gap, as moments about the latest one: `m_k = sum w u^k` (u <= 0,
/// in [`FIT_TAU`]s from the latest) and `n_k = sum w a u^k` (a: the angle \[rad\] from the
/// latest), `w = exp(u) du`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Trail<T> {
    m: [T; 7],
    n: [T; 4],
}

impl<T: Real> Trail<T> {
    /// No readings.
    pub(crate) fn new() -> Self {
        Self {
            m: [T::zero(); 7],
            n: [T::zero(); 4],
        }
    }

    /// A reading `g` \[rad/s\] after a step of `dt` \[s\]: every earlier one moves `dt`
    /// back in time and `g dt` back in angle, and weighs `exp(-dt / FIT_TAU)` less.
    pub(crate) fn push(&mut self, g: T, dt: T) {
        let du = dt / T::lit(FIT_TAU);
        let decay = (-du).exp();
        let turned = g * dt;
        let m = shifted(&self.m, -du);
        // n_k about the new point: sum w (a - g dt) (u - du)^k.
        let n0: [T; 4] = core::array::from_fn(|k| self.n[k] - turned * self.m[k]);
        let n = shifted(&n0, -du);
        self.m = m.map(|x| x * decay);
        self.n = n.map(|x| x * decay);
        self.m[0] += du;
        if !self.m.iter().chain(&self.n).all(|x| x.is_finite()) {
            *self = Self::new();
        }
    }

    /// The weight held, in [`FIT_TAU`]s (1 for an endless history).
    pub(crate) fn weight(&self) -> T {
        self.m[0]
    }
}

/// The readings after a gap, as moments about its end: `p_k = sum w u^k` (u >= 0, in
/// [`FIT_TAU`]s from the gap's end), `q_k = sum w a u^k` (a: the angle \[rad\] turned since
/// the gap's end), `w = exp(-u) du`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tail<T> {
    p: [T; 7],
    q: [T; 4],
    /// The angle turned since the gap's end \[rad\] and the time since it \[s\].
    angle: T,
    since: T,
}

impl<T: Real> Tail<T> {
    /// No readings.
    pub(crate) fn new() -> Self {
        Self {
            p: [T::zero(); 7],
            q: [T::zero(); 4],
            angle: T::zero(),
            since: T::zero(),
        }
    }

    /// A reading `g` \[rad/s\] after a step of `dt` \[s\]. The first one also puts in the
    /// gap's end (angle zero) with the same weight.
    pub(crate) fn push(&mut self, g: T, dt: T) {
        let du = dt / T::lit(FIT_TAU);
        if self.since == T::zero() {
            self.p[0] += du;
        }
        self.since += dt;
        self.angle += g * dt;
        let u = self.since / T::lit(FIT_TAU);
        let w = (-u).exp() * du;
        let mut power = w;
        for k in 0..7 {
            self.p[k] += power;
            if k < 4 {
                self.q[k] += power * self.angle;
            }
            power *= u;
        }
    }

    /// Time since the gap's end \[s\].
    pub(crate) fn since(&self) -> T {
        self.since
    }
}

/// The angle \[rad\] turned through a gap of `length` \[s\] between the readings of
/// `before` and `after` (the module's fit), computed in f64 whatever `T`; `None` if the
/// fit is singular or not finite.
pub(crate) fn turned_through<T: Real>(
    before: &Trail<T>,
    after: &Tail<T>,
    length: T,
) -> Option<f64> {
    let m = before.m.map(T::to_f64);
    let n = before.n.map(T::to_f64);
    // The after side's moments about the gap's start, where the before side's are.
    let lambda = length.to_f64() / FIT_TAU;
    let s = shifted(&after.p.map(T::to_f64), lambda);
    let r = shifted(&after.q.map(T::to_f64), lambda);
    // Unknowns: the cubic's c_0..c_3 and D; the after side's rows are p(t) - D = A_L(t).
    let a = Matrix5::from_fn(|i, j| match (i, j) {
        (4, 4) => s[0],
        (4, j) => -s[j],
        (i, 4) => -s[i],
        (i, j) => m[i + j] + s[i + j],
    });
    let b = Vector5::from_fn(|i, _| if i == 4 { -r[0] } else { n[i] + r[i] });
    let x = a.lu().solve(&b)?;
    let d = x[4];
    d.is_finite().then_some(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The angle through a gap of a rate known in closed form, from readings at `rate` Hz
    /// on both sides; the gap from `t0` for `length` s.
    fn fit<T: Real>(g: impl Fn(f64) -> f64, t0: f64, length: f64, hz: f64) -> (f64, f64) {
        let dt = 1.0 / hz;
        let mut trail = Trail::<T>::new();
        let mut t = 0.0;
        while t + dt <= t0 + 1e-12 {
            t += dt;
            trail.push(T::lit(g(t)), T::lit(dt));
        }
        let start = t;
        let mut truth = 0.0;
        while t + dt <= start + length + 1e-12 {
            t += dt;
            truth += g(t) * dt;
        }
        let gap = t - start;
        let mut tail = Tail::<T>::new();
        while tail.since().to_f64() < FIT_WINDOW {
            t += dt;
            tail.push(T::lit(g(t)), T::lit(dt));
        }
        (turned_through(&trail, &tail, T::lit(gap)).unwrap(), truth)
    }

    #[test]
    fn a_rate_that_is_a_quadratic_in_time_is_integrated_exactly() {
        // The cubic angle holds it whatever the weights: the fit is exact.
        let g = |t: f64| 0.3 - 1.5 * (t - 1.0) + 4.0 * (t - 1.0) * (t - 1.0);
        let (d, truth) = fit::<f64>(g, 1.0, 0.1, 1000.0);
        // Sampled: the readings integrate the rate by right sums, as an estimator does.
        assert!((d - truth).abs() < 1e-9, "{d} against {truth}");
        let (d, truth) = fit::<f64>(g, 1.0, 0.25, 200.0);
        assert!((d - truth).abs() < 1e-9, "{d} against {truth}");
    }

    /// The line between the 25 ms means of the rate on either side of the gap (the rule
    /// the fit replaced), for comparison.
    fn line(g: impl Fn(f64) -> f64, t0: f64, length: f64, dt: f64) -> f64 {
        let tau = 0.025;
        let mut before = g(dt);
        let mut t = dt;
        while t + dt <= t0 + 1e-12 {
            t += dt;
            before += (dt / tau) * (g(t) - before);
        }
        let end = t + length;
        let (mut sum, mut weight, mut since) = (0.0, 0.0, 0.0);
        t = end;
        while since < 4.0 * tau {
            t += dt;
            let w = (-(since + dt / 2.0) / tau).exp() * dt;
            sum += w * g(t);
            weight += w;
            since += dt;
        }
        length * (before + sum / weight) / 2.0
    }

    #[test]
    fn a_manoeuvre_under_engine_vibration_is_bridged_closer_than_by_the_line() {
        // A roll of 0.3 rad/s at 0.9 Hz (the scooter3d ride's fastest), under an engine's
        // 31.5 Hz and 63 Hz of 0.041 rad/s each (its angular vibration, 0.012 deg).
        let w = 2.0 * core::f64::consts::PI * 31.5;
        let g = |t: f64| {
            0.3 * (2.0 * core::f64::consts::PI * 0.9 * t).sin()
                + 0.041 * (w * t).cos()
                + 0.041 * (2.0 * w * t + 1.0).cos()
        };
        let (mut fit_worst, mut line_worst) = (0.0f64, 0.0f64);
        for k in 0..20 {
            let t0 = 1.5 + 0.037 * k as f64;
            let (d, truth) = fit::<f64>(g, t0, 0.1, 1000.0);
            fit_worst = fit_worst.max((d - truth).abs());
            line_worst = line_worst.max((line(g, t0, 0.1, 1e-3) - truth).abs());
        }
        // Measured 1.2 and 2.8 mrad: the cubic keeps the curve the line cuts.
        assert!(fit_worst < 1.5e-3, "{fit_worst} rad");
        assert!(
            fit_worst < 0.6 * line_worst,
            "{fit_worst} against {line_worst} rad"
        );
    }

    #[test]
    fn f32_moments_give_the_f64_fit() {
        let w = 2.0 * core::f64::consts::PI * 31.5;
        let g = |t: f64| 0.2 * (0.9 * t).sin() + 0.04 * (w * t).cos();
        let (d64, truth) = fit::<f64>(g, 30.0, 0.1, 1000.0);
        let (d32, _) = fit::<f32>(g, 30.0, 0.1, 1000.0);
        assert!((d64 - truth).abs() < 1e-3, "{d64} {truth}");
        // 30 s of f32 steps: the moments' rounding moves the fit by far less than it misses.
        assert!((d32 - d64).abs() < 1e-5, "{d32} against {d64}");
    }

    #[test]
    fn the_trail_forgets_at_fit_tau_and_holds_one_constant_of_weight() {
        let mut trail = Trail::<f64>::new();
        for _ in 0..2000 {
            trail.push(0.1, 1e-3);
        }
        // sum exp(-k du) du over an endless history: du / (1 - exp(-du)), 1 + du / 2.
        let du = 1e-3 / FIT_TAU;
        assert!((trail.weight() - du / (1.0 - (-du).exp())).abs() < 1e-9);
        // A reading that is not finite does not poison it: it starts again.
        trail.push(f64::INFINITY, 1e-3);
        assert_eq!(trail.weight(), 0.0);
    }
}
