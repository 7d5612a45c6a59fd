//! The fits themselves: the kinematics prepared once ([`prepare`]), the identifiability
//! check ([`sensitivity`]), and Newton's method or Levenberg-Marquardt on the inverse
//! cost ([`fit`], [`fit_log`]) or the output-error cost ([`fit_output_log`]).
use std::time::Instant;

use super::{
    lm, output, Algorithm, Cost, FitError, FitReport, FitSettings, Iteration, Method, Problem,
    Stop, Target,
};
use nalgebra::{SMatrix, SVector, Vector4};
use pendtilt_core::supervision::newton::{converged, newton_iteration, NewtonError};
use pendtilt_core::supervision::{NewtonSettings, Objective};
use pendtilt_core::Sample;

/// Computes the kinematics of a log once: see [`Problem::new`].
pub fn prepare(
    samples: &[Sample<f64>],
    truth: Option<&[f64]>,
    settings: &FitSettings,
) -> Result<Problem, FitError> {
    settings.start_vector()?;
    Problem::new(
        samples,
        truth,
        settings.algorithm,
        settings.target,
        &settings.front_end,
        &settings.kinematics,
    )
}

/// The identifiability check: the RMS change of the estimate (truth) or of its rate
/// (gyro) when the parameters change by 100 % of their start size along the least
/// sensitive direction: `sqrt(lambda_min(D J'J D / n))`, D = diag(|p0|) (N scaled like K).
/// Returns it with that direction.
pub fn sensitivity(problem: &Problem, p0: &Vector4<f64>, active: [bool; 4]) -> (f64, Vec<f64>) {
    let (jtj, _, _) = problem.normal_equations(p0);
    let scale = [p0[0].abs(), p0[1].abs(), p0[2].abs(), p0[0].abs()];
    let idx: Vec<usize> = (0..4).filter(|&j| active[j]).collect();
    let m = idx.len();
    let mut s = nalgebra::DMatrix::<f64>::zeros(m, m);
    for (a, &i) in idx.iter().enumerate() {
        for (b, &j) in idx.iter().enumerate() {
            s[(a, b)] = jtj[(i, j)] * scale[i] * scale[j] / problem.len() as f64;
        }
    }
    let eig = s.symmetric_eigen();
    let (k, &lmin) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &0.0));
    let dir = if m > 0 {
        eig.eigenvectors.column(k).iter().copied().collect()
    } else {
        Vec::new()
    };
    (lmin.max(0.0).sqrt(), dir)
}

/// Identifiability of the inverse fit ([`sensitivity`] at `p0`): the sensitivity, its
/// threshold and unit, or [`FitError::Unidentifiable`] with the flat direction.
fn inverse_identifiability(
    problem: &Problem,
    settings: &FitSettings,
    p0: &Vector4<f64>,
) -> Result<(f64, f64, &'static str), FitError> {
    let (sens, dir) = sensitivity(problem, p0, settings.algorithm.active());
    let threshold = settings.threshold(Cost::Inverse);
    let unit = match settings.target {
        Target::Truth => "rad",
        Target::Gyro => "rad/s",
    };
    if sens.is_nan() || sens < threshold {
        let names = settings.algorithm.names();
        let direction = names
            .iter()
            .zip(&dir)
            .map(|(n, d)| format!("{n} {d:+.2}"))
            .collect::<Vec<_>>()
            .join(", ");
        return Err(FitError::Unidentifiable {
            sensitivity: sens,
            threshold,
            unit,
            direction,
        });
    }
    Ok((sens, threshold, unit))
}

