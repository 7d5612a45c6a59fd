//! Output-error cost (beyond the paper): simulate the pendulum from the true angle with
//! candidate a, b and compare the simulated encoder reading with the measured one.
//!
//! # Why
//! Eq (23) compares the inverted estimate `phi + asin(a phi' + b (phi'' - theta''))` with the
//! true angle. On a vibrating body phi'' carries a vibration-driven part that the estimate
//! amplifies by b w^2; the least-squares fit then shrinks b to keep that part small (an
//! errors-in-variables bias: measured on the `scooter` scenario, b 40-70 % low). Run the
//! other way, the vibration is only a small process disturbance of the simulated pendulum
//! and the fit is unbiased.
//!
//! # The model
//! With beta = theta - phi (the pendulum's absolute angle), the paper's Eq (18) (l12 = 0)
//! `b phi'' + a phi' + sin(phi - theta) = b theta''` becomes
//!
//! ```text
//! b beta'' = a (theta' - beta') - sin(beta)
//! ```
//!
//! driven only by theta'. With [`OutputSettings::accel`] the restoring term is the
//! accelerometer's specific force instead of gravity alone (MODEL.md section 2, pivot
//! fixed to the body's accelerometer): `b beta'' = a (theta' - beta') - (f_x cos phi -
//! f_y sin phi) / g`, which makes the floor's translational vibration a known input.
//! Without it that vibration is a process disturbance that still leaves b 8-13 % low on the
//! 60 s `scooter` ride (its rectified effect stiffens the pendulum); with it a and b come
//! out within 1 % (seeds 1, 3, 7). theta' is the central difference of the true angle after a
//! zero-phase (forward-backward) first-order low-pass at [`OutputSettings::smoothing_hz`]
//! (offline, so no delay). The ODE is integrated with RK4 at the log's own time steps
//! (theta' linear in between), from beta = theta_0 - phi_0, beta' = 0; the first
//! [`OutputSettings::skip`] seconds are left out of the cost while that start decays.
//! The residual is `beta_sim - (theta - phi)`, i.e. `phi_measured - phi_simulated`.
//!
//! Minimised over (a, b) by Levenberg-Marquardt with a central finite-difference Jacobian
//! ([`fit_output`]), or by the paper's Newton (Eqs 24-28) on the RMS of the residual.
use nalgebra::{Matrix2, Vector2};

use super::lm::{minimise, Gradient, LeastSquares, LmIteration, LmOutcome, Normal};
use super::problem::MIN_ROWS;
use super::{FitError, LmSettings};
use pendtilt_core::Sample;

/// Settings of the output-error cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputSettings {
    /// Cutoff of the zero-phase low-pass on the true angle before it is differentiated
    /// \[Hz\]. Default 20 Hz (well above the pendulum's ~2 Hz, well below the encoder's
    /// quantisation noise turned into rate).
    pub smoothing_hz: f64,
    /// Seconds at the start left out of the cost while the simulated pendulum forgets its
    /// start state. Default 1 s.
    pub skip: f64,
    /// Drive the simulated pendulum with the accelerometer's specific force (columns `ax`,
    /// `ay`, body axes, taken as felt at the pendulum's pivot) instead of gravity alone:
    /// `b beta'' = a (theta' - beta') - (f_x cos phi - f_y sin phi) / g` (MODEL.md
    /// section 2), so that the floor's translational vibration is an input, not a
    /// disturbance. Default false (but see `auto_accel`).
    pub accel: bool,
    /// Drive with the accelerometer also when `accel` is false, if the log has finite
    /// `ax`, `ay` and vibrates: their high-frequency RMS ([`vibration_rms`]) is above
    /// [`VIBRATION_RMS`]. Default true. (Measured, seed 1: on the 60 s `scooter` ride
    /// (3.4 m/s^2) the drive takes b from 12.9 % low to within 0.2 %; on logs without
    /// vibration (0.12-0.16 m/s^2, the sensor's noise) it is not used, because there the
    /// accelerometer's bias outweighs what it adds: a sigmoid's a came out 31 % high.)
    pub auto_accel: bool,
}

/// High-frequency RMS of the accelerometer (m/s^2, larger of `ax`, `ay`) above which the
/// output cost is driven by the accelerometer by default: 0.5 m/s^2, about four times the
/// simulated sensor's own noise (0.12 m/s^2) and a seventh of the `scooter` ride's 3.4.
pub const VIBRATION_RMS: f64 = 0.5;

