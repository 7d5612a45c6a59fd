//! The output-error cost of a 3-D fit: the Cardan pendulum simulated over the cached
//! drive ([`super::drive`]) with candidate parameters, against the measured encoders.
//!
//! The joint equations are the core's normalised MODEL.md 7.3 ([`CardanParams`], the
//! ones ekf3d predicts with), integrated with the simulator's RK4 step
//! ([`crate::sim::planar::integrator::rk4_step`]), one step per sample interval on the nodes the
//! drive keeps. The residuals are `phi_sim + offset - phi_measured` per axis, two per used
//! row (rows whose encoders are missing are simulated but not compared).
use nalgebra::{SMatrix, SVector};
use pendtilt_core::spatial::cardan::{CardanParams, Joints};
use rayon::prelude::*;

use super::drive::{self, Log3dColumns, Node};
use super::{Fit3dSettings, NP};
use crate::fit::lm::{Gradient, LeastSquares, Normal};
use crate::fit::problem::MIN_ROWS;
use crate::fit::FitError;
use crate::sim::planar::integrator::{rk4_step, Node as RkNode};

/// The parameter vector of a 3-D fit: a_x, a_y, b_x + b_ring, b_y, c_z, and the encoder
/// offsets of phi_x and phi_y.
pub type Params = SVector<f64, NP>;

/// Largest joint angle the simulation may reach before it counts as diverged \[rad\]
/// (80 deg: the Cardan joint locks at 90).
const MAX_SWING: f64 = 1.4;

/// The cached data of a 3-D output-error fit.
#[derive(Debug, Clone)]
pub struct CardanProblem {
    nodes: Vec<Node>,
    /// Time step to the next row \[s\].
    dt: Vec<f64>,
    /// Measured (phi_x, phi_y) \[rad\].
    phi: Vec<[f64; 2]>,
    used: Vec<bool>,
    count: usize,
    /// Start state (a, b, a', b') from the encoders.
    start: [f64; 4],
    /// The held parameters (b_z, b_ring, c_x, c_y, gravity) and the fitted ones' start.
    base: CardanParams<f64>,
    /// Relative (or, for c_z and the offsets, absolute) finite-difference steps.
    steps: [f64; NP],
    /// Two-sided noise densities of the drive: the force along body (x, y) over g
    /// \[1/sqrt(Hz)\] and the rate about body (x, y) \[rad/s/sqrt(Hz)\] ([`noise_power`]).
    noise: ([f64; 2], [f64; 2]),
}

/// The power the drive's white noise adds to the simulated encoders, per row, summed over
/// both axes \[rad^2\]: linearised about the hanging pendulum, a force noise of density
/// d_f (over g) moves the outer joint by d_f^2 / (2 a_x), and a rate noise of density d_w
/// by d_w^2 B / (2 a_x) (B = b_x + b_ring; the inner joint likewise with a_y, b_y). The
/// measured encoders do not carry it (the real pendulum never felt the sensors' noise), so
/// without this term the least-squares fit buys it down: damping high, inertia low.
pub fn noise_power(p: &Params, force: [f64; 2], rate: [f64; 2]) -> f64 {
    let axis = |a: f64, b: f64, df: f64, dw: f64| (df * df + dw * dw * b) / (2.0 * a);
    // The outer joint feels the force along y, the inner one along x.
    axis(p[0], p[2], force[1], rate[0]) + axis(p[1], p[3], force[0], rate[1])
}

/// phi and phi' at the first row: a straight line fitted to the encoders over the first
/// 50 ms (at least 3 rows), so that the simulation starts where the pendulum was.
fn encoder_start(t: &[f64], phi: &[[f64; 2]]) -> [f64; 4] {
    let mut rows: Vec<usize> = (0..t.len())
        .take_while(|&k| k < 3 || t[k] - t[0] <= 0.05)
        .filter(|&k| phi[k][0].is_finite() && phi[k][1].is_finite())
        .collect();
    rows.truncate(200);
    let m = rows.len() as f64;
    if m < 2.0 {
        let p = phi.iter().find(|p| p[0].is_finite() && p[1].is_finite());
        let p = p.copied().unwrap_or([0.0; 2]);
        return [-p[0], -p[1], 0.0, 0.0];
    }
    let tm = rows.iter().map(|&k| t[k] - t[0]).sum::<f64>() / m;
    let stt = rows
        .iter()
        .map(|&k| (t[k] - t[0] - tm).powi(2))
        .sum::<f64>();
    let line = |i: usize| {
        let ym = rows.iter().map(|&k| phi[k][i]).sum::<f64>() / m;
        let sty = rows
            .iter()
            .map(|&k| (t[k] - t[0] - tm) * (phi[k][i] - ym))
            .sum::<f64>();
        let slope = if stt > 0.0 { sty / stt } else { 0.0 };
        (ym - slope * tm, slope)
    };
    let ((x0, xd), (y0, yd)) = (line(0), line(1));
    [-x0, -y0, -xd, -yd]
}