/// Fits the parameters of `problem` as `settings` say; `on_iteration` sees every
/// iteration as it is made (iteration 0 is the start).
pub fn fit(
    problem: &Problem,
    settings: &FitSettings,
    mut on_iteration: impl FnMut(&Iteration),
) -> Result<FitReport, FitError> {
    if problem.algorithm() != settings.algorithm || problem.target() != settings.target {
        return Err(FitError::BadSettings(
            "the problem was prepared for another algorithm or target".into(),
        ));
    }
    let p0 = settings.start_vector()?;
    let active = settings.algorithm.active();
    let n_active = settings.algorithm.names().len();
    let started = Instant::now();
    let (sens, threshold, unit) = inverse_identifiability(problem, settings, &p0)?;
    let start_cost = problem.cost(&p0, Objective::Rms);
    if !start_cost.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let take = |p: &Vector4<f64>| p.iter().take(n_active).copied().collect::<Vec<f64>>();
    let it0 = Iteration::start(take(&p0), start_cost, 2);
    on_iteration(&it0);
    let mut iterations = vec![it0];
    let mut evaluations = 2usize;
    let (p, stop) = match settings.method {
        Method::Newton => {
            let objective = settings.objective;
            newton_fit(
                &mut |p: &Vector4<f64>| problem.cost(p, objective),
                p0,
                &active,
                &settings.newton,
                (sens, threshold, unit),
                |p| (take(p), problem.cost(p, Objective::Rms)),
                &mut on_iteration,
                &mut iterations,
                &mut evaluations,
            )?
        }
        Method::Lm => {
            let out = lm::levenberg_marquardt(problem, &p0, &active, &settings.lm, |it| {
                let rec = Iteration::from_lm(it, take(&it.params));
                on_iteration(&rec);
                iterations.push(rec);
            })?;
            evaluations += out.evaluations;
            (out.params, out.stop)
        }
    };
    let elapsed = started.elapsed();
    Ok(FitReport {
        algorithm: settings.algorithm,
        target: settings.target,
        method: settings.method,
        cost_kind: Cost::Inverse,
        accel_drive: false,
        vibration_rms: None,
        names: settings.algorithm.names().to_vec(),
        start: take(&p0),
        params: take(&p),
        start_cost,
        cost: problem.cost(&p, Objective::Rms),
        iterations,
        evaluations,
        stop,
        samples: problem.len(),
        sensitivity: sens,
        cutoff_hz: problem.cutoff_hz(),
        elapsed,
    })
}

/// [`prepare`] then [`fit`]; with [`Cost::Output`] (also [`Cost::Auto`] for a, b against
/// the true angle), [`fit_output_log`].
pub fn fit_log(
    samples: &[Sample<f64>],
    truth: Option<&[f64]>,
    settings: &FitSettings,
    on_iteration: impl FnMut(&Iteration),
) -> Result<FitReport, FitError> {
    if settings.cost.resolve(settings.target, settings.algorithm) == Cost::Output {
        return fit_output_log(samples, truth, settings, on_iteration);
    }
    let problem = prepare(samples, truth, settings)?;
    fit(&problem, settings, on_iteration)
}

/// The output-error fit ([`output`]) of a, b: Levenberg-Marquardt ([`Method::Lm`]) or the
/// paper's Newton, Eqs (24)-(28), on the RMS output error ([`Method::Newton`]). Needs the
/// truth target and alg1 or alg2; reports [`FitError::Unidentifiable`] like [`fit`].
pub fn fit_output_log(
    samples: &[Sample<f64>],
    truth: Option<&[f64]>,
    settings: &FitSettings,
    mut on_iteration: impl FnMut(&Iteration),
) -> Result<FitReport, FitError> {
    if settings.target != Target::Truth || settings.algorithm == Algorithm::Alg3 {
        return Err(FitError::BadSettings(
            "the output-error cost fits a, b (alg1, alg2) against the true angle only".into(),
        ));
    }
    let p0 = settings.start_vector()?;
    let problem = output::OutputProblem::new(samples, truth, &settings.output)?;
    let started = Instant::now();
    let threshold = settings.threshold(Cost::Output);
    let (sens, sum0) = output_identifiability(&problem, &p0, threshold)?;
    let n = problem.len() as f64;
    let start_cost = (sum0 / n).sqrt();
    if !start_cost.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let it0 = Iteration::start(vec![p0[0], p0[1]], start_cost, 5);
    on_iteration(&it0);
    let mut iterations = vec![it0];
    let mut evaluations = 5usize;
    let (p, stop) = match settings.method {
        Method::Lm => {
            let out = output::fit_output(&problem, p0[0], p0[1], &settings.lm, |it| {
                let rec = Iteration::from_lm(it, vec![it.params[0], it.params[1]]);
                on_iteration(&rec);
                iterations.push(rec);
            })?;
            evaluations += out.evaluations;
            (
                Vector4::new(out.params[0], out.params[1], 0.0, 0.0),
                out.stop,
            )
        }
        Method::Newton => {
            let objective = settings.objective;
            let mut scratch = Vec::with_capacity(problem.len());
            newton_fit(
                &mut |p: &Vector4<f64>| {
                    objective.from_sum(problem.residuals(p[0], p[1], &mut scratch), problem.len())
                },
                p0,
                &[true, true, false, false],
                &settings.newton,
                (sens, threshold, "rad"),
                |p| (vec![p[0], p[1]], problem.cost(p[0], p[1])),
                &mut on_iteration,
                &mut iterations,
                &mut evaluations,
            )?
        }
    };
    let elapsed = started.elapsed();
    Ok(FitReport {
        algorithm: settings.algorithm,
        target: settings.target,
        method: settings.method,
        cost_kind: Cost::Output,
        accel_drive: problem.accel_driven(),
        vibration_rms: problem.vibration_rms(),
        names: settings.algorithm.names().to_vec(),
        start: vec![p0[0], p0[1]],
        params: vec![p[0], p[1]],
        start_cost,
        cost: problem.cost(p[0], p[1]),
        iterations,
        evaluations,
        stop,
        samples: problem.len(),
        sensitivity: sens,
        cutoff_hz: settings.output.smoothing_hz,
        elapsed,
    })
}

