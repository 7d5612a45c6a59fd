//! The paper's Newton's method, Eqs (24)-(28), with the finite-difference gradient and
//! Hessian written out in MODEL.md section 3:
//!
//! ```text
//! P_n = P_{n-1} - h F'(P) (F''(P))^-1                                   (24)
//! F'_j  = (F(P + dP_j) - F(P)) / dp                                     (25)
//! F''_jk = (F(P + dP_j + dP_k) - F(P + dP_j) - F(P + dP_k) + F(P)) / dp^2  (26)-(28)
//! ```
//!
//! One call of [`newton_iteration`] is one iteration: `1 + n + n (n + 1) / 2` cost
//! evaluations for the derivatives (6 for a, b; 15 for K, L, M, N), then the step.
//! Two safeguards the paper does not spell out, both logged in [`NewtonIteration`]:
//! - when the finite-difference Hessian is not positive definite (far from the minimum,
//!   or on a flat cost), a multiple of the identity scaled to its diagonal is added until
//!   it is ([`NewtonIteration::shift`]);
//! - when the full step `h` does not lower the cost, it is halved up to
//!   [`NewtonSettings::max_halvings`] times ([`NewtonIteration::step_scale`]). This
//!   matters for the RMS cost of Eqs (23)/(29): far from its minimum the RMS is close to a
//!   cone, whose curvature along the radial direction is small, so the raw Newton step
//!   overshoots.
//!
//! Everything is on the stack (nalgebra fixed-size matrices): it runs in the `no_std` core.
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// Settings of Newton's method (Eqs 24-28). All are user settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings<T> {
    /// The step factor h of Eq (24). Default 1 (the full Newton step).
    pub h: T,
    /// The finite difference dp of Eqs (25)-(28), absolute, in the parameters' units.
    /// Default 1e-6 (for f64; with f32 use about 1e-3 of the parameters' size).
    pub dp: T,
    /// Stop when the cost changes by less than `ftol` times itself. Default 1e-10.
    pub ftol: T,
    /// Stop when every parameter changes by less than `xtol` times its size (plus `xtol`
    /// times dp). Default 1e-8.
    pub xtol: T,
    /// Iteration limit. Default 100.
    pub max_iterations: usize,
    /// Step halvings tried when the step `h` does not lower the cost. Default 40.
    pub max_halvings: usize,
}

impl<T: Real> Default for NewtonSettings<T> {
    fn default() -> Self {
        Self {
            h: T::one(),
            dp: T::lit(1e-6),
            ftol: T::lit(1e-10),
            xtol: T::lit(1e-8),
            max_iterations: 100,
            max_halvings: 40,
        }
    }
}

/// Why [`newton_iteration`] could not make a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NewtonError {
    /// The settings are not usable (h or dp not finite and positive).
    BadSettings,
    /// The cost was not finite at the start point or at a finite-difference point.
    NonFiniteCost,
    /// The Hessian stayed singular after regularisation: the cost is flat (the
    /// parameters are not identifiable from these data).
    FlatCost,
}

/// What one Newton iteration did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonIteration<T: Real, const N: usize> {
    /// The parameters after the step (equal to the start when no step lowered the cost).
    pub params: SVector<T, N>,
    /// The cost at [`NewtonIteration::params`].
    pub cost: T,
    /// The finite-difference gradient F' at the start point, Eq (25).
    pub gradient: SVector<T, N>,
    /// The factor that multiplied the Newton step: h, halved as often as needed.
    pub step_scale: T,
    /// The identity multiple added to F'' to make it positive definite (0 when none).
    pub shift: T,
    /// Cost evaluations used.
    pub evaluations: usize,
    /// True when no step (down to the last halving) lowered the cost: the start point is a
    /// minimum to within the finite differences.
    pub stalled: bool,
}

/// Checks [`NewtonSettings`].
pub fn check_settings<T: Real>(s: &NewtonSettings<T>) -> Result<(), NewtonError> {
    let pos = |v: T| v.is_finite() && v > T::zero();
    if pos(s.h) && pos(s.dp) && s.ftol.is_finite() && s.xtol.is_finite() {
        Ok(())
    } else {
        Err(NewtonError::BadSettings)
    }
}

