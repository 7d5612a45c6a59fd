//! The paper's estimation equations (MODEL.md section 3): as pure functions, and as values
//! ([`Equation`]) evaluated on what the front end hands them ([`Kinematics`], from
//! [`super::front_end`]).
//!
//! Sign: the paper prints `phi - asin(...)` in Eqs (20), (21), (30); solving its own
//! Eq (18), `C phi' + I (phi'' - theta'') + m g l sin(phi - theta) = 0`, for theta gives
//! `theta = phi + asin(a phi' + b (phi'' - theta''))`. These functions use the plus sign.
use super::encoder::wrap_angle;
use crate::{Flags, PendulumParams, Real};

/// An inverted angle and whether its asin argument had to be clamped to [-1, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inversion<T> {
    /// Estimated body tilt theta \[rad\].
    pub theta: T,
    /// True when the asin argument left [-1, 1] and was clamped.
    pub clamped: bool,
}

/// `asin(x)` with `x` clamped to [-1, 1]; the flag tells whether it was.
#[inline]
pub(crate) fn clamped_asin<T: Real>(x: T) -> (T, bool) {
    let one = T::one();
    if x > one {
        (T::frac_pi_2(), true)
    } else if x < -one {
        (-T::frac_pi_2(), true)
    } else if x.is_finite() {
        (x.asin(), false)
    } else {
        (T::zero(), true)
    }
}

/// Eq (1): tilt from the accelerometer, `theta = atan2(ax, ay)`.
#[inline]
pub fn accel_angle<T: Real>(ax: T, ay: T) -> T {
    ax.atan2(ay)
}

/// Eq (20), Algorithm 1: `theta = phi + asin(a phi' + b phi'')` (theta'' neglected).
#[inline]
pub fn alg1<T: Real>(p: &PendulumParams<T>, phi: T, dphi: T, ddphi: T) -> Inversion<T> {
    let (s, clamped) = clamped_asin(p.a * dphi + p.b * ddphi);
    Inversion {
        theta: phi + s,
        clamped,
    }
}

/// Eq (21), Algorithm 2: `theta = phi + asin(a phi' + b (phi'' - theta''))`, with theta''
/// from the gyro (Eq 22's `G_d`, or the matched differentiator).
#[inline]
pub fn alg2<T: Real>(
    p: &PendulumParams<T>,
    phi: T,
    dphi: T,
    ddphi: T,
    theta_dd: T,
) -> Inversion<T> {
    let (s, clamped) = clamped_asin(p.a * dphi + p.b * (ddphi - theta_dd));
    Inversion {
        theta: phi + s,
        clamped,
    }
}

/// Algorithm 2 with the pivot-offset term the paper dropped (MODEL.md sections 2-3):
/// `theta = phi + asin(a phi' + b (phi'' - theta'') + c (theta'' cos phi - theta'^2 sin phi))`,
/// `c = l12 / g`. With `c = 0` it is [`alg2`].
#[inline]
pub fn alg2_offset<T: Real>(
    p: &PendulumParams<T>,
    phi: T,
    dphi: T,
    ddphi: T,
    theta_d: T,
    theta_dd: T,
) -> Inversion<T> {
    let offset = p.c * (theta_dd * phi.cos() - theta_d * theta_d * phi.sin());
    let (s, clamped) = clamped_asin(p.a * dphi + p.b * (ddphi - theta_dd) + offset);
    Inversion {
        theta: phi + s,
        clamped,
    }
}

/// The four parameters of Eq (30), normalised like a and b (divided by m g l).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alg3Gains<T> {
    /// K, multiplies phi' \[s\].
    pub k: T,
    /// L, multiplies phi'' [s^2].
    pub l: T,
    /// M, multiplies G_d (theta'') [s^2].
    pub m: T,
    /// N, multiplies the raw gyro G_k \[s\]: a delay compensation outside the asin.
    pub n: T,
}

impl<T: Real> Alg3Gains<T> {
    /// The gains under which Eq (30) is Eq (21): K = a, L = b, M = -b, N = 0.
    pub fn from_params(p: &PendulumParams<T>) -> Self {
        Self {
            k: p.a,
            l: p.b,
            m: -p.b,
            n: T::zero(),
        }
    }

    /// True when all four are finite.
    pub fn is_finite(&self) -> bool {
        self.k.is_finite() && self.l.is_finite() && self.m.is_finite() && self.n.is_finite()
    }
}

