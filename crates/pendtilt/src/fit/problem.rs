//! The fitting problem: cached kinematics and the costs of Eqs (23) and (29).
//!
//! # Why fitting is fast
//! For a fixed differentiator the per-sample kinematics (phi, phi', phi'', G_d, G_k) do
//! not depend on the parameters being fitted: the cutoff is fixed in Hz from the start
//! parameters ([`fixed_cutoff`]), so [`Problem::new`] runs the estimator's
//! front end once over the log and keeps the terms. Each cost evaluation is then one cheap
//! pass of the pure Eq (20)/(21)/(30) over the cached arrays, and the analytic Jacobian
//! for Levenberg-Marquardt is one more multiply per term.
//!
//! All three algorithms are one model with four parameters p = (p0, p1, p2, p3):
//! `theta = phi + asin(p0 x0 + p1 x1 + p2 x2) + p3 G_k`, with
//! - alg1 (Eq 20): x = (phi', phi'', 0), p = (a, b, 0, 0);
//! - alg2 (Eq 21): x = (phi', phi'' - G_d, 0), p = (a, b, 0, 0);
//! - alg3 (Eq 30): x = (phi', phi'', G_d), p = (K, L, M, N).
use super::{Algorithm, FitError, Target};
use nalgebra::{Matrix4, Vector4};
use pendtilt_core::estimators::alg3::{Alg3, Alg3Settings, Alg3Terms};
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::estimators::PhiSource;
use pendtilt_core::filters::diff::{Cutoff, DiffSettings, SmoothingDifferentiator};
use pendtilt_core::supervision::Objective;
use pendtilt_core::{PendulumParams, Sample};

/// What the cost reads of the kinematics (the front end they are computed with is
/// [`super::FitSettings::front_end`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicsSettings {
    /// Seconds at the start of the log left out of the cost while the differentiators
    /// settle. Default 0.5 s.
    pub skip: f64,
    /// Pass the target (true angle, or gyro) through the same low-pass as phi, and use
    /// the low-passed phi, so that both sides of the cost carry the same delay. Then the
    /// fit identifies the pendulum's own a, b (for a noise-free log: to within a fraction
    /// of a percent) instead of values bent to make up for the differentiator's delay, and
    /// the Eq (29) residual is not swamped by the encoder's quantisation steps turned
    /// into rate. Default true. With false, the cost is exactly the paper's: the
    /// estimator's output as it runs (phi as in [`FrontEndSettings::phi`]) against the
    /// raw target.
    pub matched_target: bool,
}

impl Default for KinematicsSettings {
    fn default() -> Self {
        Self {
            skip: 0.5,
            matched_target: true,
        }
    }
}

/// `front_end`'s differentiator with its cutoff fixed in Hz for its own pendulum (the
/// start a, b).
pub fn fixed_cutoff(front_end: &FrontEndSettings<f64>) -> DiffSettings<f64> {
    let d = front_end.differentiator;
    DiffSettings {
        response: d.response,
        cutoff: Cutoff::Hz(d.cutoff_hz(&front_end.params)),
    }
}

/// The cached data of one fit: per-sample features, target, time steps.
#[derive(Debug, Clone)]
pub struct Problem {
    algorithm: Algorithm,
    target: Target,
    /// x0, x1, x2, G_k per sample.
    x: Vec<[f64; 4]>,
    /// theta - phi (truth) or G_mid - (phi_k - phi_(k-1)) / dt (gyro).
    y: Vec<f64>,
    /// 1 / dt to the previous row (gyro target).
    inv_dt: Vec<f64>,
    /// Whether the row enters the cost.
    used: Vec<bool>,
    count: usize,
    cutoff_hz: f64,
}

/// Minimum number of residuals a fit needs.
pub const MIN_ROWS: usize = 20;

impl Problem {
    /// Runs the estimator front end over the log once and caches what the costs need.
    ///
    /// `truth` (one value per sample, NaN where missing) is required for
    /// [`Target::Truth`]; the gyro is required for [`Target::Gyro`] and for alg2/alg3.
    pub fn new(
        samples: &[Sample<f64>],
        truth: Option<&[f64]>,
        algorithm: Algorithm,
        target: Target,
        front_end: &FrontEndSettings<f64>,
        kin: &KinematicsSettings,
    ) -> Result<Self, FitError> {
        let start = &front_end.params;
        let truth = check_inputs(samples, truth, algorithm, target, start)?;
        let differentiator = fixed_cutoff(front_end);
        let cutoff_hz = differentiator.cutoff_hz(start);
        let mut est = Alg3::<f64>::new(estimator_settings(front_end, differentiator, kin));
        let mut target_lp = TargetFilter::new(kin.matched_target, differentiator, cutoff_hz);
        let n = samples.len();
        let mut p = Self {
            algorithm,
            target,
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            inv_dt: Vec::with_capacity(n),
            used: Vec::with_capacity(n),
            count: 0,
            cutoff_hz,
        };
        // Time since the first row with a good stamp.
        let mut elapsed: Option<f64> = None;
        let mut prev: Option<(f64, f64)> = None; // phi, target of the previous row
        for (i, s) in samples.iter().enumerate() {
            let (_, terms) = est.update_with_terms(s);
            if s.dt.is_finite() {
                elapsed = Some(elapsed.map_or(0.0, |e| e + s.dt));
            }
            let raw_target = match target {
                Target::Truth => truth.map_or(f64::NAN, |t| t[i]),
                Target::Gyro => s.gyro,
            };
            let target_value = target_lp.value(raw_target, s.dt);
            let Some(k) = terms else {
                continue;
            };
            let settled = elapsed.is_some_and(|e| e >= kin.skip);
            let (y, inv_dt, used) = residual(target, &k, target_value, prev, settled);
            prev = Some((k.phi, target_value));
            p.x.push(features(algorithm, &k));
            p.y.push(y);
            p.inv_dt.push(inv_dt);
            p.used.push(used);
            p.count += usize::from(used);
        }
        if p.count < MIN_ROWS {
            return Err(FitError::TooFewSamples {
                have: p.count,
                need: MIN_ROWS,
            });
        }
        Ok(p)
    }