/// The finite differences that Eqs (25)-(28) are made of, at a point P:
/// `first[j] = F(P + dP_j) - F(P)` and
/// `second[(j, k)] = F(P + dP_j + dP_k) - F(P + dP_j) - F(P + dP_k) + F(P)`.
///
/// [`newton_iteration`] computes them from cost values, as the paper does. A caller that
/// can accumulate the differences directly (per sample, before summing) gets the same
/// numbers without the cancellation of subtracting nearly equal costs: in `f32` the second
/// difference of a cost is about `dp^2` (1e-8 for dp = 1e-4) of the cost, below the type's
/// resolution, so from cost values it is rounding noise. See
/// [`super::supervised`] for the one that does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CostDifferences<T: Real, const N: usize> {
    /// `F(P + dP_j) - F(P)`.
    pub first: SVector<T, N>,
    /// The second differences (symmetric; only entries of active pairs are read).
    pub second: SMatrix<T, N, N>,
    /// Cost evaluations (or passes over the data) the differences took.
    pub evaluations: usize,
}

/// One iteration of Newton's method, Eqs (24)-(28), on `cost` from `p` (whose cost `f0`
/// the caller already has). Only the parameters with `active[j]` true move; the others
/// keep their values (their gradient is zero and their Hessian row is the identity).
pub fn newton_iteration<T: Real, const N: usize>(
    cost: &mut impl FnMut(&SVector<T, N>) -> T,
    p: &SVector<T, N>,
    f0: T,
    active: &[bool; N],
    s: &NewtonSettings<T>,
) -> Result<NewtonIteration<T, N>, NewtonError> {
    check_settings(s)?;
    if !f0.is_finite() {
        return Err(NewtonError::NonFiniteCost);
    }
    let dp = s.dp;
    let mut evaluations = 0usize;
    // Eq (27): F(P + dP_j).
    let mut fj = SVector::<T, N>::zeros();
    for j in 0..N {
        if active[j] {
            let mut q = *p;
            q[j] += dp;
            fj[j] = cost(&q);
            evaluations += 1;
            if !fj[j].is_finite() {
                return Err(NewtonError::NonFiniteCost);
            }
        }
    }
    let mut d = CostDifferences {
        first: SVector::<T, N>::zeros(),
        second: SMatrix::<T, N, N>::zeros(),
        evaluations: 0,
    };
    for j in 0..N {
        if active[j] {
            d.first[j] = fj[j] - f0;
        }
    }
    // Eq (28): F(P + dP_jk) with dP_jk = dP_j + dP_k.
    for j in 0..N {
        if !active[j] {
            continue;
        }
        for k in j..N {
            if !active[k] {
                continue;
            }
            let mut q = *p;
            q[j] += dp;
            q[k] += dp;
            let fjk = cost(&q);
            evaluations += 1;
            if !fjk.is_finite() {
                return Err(NewtonError::NonFiniteCost);
            }
            let v = fjk - fj[j] - fj[k] + f0;
            d.second[(j, k)] = v;
            d.second[(k, j)] = v;
        }
    }
    d.evaluations = evaluations;
    newton_step(
        &d,
        &mut |q: &SVector<T, N>| {
            let fq = cost(q);
            (fq - f0, fq)
        },
        p,
        f0,
        active,
        s,
    )
}

/// Eqs (24)-(28) from differences the caller computed ([`CostDifferences`]): the gradient
/// `first / dp`, the Hessian `second / dp^2`, the regularised Newton step and its
/// halvings. `change(q)` returns `(F(q) - F(p), F(q))`; a step is taken when the change is
/// negative (a caller that computes the change directly decides on its sign without the
/// cancellation of comparing two nearly equal costs).
pub(crate) fn newton_step<T: Real, const N: usize>(
    d: &CostDifferences<T, N>,
    change: &mut impl FnMut(&SVector<T, N>) -> (T, T),
    p: &SVector<T, N>,
    f0: T,
    active: &[bool; N],
    s: &NewtonSettings<T>,
) -> Result<NewtonIteration<T, N>, NewtonError> {
    check_settings(s)?;
    if !f0.is_finite() {
        return Err(NewtonError::NonFiniteCost);
    }
    let g = gradient(d, active, s.dp)?;
    let hess = hessian(d, active, s.dp)?;
    let (step, shift) = regularised_solve(&hess, &g, active)?;
    let mut it = step_halving(change, p, f0, &step, s);
    it.gradient = g;
    it.shift = shift;
    it.evaluations += d.evaluations;
    Ok(it)
}