/// Identifiability of the output-error fit, as [`sensitivity`] on the output error's
/// Jacobian at `p0`: the sensitivity and the sum of squares there, or
/// [`FitError::Unidentifiable`] below `threshold`.
fn output_identifiability(
    problem: &output::OutputProblem,
    p0: &Vector4<f64>,
    threshold: f64,
) -> Result<(f64, f64), FitError> {
    let (jtj, _, sum0) = problem.normal_equations(p0[0], p0[1]);
    let n = problem.len() as f64;
    let d = nalgebra::Matrix2::new(p0[0], 0.0, 0.0, p0[1]);
    let eig = (d * jtj * d / n).symmetric_eigen();
    let k = if eig.eigenvalues[0] <= eig.eigenvalues[1] {
        0
    } else {
        1
    };
    let sens = eig.eigenvalues[k].max(0.0).sqrt();
    if sens.is_nan() || sens < threshold {
        let v = eig.eigenvectors.column(k);
        return Err(FitError::Unidentifiable {
            sensitivity: sens,
            threshold,
            unit: "rad",
            direction: format!("a {:+.2}, b {:+.2}", v[0], v[1]),
        });
    }
    Ok((sens, sum0))
}

/// Solves `(A + shift) x = b` on the active block with Cholesky (inactive: x = 0).
pub(crate) fn solve_active<const N: usize>(
    a: &SMatrix<f64, N, N>,
    b: &SVector<f64, N>,
    active: &[bool; N],
) -> Option<SVector<f64, N>> {
    let mut m = *a;
    let mut r = *b;
    for j in 0..N {
        if !active[j] {
            for k in 0..N {
                m[(j, k)] = 0.0;
                m[(k, j)] = 0.0;
            }
            m[(j, j)] = 1.0;
            r[j] = 0.0;
        }
    }
    let x = m.cholesky()?.solve(&r);
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The paper's Newton loop (Eqs 24-28) on `cost` from `p0` over the `active` parameters,
/// shared by the Eq (23) and the output-error fits: one logged [`Iteration`] per step
/// (its parameters and RMS cost from `record`), evaluations counted, stopping on
/// convergence, on no descent or at the iteration limit. A singular Hessian is reported
/// as unidentifiable with `flat` = (sensitivity, threshold, unit).
#[allow(clippy::too_many_arguments)]
fn newton_fit(
    cost: &mut impl FnMut(&Vector4<f64>) -> f64,
    p0: Vector4<f64>,
    active: &[bool; 4],
    s: &NewtonSettings<f64>,
    flat: (f64, f64, &'static str),
    mut record: impl FnMut(&Vector4<f64>) -> (Vec<f64>, f64),
    on_iteration: &mut impl FnMut(&Iteration),
    iterations: &mut Vec<Iteration>,
    evaluations: &mut usize,
) -> Result<(Vector4<f64>, Stop), FitError> {
    pendtilt_core::supervision::newton::check_settings(s)
        .map_err(|_| FitError::BadSettings("Newton h and dp must be finite and > 0".into()))?;
    let mut p = p0;
    let mut f = cost(&p);
    *evaluations += 1;
    for n in 1..=s.max_iterations {
        let it = match newton_iteration(cost, &p, f, active, s) {
            Ok(it) => it,
            Err(NewtonError::FlatCost) => {
                return Err(FitError::Unidentifiable {
                    sensitivity: flat.0,
                    threshold: flat.1,
                    unit: flat.2,
                    direction: "Newton's finite-difference Hessian is singular".into(),
                })
            }
            Err(NewtonError::NonFiniteCost) => return Err(FitError::NonFiniteCost),
            Err(NewtonError::BadSettings) => {
                return Err(FitError::BadSettings("Newton settings".into()))
            }
        };
        *evaluations += it.evaluations;
        let (params, rms) = record(&it.params);
        let rec = Iteration {
            n,
            params,
            cost: rms,
            gradient_norm: it.gradient.norm(),
            step: it.step_scale,
            evaluations: it.evaluations,
        };
        on_iteration(&rec);
        iterations.push(rec);
        if it.stalled {
            return Ok((p, Stop::NoDescent));
        }
        let done = converged(&p, &it.params, f, it.cost, s);
        p = it.params;
        f = it.cost;
        if done {
            return Ok((p, Stop::Converged));
        }
    }
    Ok((p, Stop::IterationLimit))
}