impl CardanProblem {
    /// Caches the drive of the first usable rows of `log` (finite increasing time) for the
    /// target of `s`, with the held parameters of `start`; the first `s.skip` seconds are
    /// left out of the cost while the start state's error decays.
    pub fn new(
        log: &Log3dColumns,
        start: &CardanParams<f64>,
        accel_at: [f64; 3],
        s: &Fit3dSettings,
    ) -> Result<Self, FitError> {
        let n = log.usable_rows();
        if n < MIN_ROWS {
            return Err(FitError::TooFewSamples {
                have: n,
                need: MIN_ROWS,
            });
        }
        let g = start.gravity;
        let r_held = [
            start.c[0] * g - accel_at[0],
            start.c[1] * g - accel_at[1],
            -accel_at[2],
        ];
        let nodes = drive::nodes(log, n, s, r_held, g)?;
        let t = &log.t[..n];
        let dt: Vec<f64> = (0..n)
            .map(|k| if k + 1 < n { t[k + 1] - t[k] } else { 0.0 })
            .collect();
        let phi = log.phi[..n].to_vec();
        let used: Vec<bool> = (0..n)
            .map(|k| t[k] - t[0] >= s.skip && phi[k][0].is_finite() && phi[k][1].is_finite())
            .collect();
        let count = used.iter().filter(|&&u| u).count();
        if count < MIN_ROWS {
            return Err(FitError::TooFewSamples {
                have: count,
                need: MIN_ROWS,
            });
        }
        let (force, rate) = match s.noise {
            Some(d) => (
                [d.accel[0] / g, d.accel[1] / g],
                if s.target == crate::fit::Target::Gyro {
                    [d.gyro[0], d.gyro[1]]
                } else {
                    [0.0; 2]
                },
            ),
            None => ([0.0; 2], [0.0; 2]),
        };
        let steps = [1e-5, 1e-5, 1e-5, 1e-5, 1e-5 * super::C_SCALE, 1e-6, 1e-6];
        Ok(Self {
            nodes,
            dt,
            start: encoder_start(t, &phi),
            phi,
            used,
            count,
            base: *start,
            steps,
            noise: (force, rate),
        })
    }

    /// Rows compared (each gives two residuals).
    pub fn rows(&self) -> usize {
        self.count
    }

    /// The pendulum of parameter vector `p`: the fitted values put into the held ones.
    pub fn cardan(&self, p: &Params) -> CardanParams<f64> {
        CardanParams {
            a_x: p[0],
            a_y: p[1],
            b_x: p[2] - self.base.b_ring,
            b_y: p[3],
            c: [self.base.c[0], self.base.c[1], p[4]],
            ..self.base
        }
    }

    /// Simulates the pendulum of `p` and hands each used row's residuals (phi_x, phi_y) to
    /// `sink`; returns their sum of squares, NaN when `p` is no pendulum or the simulation
    /// leaves the joint's range.
    pub fn simulate(&self, p: &Params, mut sink: impl FnMut([f64; 2])) -> f64 {
        let c = self.cardan(p);
        if !(c.a_x >= 0.0 && c.a_y >= 0.0 && c.b_x > 0.0 && c.b_y > 0.0)
            || p.iter().any(|v| !v.is_finite())
        {
            return f64::NAN;
        }
        let rz = p[4] * c.gravity;
        let rhs = |nd: &Node, y: [f64; 4]| -> [f64; 4] {
            let f = core::array::from_fn(|i| nd.f0[i] + rz * nd.fz[i]);
            let s = Joints {
                a: y[0],
                b: y[1],
                a_dot: y[2],
                b_dot: y[3],
            };
            let [add, bdd] = c.joint_accelerations(&s, nd.w, nd.wd, f);
            [y[2], y[3], add, bdd]
        };
        let mut y = self.start;
        let mut sum = 0.0;
        let n = self.phi.len();
        for k in 0..n {
            if self.used[k] {
                let r = [-y[0] + p[5] - self.phi[k][0], -y[1] + p[6] - self.phi[k][1]];
                sink(r);
                sum += r[0] * r[0] + r[1] * r[1];
            }
            if k + 1 == n {
                break;
            }
            let nodes = &self.nodes[2 * k..=2 * k + 2];
            y = rk4_step(y, self.dt[k], |node, y| match node {
                RkNode::Start => rhs(&nodes[0], y),
                RkNode::Mid => rhs(&nodes[1], y),
                RkNode::End => rhs(&nodes[2], y),
            });
            if !(y[0].abs() < MAX_SWING && y[1].abs() < MAX_SWING && y[2].is_finite()) {
                return f64::NAN;
            }
        }
        if sum.is_finite() {
            sum
        } else {
            f64::NAN
        }
    }