/// Eq (25): the forward-difference gradient `first / dp` (0 for inactive parameters).
#[inline]
fn gradient<T: Real, const N: usize>(
    d: &CostDifferences<T, N>,
    active: &[bool; N],
    dp: T,
) -> Result<SVector<T, N>, NewtonError> {
    let mut g = SVector::<T, N>::zeros();
    for j in 0..N {
        if active[j] {
            if !d.first[j].is_finite() {
                return Err(NewtonError::NonFiniteCost);
            }
            g[j] = d.first[j] / dp;
        }
    }
    Ok(g)
}

/// Eqs (26), (28): the Hessian `second / dp^2` with dP_jk = dP_j + dP_k (the identity's
/// rows and columns for inactive parameters).
#[inline]
fn hessian<T: Real, const N: usize>(
    d: &CostDifferences<T, N>,
    active: &[bool; N],
    dp: T,
) -> Result<SMatrix<T, N, N>, NewtonError> {
    let mut hess = SMatrix::<T, N, N>::identity();
    let dp2 = dp * dp;
    for j in 0..N {
        if !active[j] {
            continue;
        }
        for k in j..N {
            if !active[k] {
                continue;
            }
            let v = d.second[(j, k)];
            if !v.is_finite() {
                return Err(NewtonError::NonFiniteCost);
            }
            hess[(j, k)] = v / dp2;
            hess[(k, j)] = v / dp2;
        }
    }
    Ok(hess)
}

/// Solves `F'' s = F'` (Cholesky), shifting F'' by `mu I` (on the active diagonal) until
/// it is positive definite: the step `s` and the shift used.
#[inline]
fn regularised_solve<T: Real, const N: usize>(
    hess: &SMatrix<T, N, N>,
    g: &SVector<T, N>,
    active: &[bool; N],
) -> Result<(SVector<T, N>, T), NewtonError> {
    let mut scale = T::zero();
    for j in 0..N {
        if active[j] {
            let d = hess[(j, j)].abs();
            if d > scale {
                scale = d;
            }
        }
    }
    if scale.partial_cmp(&T::zero()) != Some(core::cmp::Ordering::Greater) || !scale.is_finite() {
        return Err(NewtonError::FlatCost);
    }
    let mut shift = T::zero();
    let mut mu = scale * T::lit(1e-9);
    for _ in 0..24 {
        let mut m = *hess;
        for j in 0..N {
            if active[j] {
                m[(j, j)] += shift;
            }
        }
        if let Some(ch) = m.cholesky() {
            let sol = ch.solve(g);
            if sol.iter().all(|v| v.is_finite()) {
                return Ok((sol, shift));
            }
        }
        shift = mu;
        mu *= T::lit(10.0);
    }
    Err(NewtonError::FlatCost)
}

/// Eq (24) with step factor h, halved while the cost does not go down: the first point
/// that lowers it, or `p` itself, stalled. The gradient and shift are the caller's to
/// fill in; `evaluations` counts the changes evaluated here.
#[inline]
fn step_halving<T: Real, const N: usize>(
    change: &mut impl FnMut(&SVector<T, N>) -> (T, T),
    p: &SVector<T, N>,
    f0: T,
    step: &SVector<T, N>,
    s: &NewtonSettings<T>,
) -> NewtonIteration<T, N> {
    let mut evaluations = 0;
    let mut t = s.h;
    let half = T::lit(0.5);
    for _ in 0..=s.max_halvings {
        let q = *p - step * t;
        let (dq, fq) = change(&q);
        evaluations += 1;
        if dq.is_finite() && fq.is_finite() && dq < T::zero() {
            return NewtonIteration {
                params: q,
                cost: fq,
                gradient: SVector::zeros(),
                step_scale: t,
                shift: T::zero(),
                evaluations,
                stalled: false,
            };
        }
        t *= half;
    }
    NewtonIteration {
        params: *p,
        cost: f0,
        gradient: SVector::zeros(),
        step_scale: T::zero(),
        shift: T::zero(),
        evaluations,
        stalled: true,
    }
}

