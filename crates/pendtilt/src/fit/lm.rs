//! Levenberg-Marquardt (beyond the paper) with the analytic Jacobian of Eqs (20), (21),
//! (30).
//!
//! Minimises the sum of squared residuals (the square of Eq 23 / 29 times the sample
//! count, so the same minimiser). Each iteration is one pass over the cached kinematics
//! ([`super::Problem::normal_equations`]) giving `J'J`, `J'r` and the cost, then the
//! damped step `(J'J + lambda diag(J'J)) d = -J'r` (Marquardt's scaling, which makes the
//! step independent of the parameters' very different sizes). A step that lowers the cost
//! is taken and lambda divided by [`LmSettings::decrease`]; otherwise lambda is multiplied
//! by [`LmSettings::increase`] and the step retried. Own implementation on nalgebra fixed
//! matrices: see [`super`] for why not the `levenberg-marquardt` crate. The loop,
//! [`minimise`], is generic over the cost ([`LeastSquares`]): the output-error fit
//! ([`super::output`]) runs the same one on a, b.
use super::{solve_active, FitError, Problem, Stop};
use nalgebra::{SMatrix, SVector, Vector4};

/// Settings of [`levenberg_marquardt`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmSettings {
    /// Starting damping lambda. Default 1e-3.
    pub lambda: f64,
    /// Divides lambda after a successful step. Default 10.
    pub decrease: f64,
    /// Multiplies lambda after a failed step. Default 10.
    pub increase: f64,
    /// Stop when the cost falls by less than `ftol` times itself. Default 1e-12.
    pub ftol: f64,
    /// Stop when every parameter moves by less than `xtol` times its size. Default 1e-10.
    pub xtol: f64,
    /// Iteration limit (each iteration may retry several lambdas). Default 100.
    pub max_iterations: usize,
}

impl Default for LmSettings {
    fn default() -> Self {
        Self {
            lambda: 1e-3,
            decrease: 10.0,
            increase: 10.0,
            ftol: 1e-12,
            xtol: 1e-10,
            max_iterations: 100,
        }
    }
}

/// One LM iteration, for the log; `N` parameters (4 for the Eq (23) fit, 2 for the
/// output-error fit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmIteration<const N: usize = 4> {
    /// 1-based.
    pub n: usize,
    /// Parameters after it.
    pub params: SVector<f64, N>,
    /// RMS residual after it.
    pub rms: f64,
    /// |J'r| / samples before the step.
    pub gradient_norm: f64,
    /// Damping of the accepted step.
    pub lambda: f64,
    /// Passes over the log.
    pub evaluations: usize,
}

/// What [`levenberg_marquardt`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmOutcome<const N: usize = 4> {
    /// The parameters.
    pub params: SVector<f64, N>,
    /// Why it stopped.
    pub stop: Stop,
    /// Passes over the log.
    pub evaluations: usize,
}

/// The normal equations of a sum of squares at a point: `(J'J, J'r, sum r^2)`.
pub type Normal<const N: usize> = (SMatrix<f64, N, N>, SVector<f64, N>, f64);

/// `J'J` and `J'r` at a point.
pub type Gradient<const N: usize> = (SMatrix<f64, N, N>, SVector<f64, N>);

/// A sum-of-squares cost over `N` parameters that [`minimise`] can step on.
pub trait LeastSquares<const N: usize> {
    /// Passes over the log one [`LeastSquares::linearise`] costs.
    const LINEARISE_PASSES: usize;
    /// Residuals in the cost (the gradient and RMS are per residual).
    fn residual_count(&self) -> usize;
    /// The normal equations at `p`.
    fn linearise(&self, p: &SVector<f64, N>) -> Normal<N>;
    /// The sum of squares at a trial point `q` (one pass over the log), with `J'J` and
    /// `J'r` there when that pass gives them too (then an accepted step needs no
    /// [`LeastSquares::linearise`]).
    fn trial(&self, q: &SVector<f64, N>) -> (f64, Option<Gradient<N>>);
}

impl LeastSquares<4> for Problem {
    const LINEARISE_PASSES: usize = 1;

    fn residual_count(&self) -> usize {
        self.len()
    }

    fn linearise(&self, p: &Vector4<f64>) -> Normal<4> {
        self.normal_equations(p)
    }

