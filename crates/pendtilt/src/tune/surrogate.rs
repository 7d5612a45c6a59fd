//! The `kf_*` filters' q_angle, q_bias and R against a surrogate of their own error, built
//! from the log without a true angle.
//!
//! The angle + bias filter is linear: its error is its response to the measurement's
//! error (fed as `z`) plus its response to the gyro's error (fed as the input), whatever
//! the tilt. Both are known well enough from the log:
//! - the measurement's error above [`super::reference::CORNER_HZ`] is
//!   `HP(z - integral of the gyro)` ([`super::reference`]): the gyro's integral is the
//!   tilt there but for the gyro's own (small) noise;
//! - the gyro's error is its bias (estimated, [`super::gyro`]), its white noise (density
//!   estimated) and the bias walk (the start's figure), drawn here from a fixed seed.
//!
//! Running the filter on that surrogate (true angle 0) gives its error as a function of
//! its settings; the fit minimises its RMS with the same coordinate search as the
//! likelihood ([`super::search`]) after a coarse grid ([`fit`]). What it cannot see is the measurement's error below the
//! corner (taken as none).
//!
//! Why not the likelihood alone: Algorithm 2's errors are coloured (the differentiator's
//! delay, the pivot offset's term at the motion's own frequency), and a likelihood that
//! takes them as white trusts the measurement too much. On zoo ride 1 (l12 = 60 mm, a
//! 1 Hz sine, alg2 10.7 deg RMS) the likelihood fit left kf_alg2 at 3.55 deg where the
//! oracle grid reached 0.42.
use super::kalman::{innovation_pass, KalmanData, ROUNDS};
use super::reference::{integral, CORNER_HZ};
use super::search::{coordinate_log, Budget};
use pendtilt_core::filters::biquad::LowPass2;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::Sample;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The gyro's error figures the surrogate draws from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroErrors {
    /// Bias \[rad/s\].
    pub bias: f64,
    /// White-noise density \[rad/s/sqrt(Hz)\].
    pub density: f64,
    /// Bias random-walk density \[rad/s/sqrt(s)\].
    pub bias_walk: f64,
}

/// The surrogate: the measurement's error (NaN where `z` is) and the gyro's error per row.
pub struct Surrogate {
    /// Steps \[s\].
    pub dt: Vec<f64>,
    /// Error of the measurement above the corner \[rad\].
    pub z: Vec<f64>,
    /// Surrogate gyro: its error alone \[rad/s\].
    pub gyro: Vec<f64>,
}

impl Surrogate {
    /// Builds it from the rows `samples`, the measurement `z` per row (NaN: none) and the
    /// gyro's figures.
    pub fn new(samples: &[Sample<f64>], z: &[f64], g: &GyroErrors) -> Self {
        Self::with_corner(samples, z, g, CORNER_HZ)
    }

    /// [`Self::new`] with the high-pass corner `corner` \[Hz\].
    pub fn with_corner(samples: &[Sample<f64>], z: &[f64], g: &GyroErrors, corner: f64) -> Self {
        let reference = integral(samples, g.bias);
        let mut lp = LowPass2::new(corner);
        let mut started = false;
        let mut rng = ChaCha8Rng::seed_from_u64(0x5eed);
        let mut walk = 0.0;
        let mut out = Self {
            dt: Vec::with_capacity(z.len()),
            z: Vec::with_capacity(z.len()),
            gyro: Vec::with_capacity(z.len()),
        };
        for ((s, &zk), r) in samples.iter().zip(z).zip(&reference) {
            let dt = if s.dt.is_finite() && s.dt > 0.0 {
                s.dt
            } else {
                0.0
            };
            let d = zk - r;
            let e = if d.is_finite() {
                let h = if started { dt } else { 0.0 };
                started = true;
                d - lp.update(d, h)
            } else {
                f64::NAN
            };
            let n: f64 = StandardNormal.sample(&mut rng);
            let w: f64 = StandardNormal.sample(&mut rng);
            walk += g.bias_walk * dt.sqrt() * w;
            let white = if dt > 0.0 { g.density / dt.sqrt() } else { 0.0 };
            out.dt.push(s.dt);
            out.z.push(e);
            out.gyro.push(g.bias + walk + white * n);
        }
        out
    }