/// The vibration of a log: the RMS of `ax` and of `ay` minus their centred 101-sample
/// moving average (what lies above about 10 Hz at 1 kHz), the larger of the two (m/s^2).
/// None when the log has fewer than 202 rows or a non-finite `ax`/`ay`.
pub fn vibration_rms(samples: &[Sample<f64>]) -> Option<f64> {
    const W: usize = 50;
    let n = samples.len();
    if n < 4 * W + 2 || !samples.iter().all(|x| x.ax.is_finite() && x.ay.is_finite()) {
        return None;
    }
    let hf = |get: &dyn Fn(&Sample<f64>) -> f64| {
        let mut prefix = Vec::with_capacity(n + 1);
        prefix.push(0.0);
        for x in samples {
            prefix.push(prefix.last().copied().unwrap_or(0.0) + get(x));
        }
        let mut sum = 0.0;
        for k in W..n - W {
            let mean = (prefix[k + W + 1] - prefix[k - W]) / (2 * W + 1) as f64;
            sum += (get(&samples[k]) - mean).powi(2);
        }
        (sum / (n - 2 * W) as f64).sqrt()
    };
    Some(hf(&|x| x.ax).max(hf(&|x| x.ay)))
}

impl Default for OutputSettings {
    fn default() -> Self {
        Self {
            smoothing_hz: 20.0,
            skip: 1.0,
            accel: false,
            auto_accel: true,
        }
    }
}

/// The cached data of an output-error fit.
#[derive(Debug, Clone)]
pub struct OutputProblem {
    /// Time steps to the next row.
    dt: Vec<f64>,
    /// theta' (smoothed true angle, central difference).
    omega: Vec<f64>,
    /// theta - phi (measured).
    y: Vec<f64>,
    /// Smoothed theta (accelerometer drive only).
    theta: Vec<f64>,
    /// Specific force / g, body axes (accelerometer drive only; empty otherwise).
    f: Vec<[f64; 2]>,
    used: Vec<bool>,
    count: usize,
    vibration: Option<f64>,
}

/// The leading run of complete rows (t, phi and the truth finite) with increasing time.
fn usable_rows(samples: &[Sample<f64>], truth: &[f64]) -> usize {
    samples
        .iter()
        .zip(truth)
        .enumerate()
        .take_while(|(n, (x, th))| {
            x.dt.is_finite() && x.phi.is_finite() && th.is_finite() && (*n == 0 || x.dt > 0.0)
        })
        .count()
}

/// `x` through a first-order low-pass at `hz` forward then backward (zero phase);
/// `step[k]` is the time from row k - 1 to row k (`step[0]` unused).
fn zero_phase_low_pass(x: &[f64], step: &[f64], hz: f64) -> Vec<f64> {
    let n = x.len();
    let wc = 2.0 * std::f64::consts::PI * hz;
    let mut th = x.to_vec();
    for k in 1..n {
        let al = 1.0 - (-wc * step[k]).exp();
        th[k] = th[k - 1] + al * (th[k] - th[k - 1]);
    }
    for k in (0..n.saturating_sub(1)).rev() {
        let al = 1.0 - (-wc * step[k + 1]).exp();
        th[k] = th[k + 1] + al * (th[k] - th[k + 1]);
    }
    th
}

/// The accelerometer in units of g, per row: the drive of the accelerometer-driven
/// simulation; an error if a reading is missing.
fn accel_drive(samples: &[Sample<f64>]) -> Result<Vec<[f64; 2]>, FitError> {
    let g = pendtilt_core::PhysicalParams::<f64>::default().gravity;
    let f: Vec<[f64; 2]> = samples.iter().map(|x| [x.ax / g, x.ay / g]).collect();
    if !f.iter().all(|v| v[0].is_finite() && v[1].is_finite()) {
        return Err(FitError::MissingColumn("ax` and `ay"));
    }
    Ok(f)
}