/// Eq (30), Algorithm 3: `theta = phi + asin(K phi' + L phi'' + M G_d) + N G_k`.
#[inline]
pub fn alg3<T: Real>(g: &Alg3Gains<T>, phi: T, dphi: T, ddphi: T, gd: T, gk: T) -> Inversion<T> {
    let (s, clamped) = clamped_asin(g.k * dphi + g.l * ddphi + g.m * gd);
    Inversion {
        theta: phi + s + g.n * gk,
        clamped,
    }
}

/// Eq (22): `G_d = (G_k - G_{k-w}) / (t_k - t_{k-w})`, the paper's windowed gyro derivative
/// (the paper writes the denominator `w dt`; the time difference is the same for uniform
/// sampling and stays right under jitter). Returns 0 when the times coincide.
#[inline]
pub(crate) fn windowed_rate<T: Real>(g_now: T, t_now: T, g_old: T, t_old: T) -> T {
    let span = t_now - t_old;
    if span > T::zero() {
        (g_now - g_old) / span
    } else {
        T::zero()
    }
}

/// What the front end hands an inversion equation for one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics<T> {
    /// The phi that enters `theta = phi + asin(...)` ([`PhiSource`](super::front_end::PhiSource)) \[rad\].
    pub phi: T,
    /// phi' through the differentiator [rad/s].
    pub dphi: T,
    /// phi'' through the differentiator [rad/s^2].
    pub ddphi: T,
    /// Gyro rate (last good one if missing), theta' [rad/s].
    pub gyro: T,
    /// theta'' [rad/s^2] from the gyro source (0 without a gyro).
    pub theta_dd: T,
    /// The gyro through the phi low-pass (0 without a gyro) [rad/s].
    pub gyro_filtered: T,
    /// DC delay of the phi low-pass \[s\].
    pub delay: T,
    /// Time since the previous accepted sample \[s\] (0 on the first).
    pub dt: T,
    /// Flags of the gyro path alone (missing gyro sample, Eq (22) window filling): the
    /// algorithms that read the gyro add them, Algorithm 1 does not.
    pub gyro_flags: Flags,
}

/// One inversion equation of the paper (or a variant), evaluated on the front end's
/// [`Kinematics`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Equation<T> {
    /// Eq (20), Algorithm 1: `phi + asin(a phi' + b phi'')`.
    Alg1(PendulumParams<T>),
    /// Eq (21), Algorithm 2: `phi + asin(a phi' + b (phi'' - theta''))`, optionally with the
    /// pivot-offset term and the delay compensation (see
    /// [`super::alg2::Alg2Settings`]).
    Alg2 {
        /// a, b (and c with `pivot_offset`).
        params: PendulumParams<T>,
        /// Add the pivot-offset term (output `alg2_offset`).
        pivot_offset: bool,
        /// Remove the differentiator's first-order delay with the gyro (`alg2_dc`).
        delay_compensation: bool,
    },
    /// Eq (30), Algorithm 3: `phi + asin(K phi' + L phi'' + M G_d) + N G_k`.
    Alg3(Alg3Gains<T>),
}

impl<T: Real> Equation<T> {
    /// True when the equation reads the gyro (its flags then include the gyro's).
    pub fn reads_gyro(&self) -> bool {
        !matches!(self, Equation::Alg1(_))
    }

    /// The unwrapped estimate for one sample's kinematics.
    // Always inlined: the stand-alone estimators pass a known variant, and the match then
    // folds away (measured: out of line it was a fifth of Algorithm 2's per-sample time).
    #[inline(always)]
    pub fn evaluate(&self, k: &Kinematics<T>) -> Inversion<T> {
        match self {
            Equation::Alg1(p) => alg1(p, k.phi, k.dphi, k.ddphi),
            Equation::Alg2 {
                params: p,
                pivot_offset,
                delay_compensation,
            } => {
                let mut r = if *pivot_offset {
                    alg2_offset(p, k.phi, k.dphi, k.ddphi, k.gyro, k.theta_dd)
                } else {
                    alg2(p, k.phi, k.dphi, k.ddphi, k.theta_dd)
                };
                if *delay_compensation {
                    r.theta -= k.delay * (k.dphi - k.gyro_filtered);
                }
                r
            }
            Equation::Alg3(g) => alg3(g, k.phi, k.dphi, k.ddphi, k.theta_dd, k.gyro),
        }
    }

