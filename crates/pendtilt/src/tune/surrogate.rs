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
//!   estimated) and the bias walk (the start's figure or, if larger, the log's upper
//!   bound [`walk_bound`]), drawn here from a fixed seed.
//!
//! Running the filter on that surrogate (true angle 0) gives its error as a function of
//! its settings; the fit minimises its RMS with the same coordinate search as the
//! likelihood ([`super::search`]) after a coarse grid ([`fit`]). What it cannot see is
//! Algorithm 2's error below the corner (taken as none); the accelerometer's there is
//! taken as its difference from Algorithm 2 ([`Surrogate::against`]).
//!
//! Why not the likelihood alone: Algorithm 2's errors are coloured (the differentiator's
//! delay, the pivot offset's term at the motion's own frequency), and a likelihood that
//! takes them as white trusts the measurement too much. On zoo ride 1 (l12 = 60 mm, a
//! 1 Hz sine, alg2 10.7 deg RMS) the likelihood fit left kf_alg2 at 3.55 deg where the
//! oracle grid reached 0.42.
use super::kalman::{pass, ROUNDS};
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

/// Segments [`walk_bound`] splits the log into.
pub const WALK_SEGMENTS: usize = 4;

/// An upper bound of the gyro's bias walk \[rad/s/sqrt(s)\] from the log: the bias seen
/// in each of [`WALK_SEGMENTS`] equal segments after row `skip` (the slope of `z` minus
/// the gyro's integral less `bias`, fitted to their one-second means), and the mean
/// square change between neighbours over `26 L / 35`: the variance of the change, per
/// unit walk, between two neighbouring stretches of `L` seconds of a random walk's mean
/// weighted as a fitted slope weighs it (`6 t (L - t) / L^3`; `2 L / 3` for a plain
/// mean). `None` with fewer than 3 one-second means per segment.
///
/// An upper bound: `z`'s own slow error changes the slopes too, and 40 s hold three
/// changes. The surrogate draws the walk at the larger of this and the start's figure
/// ([`super::tune`]): a surrogate whose gyro is steadier than the log's fixes the bias.
/// Zoo ride 14 (consumer gyro, walk 4.1e-4): the start's 1e-4 left kf_alg2 at
/// 0.133 deg, the bound (2.6e-4) at 0.081, the oracle 0.057; on a tactical gyro with a
/// slow pendulum (ride 12, walk 7e-6, bound 3.8e-4) it costs 0.109 -> 0.133.
pub fn walk_bound(samples: &[Sample<f64>], z: &[f64], bias: f64, skip: usize) -> Option<f64> {
    let reference = integral(samples, bias);
    let (mut t, mut m) = (Vec::new(), Vec::new());
    let (mut clock, mut start, mut sum, mut n) = (0.0, f64::NAN, 0.0, 0usize);
    for (k, ((s, zk), r)) in samples.iter().zip(z).zip(&reference).enumerate() {
        if s.dt.is_finite() && s.dt > 0.0 {
            clock += s.dt;
        }
        if k < skip {
            continue;
        }
        if start.is_nan() {
            start = clock;
        }
        if clock - start >= 1.0 {
            if n > 0 {
                t.push(start + 0.5);
                m.push(sum / n as f64);
            }
            (start, sum, n) = (clock, 0.0, 0);
        }
        let d = zk - r;
        if d.is_finite() {
            sum += d;
            n += 1;
        }
    }
    let per = t.len() / WALK_SEGMENTS;
    if per < 3 {
        return None;
    }
    let slopes: Vec<f64> = t
        .chunks_exact(per)
        .zip(m.chunks_exact(per))
        .map(|(a, b)| slope(a, b))
        .collect();
    let changes: Vec<f64> = slopes.windows(2).map(|w| (w[1] - w[0]).powi(2)).collect();
    let mean = changes.iter().sum::<f64>() / changes.len() as f64;
    let w = (mean / (26.0 * per as f64 / 35.0)).sqrt();
    w.is_finite().then_some(w)
}