impl OutputProblem {
    /// Caches theta' and theta - phi. Rows whose t, phi or truth is not finite end the
    /// usable log there (the simulation cannot cross a gap); a log needs a `theta`.
    pub fn new(
        samples: &[Sample<f64>],
        truth: Option<&[f64]>,
        s: &OutputSettings,
    ) -> Result<Self, FitError> {
        let truth = truth.ok_or(FitError::MissingColumn("theta"))?;
        if truth.len() != samples.len() {
            return Err(FitError::BadSettings(format!(
                "{} truth values for {} samples",
                truth.len(),
                samples.len()
            )));
        }
        if !(s.smoothing_hz.is_finite() && s.smoothing_hz > 0.0 && s.skip >= 0.0) {
            return Err(FitError::BadSettings(
                "output cost: smoothing_hz must be > 0 and skip >= 0".into(),
            ));
        }
        let n = usable_rows(samples, truth);
        if n < MIN_ROWS {
            return Err(FitError::TooFewSamples {
                have: n,
                need: MIN_ROWS,
            });
        }
        // step[k] = t_k - t_(k-1) (step[0] unused).
        let step: Vec<f64> = samples[..n].iter().map(|x| x.dt).collect();
        let th = zero_phase_low_pass(&truth[..n], &step, s.smoothing_hz);
        let omega: Vec<f64> = (0..n)
            .map(|k| {
                let (i, j) = (k.saturating_sub(1), (k + 1).min(n - 1));
                (th[j] - th[i]) / step[i + 1..=j].iter().sum::<f64>()
            })
            .collect();
        let dt: Vec<f64> = (0..n)
            .map(|k| if k + 1 < n { step[k + 1] } else { 0.0 })
            .collect();
        let y: Vec<f64> = (0..n).map(|k| truth[k] - samples[k].phi).collect();
        let vibration = vibration_rms(&samples[..n]);
        let accel = s.accel || (s.auto_accel && vibration.is_some_and(|v| v > VIBRATION_RMS));
        let f = if accel {
            accel_drive(&samples[..n])?
        } else {
            Vec::new()
        };
        let mut elapsed = 0.0;
        let used: Vec<bool> = (0..n)
            .map(|k| {
                if k > 0 {
                    elapsed += step[k];
                }
                elapsed >= s.skip
            })
            .collect();
        let count = used.iter().filter(|&&u| u).count();
        if count < MIN_ROWS {
            return Err(FitError::TooFewSamples {
                have: count,
                need: MIN_ROWS,
            });
        }
        Ok(Self {
            dt,
            omega,
            theta: if accel { th } else { Vec::new() },
            f,
            y,
            used,
            count,
            vibration,
        })
    }

    /// Residuals in the cost.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether the simulation is driven by the accelerometer.
    pub fn accel_driven(&self) -> bool {
        !self.f.is_empty()
    }

    /// The log's [`vibration_rms`] (m/s^2), when it has `ax`, `ay`.
    pub fn vibration_rms(&self) -> Option<f64> {
        self.vibration
    }

    /// True when no residual enters the cost (never after a successful
    /// [`OutputProblem::new`]).
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Simulates beta for (a, b) and writes the used residuals `beta_sim - (theta - phi)`
    /// into `out` (cleared first). Returns their sum of squares (NaN if a, b are not
    /// finite and > 0, or the simulation diverges).
    pub fn residuals(&self, a: f64, b: f64, out: &mut Vec<f64>) -> f64 {
        out.clear();
        self.simulate(a, b, |r| out.push(r))
    }

    /// The sum of squares of [`OutputProblem::residuals`] without keeping them.
    pub fn sum_of_squares(&self, a: f64, b: f64) -> f64 {
        self.simulate(a, b, |_| {})
    }