/// True when the step from `p0` to `p1` (costs `f0`, `f1`) meets the tolerances of `s`.
pub fn converged<T: Real, const N: usize>(
    p0: &SVector<T, N>,
    p1: &SVector<T, N>,
    f0: T,
    f1: T,
    s: &NewtonSettings<T>,
) -> bool {
    let small_f = (f0 - f1).abs() <= s.ftol * f0.abs();
    let small_x = (0..N).all(|j| (p1[j] - p0[j]).abs() <= s.xtol * (p0[j].abs() + s.dp));
    small_f || small_x
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn quadratic_is_solved_in_one_step() {
        // F = 3 (x - 1)^2 + (y + 2)^2 + x y: the finite differences of a quadratic are exact
        // up to the dp / 2 shift of the forward gradient.
        let mut f =
            |p: &Vector2<f64>| 3.0 * (p[0] - 1.0).powi(2) + (p[1] + 2.0).powi(2) + p[0] * p[1];
        let p0 = Vector2::new(5.0, 5.0);
        let f0 = f(&p0);
        // dp trades the forward difference's dp / 2 bias against rounding in the second
        // difference (about F eps / dp^2): 1e-4 suits a cost of order 10.
        let s = NewtonSettings {
            dp: 1e-4,
            ..NewtonSettings::default()
        };
        let it = newton_iteration(&mut f, &p0, f0, &[true, true], &s).unwrap();
        // Minimum: 6(x-1) + y = 0, 2(y+2) + x = 0 -> x = 16/11, y = -30/11.
        assert!((it.params[0] - 16.0 / 11.0).abs() < 1e-3, "{:?}", it.params);
        assert!((it.params[1] + 30.0 / 11.0).abs() < 1e-3);
        assert_eq!(it.evaluations, 1 + 2 + 3);
        assert_eq!(it.step_scale, 1.0);
    }

    #[test]
    fn frozen_parameter_does_not_move() {
        let mut f = |p: &Vector2<f64>| (p[0] - 1.0).powi(2) + (p[1] - 3.0).powi(2);
        let p0 = Vector2::new(0.0, 0.0);
        let f0 = f(&p0);
        let s = NewtonSettings {
            dp: 1e-4,
            ..NewtonSettings::default()
        };
        let it = newton_iteration(&mut f, &p0, f0, &[true, false], &s).unwrap();
        assert!((it.params[0] - 1.0).abs() < 1e-3, "{:?}", it.params);
        assert_eq!(it.params[1], 0.0);
    }

    #[test]
    fn flat_cost_and_bad_settings_are_errors() {
        let mut f = |_: &Vector2<f64>| 1.0;
        let p0 = Vector2::new(0.0, 0.0);
        let s = NewtonSettings::default();
        assert_eq!(
            newton_iteration(&mut f, &p0, 1.0, &[true, true], &s),
            Err(NewtonError::FlatCost)
        );
        let bad = NewtonSettings { dp: 0.0, ..s };
        assert_eq!(
            newton_iteration(&mut f, &p0, 1.0, &[true, true], &bad),
            Err(NewtonError::BadSettings)
        );
    }

    #[test]
    fn rms_cone_needs_halvings_but_descends() {
        // sqrt(0.01 + x^2): Newton's step from x = 1 is x (1 + x^2 / 0.01) = 101, an
        // overshoot that only halving turns into a descent.
        let mut f = |p: &SVector<f64, 1>| (0.01 + p[0] * p[0]).sqrt();
        let p0 = SVector::<f64, 1>::new(1.0);
        let s = NewtonSettings {
            dp: 1e-4,
            ..NewtonSettings::default()
        };
        let f0 = f(&p0);
        let it = newton_iteration(&mut f, &p0, f0, &[true], &s).unwrap();
        assert!(it.cost < f(&p0));
        assert!(it.step_scale < 1.0);
    }
}