    /// The algorithm whose parameters are fitted.
    pub fn algorithm(&self) -> Algorithm {
        self.algorithm
    }

    /// The cost's target (true angle or gyro).
    pub fn target(&self) -> Target {
        self.target
    }

    /// Residuals in the cost.
    pub fn len(&self) -> usize {
        self.count
    }

    /// True when no residual enters the cost (never after a successful [`Problem::new`]).
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The differentiator cutoff used \[Hz\].
    pub fn cutoff_hz(&self) -> f64 {
        self.cutoff_hz
    }

    /// Eq (23) (truth) or Eq (29) (gyro) at `p`, as `objective` (RMS is the paper's).
    /// NaN if a parameter is not finite.
    pub fn cost(&self, p: &Vector4<f64>, objective: Objective) -> f64 {
        let mut sum = 0.0;
        match self.target {
            Target::Truth => {
                for ((x, &y), &used) in self.x.iter().zip(&self.y).zip(&self.used) {
                    if used {
                        let r = s_of(p, x) - y;
                        sum += r * r;
                    }
                }
            }
            Target::Gyro => {
                let mut s_prev = 0.0;
                for (((x, &y), &inv), &used) in
                    self.x.iter().zip(&self.y).zip(&self.inv_dt).zip(&self.used)
                {
                    let s = s_of(p, x);
                    if used {
                        let r = (s - s_prev) * inv - y;
                        sum += r * r;
                    }
                    s_prev = s;
                }
            }
        }
        objective.from_sum(sum, self.count)
    }

    /// One pass for Gauss-Newton / Levenberg-Marquardt: `(J'J, J'r, sum r^2)` at `p`,
    /// with the analytic Jacobian `ds/dp = (x0 c, x1 c, x2 c, G_k)`, `c = 1 / sqrt(1 - u^2)`
    /// (0 where the asin argument is clamped).
    pub fn normal_equations(&self, p: &Vector4<f64>) -> (Matrix4<f64>, Vector4<f64>, f64) {
        let mut jtj = Matrix4::zeros();
        let mut jtr = Vector4::zeros();
        let mut sum = 0.0;
        let mut add = |j: Vector4<f64>, r: f64| {
            jtj.syger(1.0, &j, &j, 1.0);
            jtr += j * r;
            sum += r * r;
        };
        match self.target {
            Target::Truth => {
                for ((x, &y), &used) in self.x.iter().zip(&self.y).zip(&self.used) {
                    if used {
                        let (s, j) = s_and_grad(p, x);
                        add(j, s - y);
                    }
                }
            }
            Target::Gyro => {
                let mut s_prev = 0.0;
                let mut j_prev = Vector4::zeros();
                for (((x, &y), &inv), &used) in
                    self.x.iter().zip(&self.y).zip(&self.inv_dt).zip(&self.used)
                {
                    let (s, j) = s_and_grad(p, x);
                    if used {
                        add((j - j_prev) * inv, (s - s_prev) * inv - y);
                    }
                    s_prev = s;
                    j_prev = j;
                }
            }
        }
        // syger fills the lower triangle only.
        jtj.fill_upper_triangle_with_lower_triangle();
        (jtj, jtr, sum)
    }
}

/// `asin(u) + p3 G_k`, the parameter-dependent part of theta (clamped like the estimator).
#[inline(always)]
fn s_of(p: &Vector4<f64>, x: &[f64; 4]) -> f64 {
    let u = p[0] * x[0] + p[1] * x[1] + p[2] * x[2];
    u.clamp(-1.0, 1.0).asin() + p[3] * x[3]
}

