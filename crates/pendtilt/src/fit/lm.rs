//! Levenberg-Marquardt (beyond the paper) with the analytic Jacobian of Eqs (20), (21),
//! (30).
//!
//! Minimises the sum of squared residuals (the square of Eq 23 / 29 times the sample
//! count, so the same minimiser). Each iteration is one pass over the cached kinematics
//! ([`super::Problem::normal_equations`]) giving `J'J`, `J'r` and the cost, then the
//! damped step `(J'J + lambda diag(J'J)) d = -J'r` (Marquardt's scaling, which makes the
//! step independent of the parameters' very different sizes). A step that lowers the cost
//! is taken and lambda divided by [`LmSettings::decrease`]; otherwise lambda is multiplied
//! by [`LmSettings::increase`] and the step retried. Own implementation on nalgebra 4x4
//! fixed matrices: see [`super`] for why not the `levenberg-marquardt` crate.
use super::{solve_active, FitError, Problem, Stop};
use nalgebra::Vector4;

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

/// One LM iteration, for the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmIteration {
    /// 1-based.
    pub n: usize,
    /// Parameters after it.
    pub params: Vector4<f64>,
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
pub struct LmOutcome {
    /// The parameters.
    pub params: Vector4<f64>,
    /// Why it stopped.
    pub stop: Stop,
    /// Passes over the log.
    pub evaluations: usize,
}

/// Runs LM from `p0` moving the `active` parameters; `on_iteration` logs each iteration.
pub fn levenberg_marquardt(
    problem: &Problem,
    p0: &Vector4<f64>,
    active: &[bool; 4],
    s: &LmSettings,
    mut on_iteration: impl FnMut(&LmIteration),
) -> Result<LmOutcome, FitError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(s.lambda) && s.decrease > 1.0 && s.increase > 1.0 && s.ftol >= 0.0 && s.xtol >= 0.0) {
        return Err(FitError::BadSettings(
            "LM: lambda > 0, decrease and increase > 1, tolerances >= 0".into(),
        ));
    }
    let n = problem.len() as f64;
    let mut p = *p0;
    let (mut jtj, mut jtr, mut sum) = problem.normal_equations(&p);
    let mut evaluations = 1usize;
    if !sum.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let mut lambda = s.lambda;
    let mut stop = Stop::IterationLimit;
    'outer: for it in 1..=s.max_iterations {
        let mut tries = 0usize;
        loop {
            tries += 1;
            let mut a = jtj;
            for j in 0..4 {
                a[(j, j)] += lambda * jtj[(j, j)].max(f64::MIN_POSITIVE);
            }
            let step = solve_active(&a, &(-jtr), active);
            let Some(step) = step else {
                lambda *= s.increase;
                if lambda > 1e16 {
                    stop = Stop::NoDescent;
                    break 'outer;
                }
                continue;
            };
            let q = p + step;
            let (jtj1, jtr1, sum1) = problem.normal_equations(&q);
            evaluations += 1;
            if sum1.is_finite() && sum1 < sum {
                let rel_f = (sum - sum1) / sum;
                let small_x = (0..4).all(|j| step[j].abs() <= s.xtol * (p[j].abs() + s.xtol));
                let grad = jtr.norm() / n;
                p = q;
                jtj = jtj1;
                jtr = jtr1;
                sum = sum1;
                on_iteration(&LmIteration {
                    n: it,
                    params: p,
                    rms: (sum / n).sqrt(),
                    gradient_norm: grad,
                    lambda,
                    evaluations: tries,
                });
                lambda = (lambda / s.decrease).max(1e-12);
                if rel_f <= s.ftol || small_x {
                    stop = Stop::Converged;
                    break 'outer;
                }
                break;
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