    /// RMS \[rad\] of the filter's angle (its error: the surrogate's tilt is 0) with
    /// q_angle, q_bias of `x[0..2]` and R `x[2]`, rows from `skip`.
    pub fn rms(&self, s: &KalmanSettings<f64>, x: &[f64], skip: usize) -> f64 {
        let at = KalmanSettings {
            q_angle: x[0],
            q_bias: x[1],
            ..*s
        };
        let d = KalmanData {
            dt: &self.dt,
            gyro: &self.gyro,
            z: &self.z,
        };
        let (mut sum, mut n) = (0.0, 0usize);
        innovation_pass(&at, x[2], &d, |k, th, _, _| {
            if k >= skip && th.is_finite() {
                sum += th * th;
                n += 1;
            }
        });
        if n == 0 {
            f64::INFINITY
        } else {
            (sum / n as f64).sqrt()
        }
    }
}

/// The result of a surrogate fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fitted {
    /// q_angle \[rad^2/s\], q_bias \[(rad/s)^2/s\] and R \[rad^2\] fitted.
    pub x: [f64; 3],
    /// The surrogate's RMS \[rad\] at the start.
    pub rms_before: f64,
    /// ... and at the fit.
    pub rms_after: f64,
    /// The mean negative log-likelihood of the filter's innovations on the log at the fit
    /// (set by the caller, which knows the likelihood's data).
    pub nll_at: f64,
}

/// Decades either side of the start each fitted value may take.
pub const DECADES: f64 = 6.0;

/// R of the global grid: the start's times ten to these powers.
const GRID_R: [f64; 9] = [-6.0, -4.5, -3.0, -1.5, 0.0, 1.5, 3.0, 4.5, 6.0];
/// q_angle / R and q_bias / R of the global grid: these powers of ten.
const GRID_RATIO: [i32; 8] = [-12, -10, -8, -6, -4, -2, 0, 2];

/// Cost evaluations of [`fit`]: the start, the grid and the refinement.
pub const EVALUATIONS: u64 = 1
    + (GRID_R.len() * GRID_RATIO.len() * GRID_RATIO.len()) as u64
    + 1
    + ROUNDS as u64 * 3 * super::search::EVALS_PER_PARAMETER;

/// Fits q_angle, q_bias and R (from `s` and `r0`, each within [`DECADES`]) on the
/// surrogate: a grid over R and the ratios q_angle / R, q_bias / R, then [`ROUNDS`]
/// passes of the coordinate search within a decade of the grid's best; the start if
/// nothing lowered the RMS.
///
/// Why a grid first: the filter's steady gains depend on the ratios alone (R against
/// the initial covariance only sets how it starts), so the cost has a long valley along
/// (q_angle, q_bias, R) scaled together, and two basins, trusting the measurement or the
/// gyro. The coordinate search alone, from the defaults, crawled up that valley to
/// R = 1e3 and stopped in the wrong basin: zoo ride 12 (a 0.5 Hz pendulum, a tactical
/// gyro) 0.40 deg, where q_angle = q_bias = 1e-9 with R = 1 gives 0.11.
pub fn fit(
    s: &KalmanSettings<f64>,
    r0: f64,
    sur: &Surrogate,
    skip: usize,
    budget: &mut Budget,
) -> Fitted {
    let x0 = [s.q_angle, s.q_bias, r0];
    let span = 10f64.powf(DECADES);
    let clamp =
        |x: &[f64]| -> [f64; 3] { std::array::from_fn(|i| x[i].clamp(x0[i] / span, x0[i] * span)) };
    let mut cost = |x: &[f64]| sur.rms(s, &clamp(x), skip);
    let before = if budget.tick() {
        cost(&x0)
    } else {
        f64::INFINITY
    };
    let mut best = (before, x0);
    'grid: for lr in GRID_R {
        let r = r0 * 10f64.powf(lr);
        for la in GRID_RATIO {
            for lb in GRID_RATIO {
                if !budget.tick() {
                    break 'grid;
                }
                let x = clamp(&[r * 10f64.powi(la), r * 10f64.powi(lb), r]);
                let c = cost(&x);
                if c < best.0 {
                    best = (c, x);
                }
            }
        }
    }
    let (x, after) = coordinate_log(&mut cost, &best.1, 1.0, ROUNDS, budget);
    let (x, after) = if after < best.0 {
        (clamp(&x), after)
    } else {
        (best.1, best.0)
    };
    let x = if after < before { x } else { x0 };
    Fitted {
        x,
        rms_before: before,
        rms_after: after.min(before),
        nll_at: f64::NAN,
    }
}