#[inline(always)]
fn s_and_grad(p: &Vector4<f64>, x: &[f64; 4]) -> (f64, Vector4<f64>) {
    let u = p[0] * x[0] + p[1] * x[1] + p[2] * x[2];
    if u.abs() < 1.0 {
        let c = 1.0 / (1.0 - u * u).sqrt();
        (
            u.asin() + p[3] * x[3],
            Vector4::new(x[0] * c, x[1] * c, x[2] * c, x[3]),
        )
    } else {
        (
            u.clamp(-1.0, 1.0).asin() + p[3] * x[3],
            Vector4::new(0.0, 0.0, 0.0, x[3]),
        )
    }
}

/// Checks the start and the columns the fit needs: the truth (one per sample) for
/// [`Target::Truth`], the gyro for [`Target::Gyro`] and Algorithms 2-3.
fn check_inputs<'a>(
    samples: &[Sample<f64>],
    truth: Option<&'a [f64]>,
    algorithm: Algorithm,
    target: Target,
    start: &PendulumParams<f64>,
) -> Result<Option<&'a [f64]>, FitError> {
    if !(start.b.is_finite() && start.b > 0.0) {
        return Err(FitError::InvalidStart {
            name: "b",
            value: start.b,
            why:
                "b = I_p / (m_p g l_p) must be finite and > 0 (it sets the differentiator's cutoff)",
        });
    }
    let truth = match (target, truth) {
        (Target::Truth, None) => return Err(FitError::MissingColumn("theta")),
        (_, t) => t,
    };
    if let Some(t) = truth {
        if t.len() != samples.len() {
            return Err(FitError::BadSettings(format!(
                "{} truth values for {} samples",
                t.len(),
                samples.len()
            )));
        }
    }
    let needs_gyro = target == Target::Gyro || algorithm != Algorithm::Alg1;
    if needs_gyro && !samples.iter().any(|s| s.gyro.is_finite()) {
        return Err(FitError::MissingColumn("gyro"));
    }
    Ok(truth)
}

/// The estimator whose terms the fit reads: Eq (30) on `front_end` with the fixed-cutoff
/// `differentiator` (and the low-passed phi when the target is matched).
fn estimator_settings(
    front_end: &FrontEndSettings<f64>,
    differentiator: DiffSettings<f64>,
    kin: &KinematicsSettings,
) -> Alg3Settings<f64> {
    let mut settings = Alg3Settings::from_params(front_end.params);
    settings.front_end = FrontEndSettings {
        differentiator,
        phi: if kin.matched_target {
            PhiSource::Filtered
        } else {
            front_end.phi
        },
        ..*front_end
    };
    settings
}

/// The target through phi's own low-pass (same response and cutoff) when matched, held
/// over missing values; as it is otherwise.
struct TargetFilter {
    lp: Option<SmoothingDifferentiator<f64>>,
    /// Time since the last filtered target value (`None` before the first).
    since: Option<f64>,
}

impl TargetFilter {
    fn new(matched: bool, differentiator: DiffSettings<f64>, cutoff_hz: f64) -> Self {
        let lp = matched
            .then(|| SmoothingDifferentiator::<f64>::new(differentiator.response, cutoff_hz));
        Self { lp, since: None }
    }

    /// The target value of a row with raw target `raw` and step `dt` (NaN when missing).
    fn value(&mut self, raw: f64, dt: f64) -> f64 {
        let Some(lp) = self.lp.as_mut() else {
            return raw;
        };
        let good_time = dt.is_finite();
        if good_time {
            if let Some(since) = self.since.as_mut() {
                *since += dt;
            }
        }
        if !(raw.is_finite() && good_time) {
            return f64::NAN;
        }
        let step = self.since.unwrap_or(1.0);
        if step > 0.0 {
            self.since = Some(0.0);
            lp.update(raw, step).value
        } else {
            f64::NAN
        }
    }
}

/// x0, x1, x2, G_k of one row for `algorithm`.
fn features(algorithm: Algorithm, k: &Alg3Terms<f64>) -> [f64; 4] {
    match algorithm {
        Algorithm::Alg1 => [k.dphi, k.ddphi, 0.0, k.gk],
        Algorithm::Alg2 => [k.dphi, k.ddphi - k.gd, 0.0, k.gk],
        Algorithm::Alg3 => [k.dphi, k.ddphi, k.gd, k.gk],
    }
}

/// One row's residual target y, 1 / dt (gyro target) and whether it enters the cost:
/// `theta - phi` against the truth; against the gyro, the mean of this and the previous
/// row's rate minus phi's difference quotient (`prev`: phi and target of the row before).
fn residual(
    target: Target,
    k: &Alg3Terms<f64>,
    target_value: f64,
    prev: Option<(f64, f64)>,
    settled: bool,
) -> (f64, f64, bool) {
    match target {
        Target::Truth => {
            let th = target_value;
            (th - k.phi, 0.0, settled && th.is_finite())
        }
        Target::Gyro => match prev {
            Some((phip, gp)) if target_value.is_finite() && gp.is_finite() => {
                let inv = 1.0 / k.dt;
                let y = 0.5 * (target_value + gp) - (k.phi - phip) * inv;
                (y, inv, settled && y.is_finite() && inv.is_finite())
            }
            _ => (0.0, 0.0, false),
        },
    }
}