    fn trial(&self, q: &Vector4<f64>) -> (f64, Option<Gradient<4>>) {
        let (jtj, jtr, sum) = self.normal_equations(q);
        (sum, Some((jtj, jtr)))
    }
}

/// Runs LM from `p0` moving the `active` parameters; `on_iteration` logs each iteration.
pub fn levenberg_marquardt(
    problem: &Problem,
    p0: &Vector4<f64>,
    active: &[bool; 4],
    s: &LmSettings,
    on_iteration: impl FnMut(&LmIteration),
) -> Result<LmOutcome, FitError> {
    minimise(problem, p0, active, s, on_iteration)
}

/// Refuses settings the loop cannot run with.
fn check_settings(s: &LmSettings) -> Result<(), FitError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(s.lambda) && s.decrease > 1.0 && s.increase > 1.0 && s.ftol >= 0.0 && s.xtol >= 0.0) {
        return Err(FitError::BadSettings(
            "LM: lambda > 0, decrease and increase > 1, tolerances >= 0".into(),
        ));
    }
    Ok(())
}

/// `jtj` with Marquardt's damping: each diagonal entry times `1 + lambda`.
fn damped<const N: usize>(jtj: &SMatrix<f64, N, N>, lambda: f64) -> SMatrix<f64, N, N> {
    let mut a = *jtj;
    for j in 0..N {
        a[(j, j)] += lambda * jtj[(j, j)].max(f64::MIN_POSITIVE);
    }
    a
}

/// The Levenberg-Marquardt loop (Marquardt's diagonal scaling) on any [`LeastSquares`]
/// cost from `p0`, moving the `active` parameters; `on_iteration` logs each accepted step
/// and the last try of a stop on no descent.
pub fn minimise<const N: usize, P: LeastSquares<N>>(
    problem: &P,
    p0: &SVector<f64, N>,
    active: &[bool; N],
    s: &LmSettings,
    mut on_iteration: impl FnMut(&LmIteration<N>),
) -> Result<LmOutcome<N>, FitError> {
    check_settings(s)?;
    let n = problem.residual_count() as f64;
    let mut p = *p0;
    let (mut jtj, mut jtr, mut sum) = problem.linearise(&p);
    let mut evaluations = P::LINEARISE_PASSES;
    if !sum.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let mut lambda = s.lambda;
    let mut stop = Stop::IterationLimit;
    'outer: for it in 1..=s.max_iterations {
        let mut tries = 0usize;
        loop {
            tries += 1;
            // A singular damped system is retried with more damping, like a failed step.
            if let Some(step) = solve_active(&damped(&jtj, lambda), &(-jtr), active) {
                let q = p + step;
                let (sum1, normal1) = problem.trial(&q);
                evaluations += 1;
                if sum1.is_finite() && sum1 < sum {
                    let rel_f = (sum - sum1) / sum;
                    let small_x = (0..N).all(|j| step[j].abs() <= s.xtol * (p[j].abs() + s.xtol));
                    let grad = jtr.norm() / n;
                    p = q;
                    let passes = match normal1 {
                        Some((jtj1, jtr1)) => {
                            (jtj, jtr, sum) = (jtj1, jtr1, sum1);
                            0
                        }
                        None => {
                            (jtj, jtr, sum) = problem.linearise(&p);
                            P::LINEARISE_PASSES
                        }
                    };
                    evaluations += passes;
                    on_iteration(&LmIteration {
                        n: it,
                        params: p,
                        rms: (sum / n).sqrt(),
                        gradient_norm: grad,
                        lambda,
                        evaluations: tries + passes,
                    });
                    lambda = (lambda / s.decrease).max(1e-12);
                    if rel_f <= s.ftol || small_x {
                        stop = Stop::Converged;
                        break 'outer;
                    }
                    break;
                }
            }
            lambda *= s.increase;
            if lambda > 1e16 {
                stop = Stop::NoDescent;
                on_iteration(&LmIteration {
                    n: it,
                    params: p,
                    rms: (sum / n).sqrt(),
                    gradient_norm: jtr.norm() / n,
                    lambda,
                    evaluations: tries,
                });
                break 'outer;
            }
        }
    }
    Ok(LmOutcome {
        params: p,
        stop,
        evaluations,
    })
}
