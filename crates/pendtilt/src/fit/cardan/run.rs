//! The 3-D fit itself: settings and start checked, the drive cached, the identifiability
//! check, Levenberg-Marquardt, the report.
use std::time::Instant;

use nalgebra::DMatrix;
use pendtilt_core::spatial::cardan::CardanParams;

use super::problem::CardanProblem;
use super::{Fit3dReport, Fit3dSettings, Log3dColumns, Params, C_SCALE, NAMES, NP};
use crate::fit::lm::minimise;
use crate::fit::{FitError, Iteration, Target};

/// Refuses settings no fit can run with.
fn check_settings(s: &Fit3dSettings) -> Result<(), FitError> {
    let ok = s.skip.is_finite()
        && s.skip >= 0.0
        && s.smoothing_hz.is_finite()
        && s.smoothing_hz > 0.0
        && s.truth_accel_hz >= 0.0
        && s.min_sensitivity >= 0.0
        && s.min_offset_sensitivity >= 0.0;
    if ok {
        Ok(())
    } else {
        Err(FitError::BadSettings(
            "3-D fit: skip >= 0, smoothing_hz > 0, truth_accel_hz >= 0, sensitivities >= 0".into(),
        ))
    }
}

/// The start vector of `c`, checked: damping >= 0, inertias > 0, everything finite.
fn start_vector(c: &CardanParams<f64>) -> Result<Params, FitError> {
    let p = Params::from_column_slice(&[c.a_x, c.a_y, c.b_x + c.b_ring, c.b_y, c.c[2], 0.0, 0.0]);
    for (j, why, ok) in [
        (0, "must be a finite number >= 0", c.a_x >= 0.0),
        (1, "must be a finite number >= 0", c.a_y >= 0.0),
        (2, "must be a finite number > 0", c.b_x > 0.0),
        (3, "must be a finite number > 0", c.b_y > 0.0),
        (4, "must be finite", true),
    ] {
        if !(ok && p[j].is_finite()) {
            return Err(FitError::InvalidStart {
                name: NAMES[j],
                value: p[j],
                why,
            });
        }
    }
    if !(c.gravity.is_finite() && c.gravity > 0.0 && c.b_ring >= 0.0 && c.b_z > 0.0) {
        return Err(FitError::InvalidStart {
            name: "gravity, b_ring or b_z",
            value: f64::NAN,
            why: "gravity and b_z must be > 0, b_ring >= 0",
        });
    }
    Ok(p)
}

/// The identifiability check at `p0` from `(J'J, residual count)`: the sensitivity of the
/// four dynamic parameters (or [`FitError::Unidentifiable`] below `s.min_sensitivity`),
/// and c_z's with the other parameters refitted (the Schur complement of its entry).
fn identifiability(
    jtj: &nalgebra::SMatrix<f64, NP, NP>,
    count: usize,
    p0: &Params,
    s: &Fit3dSettings,
) -> Result<(f64, f64), FitError> {
    let n = count as f64;
    let mut m = DMatrix::<f64>::zeros(4, 4);
    for i in 0..4 {
        for j in 0..4 {
            m[(i, j)] = jtj[(i, j)] * p0[i].abs() * p0[j].abs() / n;
        }
    }
    let eig = m.symmetric_eigen();
    let (k, &lmin) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &0.0));
    let sens = lmin.max(0.0).sqrt();
    if sens.is_nan() || sens < s.min_sensitivity {
        let v = eig.eigenvectors.column(k);
        let direction = (0..4)
            .map(|j| format!("{} {:+.2}", NAMES[j], v[j]))
            .collect::<Vec<_>>()
            .join(", ");
        return Err(FitError::Unidentifiable {
            sensitivity: sens,
            threshold: s.min_sensitivity,
            unit: "rad",
            direction,
        });
    }
    // c_z given the others: J'J_cc - J'J_co (J'J_oo)^-1 J'J_oc.
    let others = [0, 1, 2, 3, 5, 6];
    let oo = DMatrix::from_fn(6, 6, |i, j| jtj[(others[i], others[j])]);
    let oc = nalgebra::DVector::from_fn(6, |i, _| jtj[(others[i], 4)]);
    let info = match oo.cholesky() {
        Some(ch) => jtj[(4, 4)] - oc.dot(&ch.solve(&oc)),
        None => 0.0,
    };
    let offset_sens = (info.max(0.0) * C_SCALE * C_SCALE / n).sqrt();
    Ok((sens, offset_sens))
}

/// Fits the Cardan pendulum to `log` from the start rig `start` (whose b_z, b_ring, c_x,
/// c_y and gravity are held), the accelerometer at `accel_at` from P1 (`[mounting]`);
/// `on_iteration` sees every iteration as it is made (0 is the start). The result is not
/// checked for plausibility: see [`super::check`].
pub fn fit_cardan(
    log: &Log3dColumns,
    start: &CardanParams<f64>,
    accel_at: [f64; 3],
    s: &Fit3dSettings,
    mut on_iteration: impl FnMut(&Iteration),
) -> Result<Fit3dReport, FitError> {
    check_settings(s)?;
    let p0 = start_vector(start)?;
    if s.target == Target::Truth && !log.has_truth() {
        return Err(FitError::MissingColumn("roll` and `pitch"));
    }
    let started = Instant::now();
    let problem = CardanProblem::new(log, start, accel_at, s)?;
    let (jtj, _, sum0) = problem.normal_equations(&p0);
    if !sum0.is_finite() {
        return Err(FitError::NonFiniteCost);
    }
    let count = 2 * problem.rows();
    let (sensitivity, offset_sensitivity) = identifiability(&jtj, count, &p0, s)?;
    let mut active = [true; NP];
    active[4] = offset_sensitivity >= s.min_offset_sensitivity;
    active[5] = s.encoder_offsets;
    active[6] = s.encoder_offsets;
    let rms = |r: [f64; 2]| ((r[0] * r[0] + r[1] * r[1]) / 2.0).sqrt();
    let start_cost = rms(problem.rms_per_axis(&p0));
    let take = |p: &Params| p.iter().copied().collect::<Vec<f64>>();
    let it0 = Iteration::start(take(&p0), start_cost, 11);
    on_iteration(&it0);
    let mut iterations = vec![it0];
    let out = minimise(&problem, &p0, &active, &s.lm, |it| {
        let rec = Iteration::from_lm(it, take(&it.params));
        on_iteration(&rec);
        iterations.push(rec);
    })?;
    let p = out.params;
    let cost_per_axis = problem.rms_per_axis(&p);
    let cost = rms(cost_per_axis);
    Ok(Fit3dReport {
        target: s.target,
        active,
        start: p0,
        params: p,
        fitted: problem.cardan(&p),
        start_rig: *start,
        start_cost,
        cost,
        cost_per_axis,
        iterations,
        evaluations: 11 + out.evaluations + 1,
        stop: out.stop,
        rows: problem.rows(),
        sensitivity,
        offset_sensitivity,
        elapsed: started.elapsed(),
    })
}