/// Least-squares slope of `y` against `x`.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    x.iter()
        .zip(y)
        .map(|(a, b)| (a - mx) * (b - my))
        .sum::<f64>()
        / sxx
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
    /// gyro's figures, `z`'s error taken as none below [`CORNER_HZ`].
    pub fn new(samples: &[Sample<f64>], z: &[f64], g: &GyroErrors) -> Self {
        Self::against(samples, z, z, g)
    }

    /// [`Self::new`] with `z`'s error below the corner taken as its difference from
    /// `anchor` there: the error against a tilt that is the gyro's integral above
    /// [`CORNER_HZ`] and `anchor` below it (a complementary filter of the two). With
    /// `anchor = z` that is `HP(z - integral)`; the accelerometer's surrogates are anchored
    /// on Algorithm 2, so that they see the body's own acceleration, which the
    /// accelerometer reads below the corner and the pendulum's model does not: without it
    /// kf_fused, its accelerometer R fitted, trusted the accelerometer on a ride without
    /// vibration and was 3.2 times kf_alg2 (0.080 against 0.025 deg).
    pub fn against(samples: &[Sample<f64>], z: &[f64], anchor: &[f64], g: &GyroErrors) -> Self {
        let reference = integral(samples, g.bias);
        let mut lp = LowPass2::new(CORNER_HZ);
        // At rest on the first 1 / corner seconds' mean, not on the first reading: the
        // surrogate then starts on the log's own start error, which the filter keeps
        // (x0 = z0) as long as its R and Q say. Started on the first reading it began at 0
        // and never showed it: tuned on the quick start's ride, kf_accel's R went to 236
        // rad^2 and the filter kept its first reading, 10 deg off, for the whole minute
        // (5.08 deg RMS; untuned 1.85).
        let mut low = start_mean(samples, anchor, &reference, 1.0 / CORNER_HZ);
        let mut started = false;
        let mut rng = ChaCha8Rng::seed_from_u64(0x5eed);
        let mut walk = 0.0;
        let mut out = Self {
            dt: Vec::with_capacity(z.len()),
            z: Vec::with_capacity(z.len()),
            gyro: Vec::with_capacity(z.len()),
        };
        for (((s, &zk), &ak), r) in samples.iter().zip(z).zip(anchor).zip(&reference) {
            let dt = if s.dt.is_finite() && s.dt > 0.0 {
                s.dt
            } else {
                0.0
            };
            let d = ak - r;
            if d.is_finite() {
                if !started {
                    lp.update(low, 0.0);
                    started = true;
                } else if dt > 0.0 {
                    low = lp.update(d, dt);
                }
            }
            // NaN only if the anchor has no value at all.
            let e = zk - (r + low);
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
    /// q_angle, q_bias of `x[0..2]` and R `x[2]`, rows from `skip` ([`rms_of`]).
    pub fn rms(&self, s: &KalmanSettings<f64>, x: &[f64], skip: usize) -> f64 {
        let at = KalmanSettings {
            q_angle: x[0],
            q_bias: x[1],
            ..*s
        };
        rms_of(&at, &[(self, x[2])], skip)
    }
}

/// RMS \[rad\] of the error of the filter `s` fed by the surrogates `parts` in turn, each
/// with its R (`kf_fused`: the accelerometer's and Algorithm 2's, drawn with the same gyro
/// errors; the gyro is taken from the first), rows from `skip`.
pub fn rms_of(s: &KalmanSettings<f64>, parts: &[(&Surrogate, f64)], skip: usize) -> f64 {
    let Some(&(lead, _)) = parts.first() else {
        return f64::INFINITY;
    };
    let zs: Vec<(&[f64], f64)> = parts.iter().map(|(p, r)| (p.z.as_slice(), *r)).collect();
    let (mut sum, mut n) = (0.0, 0usize);
    pass(s, &lead.dt, &lead.gyro, &zs, |k, th, _, _| {
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

/// Mean of `z - reference` over the first `span` seconds from its first finite value
/// (NaN if there is none).
fn start_mean(samples: &[Sample<f64>], z: &[f64], reference: &[f64], span: f64) -> f64 {
    let (mut clock, mut sum, mut n) = (f64::NAN, 0.0, 0usize);
    for ((s, zk), r) in samples.iter().zip(z).zip(reference) {
        let d = zk - r;
        if clock.is_nan() {
            if !d.is_finite() {
                continue;
            }
            clock = 0.0;
        } else if s.dt.is_finite() && s.dt > 0.0 {
            clock += s.dt;
        }
        if clock > span {
            break;
        }
        if d.is_finite() {
            sum += d;
            n += 1;
        }
    }
    if n == 0 {
        f64::NAN
    } else {
        sum / n as f64
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
    /// The bias walk the surrogate drew \[rad/s/sqrt(s)\] (set by the caller).
    pub bias_walk: f64,
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
        bias_walk: f64::NAN,
    }
}

/// Powers of ten of the start's R on [`fit_r`]'s grid: every half decade within
/// [`DECADES`], the start itself left out (it is evaluated first).
const GRID_R_ALONE: [f64; 24] = {
    let mut g = [0.0; 24];
    let mut i = 0;
    while i < 24 {
        let k = if i < 12 { i } else { i + 1 };
        g[i] = -DECADES + 0.5 * k as f64;
        i += 1;
    }
    g
};

/// Cost evaluations of [`fit_r`]: the start, the grid, and one golden search with its
/// start.
pub const EVALUATIONS_R: u64 =
    1 + GRID_R_ALONE.len() as u64 + 1 + super::search::EVALS_PER_PARAMETER;

/// Fits one R on a surrogate's RMS `rms(R)`, the filter's q_angle and q_bias kept
/// (`kf_accel`'s R and `kf_fused`'s accelerometer R, after `kf_alg2`'s fit set the Q): a
/// grid over R every half decade within [`DECADES`] of `r0`, then the golden search
/// within half a decade of the grid's best. Returns `(R, RMS before, RMS after)`
/// \[rad^2, rad, rad\]; the start if nothing lowered the RMS.
///
/// Why not the likelihood, as before: the accelerometer's error under vibration is
/// coloured as Algorithm 2's is, and the likelihood trusted it far too much. On the
/// quick start's scooter ride (60 s, seed 1), tuned, kf_accel was 1.46 deg RMS with
/// the likelihood's R (0.070 rad^2) and kf_fused, which shared it, went from 0.79 deg
/// untuned to 1.44.
pub fn fit_r(r0: f64, rms: impl Fn(f64) -> f64, budget: &mut Budget) -> (f64, f64, f64) {
    let span = 10f64.powf(DECADES);
    let clamp = |r: f64| r.clamp(r0 / span, r0 * span);
    let cost = |r: f64| rms(clamp(r));
    let before = if budget.tick() {
        cost(r0)
    } else {
        f64::INFINITY
    };
    let mut best = (before, r0);
    for lr in GRID_R_ALONE {
        if !budget.tick() {
            break;
        }
        let r = r0 * 10f64.powf(lr);
        let c = cost(r);
        if c < best.0 {
            best = (c, r);
        }
    }
    let (x, after) = coordinate_log(|x| cost(x[0]), &[best.1], 0.5, 1, budget);
    let (r, after) = if after < best.0 {
        (clamp(x[0]), after)
    } else {
        (best.1, best.0)
    };
    if after < before {
        (r, before, after)
    } else {
        (r0, before, before)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log whose measurement is the tilt itself and whose gyro's bias walks at 4e-4
    /// rad/s/sqrt(s) (a consumer gyro): over 20 seeds of 60 s the bound's RMS is the walk
    /// within 25 % (each log holds three changes: one alone scatters by a factor of 2);
    /// a log too short for three one-second means per segment gives none.
    #[test]
    fn walk_bound_recovers_a_known_walk() {
        let (w, dt) = (4e-4, 1e-3);
        let log = |seed: u64, n: usize| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut b = 0.01;
            let (mut samples, mut z) = (Vec::new(), Vec::new());
            for k in 0..n {
                let t = k as f64 * dt;
                let x: f64 = StandardNormal.sample(&mut rng);
                b += w * dt.sqrt() * x;
                samples.push(Sample {
                    dt: if k == 0 { 0.0 } else { dt },
                    phi: f64::NAN,
                    gyro: 0.1 * (0.5 * t).cos() * 0.5 + b,
                    ax: f64::NAN,
                    ay: f64::NAN,
                });
                z.push(0.1 * (0.5 * t).sin());
            }
            (samples, z)
        };
        let mut sum = 0.0;
        for seed in 0..20 {
            let (s, z) = log(seed, 60_000);
            sum += walk_bound(&s, &z, 0.0, 2000).unwrap().powi(2);
        }
        let rms = (sum / 20.0).sqrt();
        eprintln!("walk bound RMS over 20 logs {rms:.3e} (walk {w:.1e})");
        assert!((rms / w - 1.0).abs() < 0.25, "{rms} vs {w}");
        let (s, z) = log(1, 12_000);
        assert_eq!(walk_bound(&s, &z, 0.0, 2000), None);
    }
}