    /// The residuals of `p`, two per used row.
    pub fn residuals(&self, p: &Params) -> (Vec<f64>, f64) {
        let mut out = Vec::with_capacity(2 * self.count);
        let sum = self.simulate(p, |r| out.extend_from_slice(&r));
        (out, sum)
    }

    /// The objective at `p`: the sum of squares of [`Self::simulate`] less the drive's
    /// expected noise power over the used rows ([`noise_power`]).
    pub fn objective(&self, p: &Params) -> f64 {
        self.simulate(p, |_| {}) - self.noise_penalty(p)
    }

    /// The drive's expected noise power over the used rows at `p` \[rad^2\].
    pub fn noise_penalty(&self, p: &Params) -> f64 {
        let (f, w) = self.noise;
        if f == [0.0; 2] && w == [0.0; 2] {
            return 0.0;
        }
        self.count as f64 * noise_power(p, f, w)
    }

    /// RMS residual per axis (phi_x, phi_y) \[rad\].
    pub fn rms_per_axis(&self, p: &Params) -> [f64; 2] {
        let mut s = [0.0; 2];
        self.simulate(p, |r| {
            s[0] += r[0] * r[0];
            s[1] += r[1] * r[1];
        });
        s.map(|v| (v / self.count as f64).sqrt())
    }

    /// `(J'J, J'r, sum r^2)` at `p`: the dynamic parameters' columns by central differences
    /// (two simulations each, run in parallel), the offsets' exactly (1 on their axis).
    pub fn normal_equations(&self, p: &Params) -> Normal<NP> {
        let (r0, sum) = self.residuals(p);
        let cols: Vec<Option<Vec<f64>>> = (0..5)
            .into_par_iter()
            .map(|j| {
                let h = self.steps[j] * if j < 4 { p[j].abs().max(1e-9) } else { 1.0 };
                let (mut pp, mut pm) = (*p, *p);
                pp[j] += h;
                pm[j] -= h;
                let ((rp, sp), (rm, sm)) = (self.residuals(&pp), self.residuals(&pm));
                (sp.is_finite() && sm.is_finite()).then(|| {
                    rp.iter()
                        .zip(&rm)
                        .map(|(a, b)| (a - b) / (2.0 * h))
                        .collect()
                })
            })
            .collect();
        if !sum.is_finite() || cols.iter().any(|c| c.is_none()) {
            return (SMatrix::zeros(), SVector::zeros(), f64::NAN);
        }
        let cols: Vec<Vec<f64>> = cols.into_iter().flatten().collect();
        let mut jtj = SMatrix::<f64, NP, NP>::zeros();
        let mut jtr = SVector::<f64, NP>::zeros();
        let mut j = SVector::<f64, NP>::zeros();
        for (i, &r) in r0.iter().enumerate() {
            for (c, col) in cols.iter().enumerate() {
                j[c] = col[i];
            }
            // Residual i is phi_x's (even) or phi_y's (odd): its offset's column is 1.
            j[5] = if i % 2 == 0 { 1.0 } else { 0.0 };
            j[6] = 1.0 - j[5];
            jtj += j * j.transpose();
            jtr += j * r;
        }
        // Half the gradient of the noise penalty (the objective is sum r^2 - penalty).
        let pen = self.noise_penalty(p);
        if pen != 0.0 {
            for j in 0..4 {
                let h = 1e-6 * p[j].abs().max(1e-12);
                let (mut pp, mut pm) = (*p, *p);
                pp[j] += h;
                pm[j] -= h;
                jtr[j] -= 0.25 * (self.noise_penalty(&pp) - self.noise_penalty(&pm)) / h;
            }
        }
        (jtj, jtr, sum - pen)
    }
}

impl LeastSquares<NP> for CardanProblem {
    const LINEARISE_PASSES: usize = 11;

    fn residual_count(&self) -> usize {
        2 * self.count
    }

    fn linearise(&self, p: &Params) -> Normal<NP> {
        self.normal_equations(p)
    }

    fn trial(&self, q: &Params) -> (f64, Option<Gradient<NP>>) {
        (self.objective(q), None)
    }
}