    /// Simulates beta for (a, b), hands each used residual to `sink` in row order and
    /// returns their sum of squares (NaN as [`OutputProblem::residuals`]).
    fn simulate(&self, a: f64, b: f64, mut sink: impl FnMut(f64)) -> f64 {
        if !(a.is_finite() && b.is_finite() && a >= 0.0 && b > 0.0) {
            return f64::NAN;
        }
        let inv_b = 1.0 / b;
        let drive = !self.f.is_empty();
        // (w, theta, f_x, f_y) at a node.
        let f = |beta: f64, v: f64, e: [f64; 4]| {
            let restoring = if drive {
                let phi = e[1] - beta;
                e[2] * phi.cos() - e[3] * phi.sin()
            } else {
                beta.sin()
            };
            (a * (e[0] - v) - restoring) * inv_b
        };
        let node = |k: usize| {
            if drive {
                [self.omega[k], self.theta[k], self.f[k][0], self.f[k][1]]
            } else {
                [self.omega[k], 0.0, 0.0, 0.0]
            }
        };
        let mut beta = self.y[0];
        let mut v = 0.0;
        let mut sum = 0.0;
        let n = self.y.len();
        for k in 0..n {
            if self.used[k] {
                let r = beta - self.y[k];
                sink(r);
                sum += r * r;
            }
            if k + 1 == n {
                break;
            }
            let h = self.dt[k];
            let (w0, w1) = (node(k), node(k + 1));
            let wm = [
                0.5 * (w0[0] + w1[0]),
                0.5 * (w0[1] + w1[1]),
                0.5 * (w0[2] + w1[2]),
                0.5 * (w0[3] + w1[3]),
            ];
            let k1b = v;
            let k1v = f(beta, v, w0);
            let k2b = v + 0.5 * h * k1v;
            let k2v = f(beta + 0.5 * h * k1b, k2b, wm);
            let k3b = v + 0.5 * h * k2v;
            let k3v = f(beta + 0.5 * h * k2b, k3b, wm);
            let k4b = v + h * k3v;
            let k4v = f(beta + h * k3b, k4b, w1);
            beta += h / 6.0 * (k1b + 2.0 * k2b + 2.0 * k3b + k4b);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        if sum.is_finite() {
            sum
        } else {
            f64::NAN
        }
    }

    /// RMS of the residual phi_measured - phi_simulated \[rad\].
    pub fn cost(&self, a: f64, b: f64) -> f64 {
        let mut r = Vec::with_capacity(self.count);
        (self.residuals(a, b, &mut r) / self.count as f64).sqrt()
    }

    /// `(J'J, J'r, sum r^2)` at (a, b), J by central differences (relative step 1e-5).
    /// Five simulations.
    pub fn normal_equations(&self, a: f64, b: f64) -> (Matrix2<f64>, Vector2<f64>, f64) {
        let mut r0 = Vec::with_capacity(self.count);
        let sum = self.residuals(a, b, &mut r0);
        let mut cols = [Vec::new(), Vec::new()];
        let mut rp = Vec::with_capacity(self.count);
        let mut rm = Vec::with_capacity(self.count);
        for (j, col) in cols.iter_mut().enumerate() {
            let p = [a, b];
            let h = 1e-5 * p[j].abs().max(1e-9);
            let (mut pp, mut pm) = (p, p);
            pp[j] += h;
            pm[j] -= h;
            let sp = self.residuals(pp[0], pp[1], &mut rp);
            let sm = self.residuals(pm[0], pm[1], &mut rm);
            if !(sp.is_finite() && sm.is_finite()) {
                return (Matrix2::zeros(), Vector2::zeros(), f64::NAN);
            }
            *col = rp
                .iter()
                .zip(&rm)
                .map(|(x, y)| (x - y) / (2.0 * h))
                .collect();
        }
        let mut jtj = Matrix2::zeros();
        let mut jtr = Vector2::zeros();
        for (k, &r) in r0.iter().enumerate() {
            let j = Vector2::new(cols[0][k], cols[1][k]);
            jtj += j * j.transpose();
            jtr += j * r;
        }
        (jtj, jtr, sum)
    }
}

impl LeastSquares<2> for OutputProblem {
    /// The simulation at (a, b) and four around it.
    const LINEARISE_PASSES: usize = 5;

    fn residual_count(&self) -> usize {
        self.len()
    }

    fn linearise(&self, p: &Vector2<f64>) -> Normal<2> {
        self.normal_equations(p[0], p[1])
    }

    fn trial(&self, q: &Vector2<f64>) -> (f64, Option<Gradient<2>>) {
        (self.sum_of_squares(q[0], q[1]), None)
    }
}

/// One iteration of [`fit_output`] (evaluations are simulations run).
pub type OutputIteration = LmIteration<2>;

/// What [`fit_output`] found: (a, b) (evaluations are simulations run).
pub type OutputOutcome = LmOutcome<2>;

/// Levenberg-Marquardt on the output-error cost from (a0, b0): the loop of [`super::lm`]
/// ([`minimise`]) with its settings and acceptance rule.
pub fn fit_output(
    problem: &OutputProblem,
    a0: f64,
    b0: f64,
    s: &LmSettings,
    on_iteration: impl FnMut(&OutputIteration),
) -> Result<OutputOutcome, FitError> {
    minimise(
        problem,
        &Vector2::new(a0, b0),
        &[true, true],
        s,
        on_iteration,
    )
}