    /// The estimate and its flags for one sample, from the front end's output.
    #[inline(always)]
    pub(crate) fn estimate(&self, k: &Kinematics<T>, phi_flags: Flags) -> (T, Flags) {
        let r = self.evaluate(k);
        let mut flags = phi_flags;
        if self.reads_gyro() {
            flags |= k.gyro_flags;
        }
        if r.clamped {
            flags |= Flags::ASIN_CLAMPED;
        }
        (wrap_angle(r.theta), flags)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> PendulumParams<f64> {
        PendulumParams {
            a: 0.04,
            b: 0.005,
            c: 0.01,
        }
    }

    #[test]
    fn accel_angle_eq1_hand_values() {
        let g = 9.81;
        let th: f64 = 0.3;
        assert!((accel_angle(g * th.sin(), g * th.cos()) - 0.3).abs() < 1e-15);
        assert!((accel_angle(1.0, 0.0) - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn alg1_eq20_hand_value() {
        // a phi' + b phi'' = 0.04 * 0.5 + 0.005 * 2 = 0.03; asin(0.03) = 0.030004501823476935
        let r = alg1(&p(), 0.1, 0.5, 2.0);
        assert!((r.theta - (0.1 + 0.030_004_501_823_476_935)).abs() < 1e-15);
        assert!(!r.clamped);
    }

    #[test]
    fn alg2_eq21_hand_value_and_reduces_to_alg1() {
        // 0.04 * 0.5 + 0.005 * (2 - 4) = 0.01; asin(0.01) = 0.010000166674167
        let r = alg2(&p(), -0.2, 0.5, 2.0, 4.0);
        assert!((r.theta - (-0.2 + 0.010_000_166_674_167_1)).abs() < 1e-15);
        assert_eq!(alg2(&p(), 0.3, 0.1, 0.2, 0.0), alg1(&p(), 0.3, 0.1, 0.2));
    }

    #[test]
    fn alg2_offset_hand_value_and_reduces_to_alg2() {
        // extra c (theta'' cos phi - theta'^2 sin phi) = 0.01 (4 cos 0.5 - 9 sin 0.5)
        let phi: f64 = 0.5;
        let extra = 0.01 * (4.0 * phi.cos() - 9.0 * phi.sin());
        let base = 0.04 * 0.5 + 0.005 * (2.0 - 4.0);
        let r = alg2_offset(&p(), phi, 0.5, 2.0, 3.0, 4.0);
        assert!((r.theta - (phi + (base + extra).asin())).abs() < 1e-15);
        let mut p0 = p();
        p0.c = 0.0;
        let a = alg2_offset(&p0, phi, 0.5, 2.0, 3.0, 4.0);
        assert!((a.theta - alg2(&p0, phi, 0.5, 2.0, 4.0).theta).abs() < 1e-15);
    }

    #[test]
    fn alg3_equals_alg2_with_matching_gains() {
        let g = Alg3Gains::from_params(&p());
        for &(phi, d, dd, gd) in &[(0.1, 0.3, -1.0, 2.0), (-0.4, -2.0, 5.0, -3.0)] {
            let a3 = alg3(&g, phi, d, dd, gd, 7.0);
            let a2 = alg2(&p(), phi, d, dd, gd);
            assert!((a3.theta - a2.theta).abs() < 1e-15);
        }
        // N adds N G_k outside the asin.
        let mut g2 = g;
        g2.n = 0.01;
        let d =
            alg3(&g2, 0.1, 0.3, -1.0, 2.0, 3.0).theta - alg3(&g, 0.1, 0.3, -1.0, 2.0, 3.0).theta;
        assert!((d - 0.03).abs() < 1e-15);
    }

    #[test]
    fn asin_argument_is_clamped_and_flagged() {
        let r = alg1(&p(), 0.0, 100.0, 0.0); // argument 4
        assert!(r.clamped);
        assert!((r.theta - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let r = alg1(&p(), 0.0, -100.0, 0.0);
        assert!(r.clamped && (r.theta + core::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let (v, c) = clamped_asin(f64::NAN);
        assert!(c && v == 0.0);
    }

    #[test]
    fn windowed_rate_eq22() {
        // (G_k - G_{k-w}) / (w dt) with w = 10, dt = 1 ms: (0.5 - 0.3) / 0.01 = 20
        assert!((windowed_rate(0.5f64, 1.010, 0.3, 1.000) - 20.0).abs() < 1e-9);
        assert_eq!(windowed_rate(0.5f64, 1.0, 0.3, 1.0), 0.0);
    }
}
