//! Gain search for the peers and the EKF process-noise fit, both on a log with a true angle.
//!
//! The cost is the paper's Eq (23), `F = RMS(theta_est - theta_true)`, over the samples
//! after a settling time. The search is a golden-section search on the logarithm of each
//! gain (gains span decades), one gain at a time, from a bracket wide enough to contain
//! every sensible value.
use super::ahrs_planar::{madgwick, mahony};
use pendtilt_core::ekf::{Ekf, ModelSettings, ProcessNoise};
use pendtilt_core::estimators::complementary::{Complementary, ComplementarySettings};
use pendtilt_core::{PlanarEstimator, Sample};

/// A log with a true angle, and how many leading samples the cost ignores.
#[derive(Debug, Clone, Copy)]
pub struct Log<'a> {
    /// The sensor samples.
    pub samples: &'a [Sample<f64>],
    /// The true tilt for each sample \[rad\] (`NaN` where unknown).
    pub truth: &'a [f64],
    /// Samples ignored at the start (settling).
    pub skip: usize,
}

/// Eq (23): the RMS error \[rad\] of `e` run over the whole log, counted after `skip`
/// samples where both are finite. `INFINITY` if nothing is counted.
pub fn rms_error(e: &mut dyn PlanarEstimator<f64>, log: &Log) -> f64 {
    e.reset();
    let mut sum = 0.0;
    let mut n = 0usize;
    for (k, (s, &th)) in log.samples.iter().zip(log.truth).enumerate() {
        let est = e.update(s).theta;
        if k >= log.skip && est.is_finite() && th.is_finite() {
            let d = est - th;
            sum += d * d;
            n += 1;
        }
    }
    if n == 0 {
        f64::INFINITY
    } else {
        (sum / n as f64).sqrt()
    }
}

/// Golden-section search of `f(x)` for `x` in `[lo, hi]` (both > 0) on a log scale,
/// `iterations` steps (each shrinks the bracket by 0.618). Returns the best `(x, f(x))`
/// seen, the bracket ends included.
pub fn golden_log(
    mut f: impl FnMut(f64) -> f64,
    lo: f64,
    hi: f64,
    iterations: usize,
) -> (f64, f64) {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (lo.ln(), hi.ln());
    let mut best = (f64::NAN, f64::INFINITY);
    let mut eval = |x: f64, best: &mut (f64, f64)| {
        let v = f(x);
        if v < best.1 || best.0.is_nan() {
            *best = (x, v);
        }
        v
    };
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let mut fc = eval(c.exp(), &mut best);
    let mut fd = eval(d.exp(), &mut best);
    for _ in 0..iterations {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = eval(c.exp(), &mut best);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = eval(d.exp(), &mut best);
        }
    }
    eval(lo, &mut best);
    eval(hi, &mut best);
    best
}

/// The peers' best gains on a log and the RMS error \[rad\] each reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeerGains {
    /// Madgwick's beta [rad/s] and its RMS error.
    pub madgwick_beta: (f64, f64),
    /// Mahony's (kp, ki) and the RMS error.
    pub mahony: ([f64; 2], f64),
    /// The complementary filter's time constant \[s\] and its RMS error (with the default
    /// 5 Hz accelerometer prefilter).
    pub complementary_tau: (f64, f64),
}

/// Searches each peer's gains on `log`: Madgwick's beta in [1e-4, 100]; Mahony's kp in
/// [1e-3, 100] with ki = 0, then ki in [1e-6 kp, kp] at that kp (kept at 0 if no ki
/// helps); the complementary filter's tau in [0.05, 100] s. `iterations` golden steps per
/// gain (20 narrows a decade-wide bracket to 0.01 %).
pub fn search_peer_gains(log: &Log, iterations: usize) -> PeerGains {
    let m = golden_log(
        |beta| rms_error(&mut madgwick(beta), log),
        1e-4,
        100.0,
        iterations,
    );
    let kp = golden_log(
        |kp| rms_error(&mut mahony(kp, 0.0), log),
        1e-3,
        100.0,
        iterations,
    );
    let ki = golden_log(
        |ki| rms_error(&mut mahony(kp.0, ki), log),
        1e-6 * kp.0,
        kp.0,
        iterations,
    );
    let mahony_best = if ki.1 < kp.1 {
        ([kp.0, ki.0], ki.1)
    } else {
        ([kp.0, 0.0], kp.1)
    };
    let c = golden_log(
        |tau| {
            rms_error(
                &mut Complementary::new(ComplementarySettings {
                    time_constant: tau,
                    ..ComplementarySettings::default()
                }),
                log,
            )
        },
        0.05,
        100.0,
        iterations,
    );
    PeerGains {
        madgwick_beta: m,
        mahony: mahony_best,
        complementary_tau: c,
    }
}

/// Fits the EKF's three process-noise densities on `log`: `rounds` passes of a
/// golden-section search on each density in turn, within `decades` decades either side of
/// its value in `start`. Returns the fitted densities and the RMS error \[rad\] they give.
pub fn fit_process_noise(
    start: &ModelSettings<f64>,
    log: &Log,
    rounds: usize,
    decades: f64,
    iterations: usize,
) -> (ProcessNoise<f64>, f64) {
    let mut s = *start;
    let cost = |s: &ModelSettings<f64>| rms_error(&mut Ekf::new(*s), log);
    let mut best = cost(&s);
    let span = 10f64.powf(decades);
    for _ in 0..rounds {
        for which in 0..3 {
            let get = |q: &ProcessNoise<f64>| match which {
                0 => q.jerk,
                1 => q.pendulum,
                _ => q.bias,
            };
            let set = |q: &mut ProcessNoise<f64>, v: f64| match which {
                0 => q.jerk = v,
                1 => q.pendulum = v,
                _ => q.bias = v,
            };
            let x0 = get(&s.process);
            if !(x0.is_finite() && x0 > 0.0) {
                continue;
            }
            let (x, v) = golden_log(
                |x| {
                    let mut t = s;
                    set(&mut t.process, x);
                    cost(&t)
                },
                x0 / span,
                x0 * span,
                iterations,
            );
            if v < best {
                best = v;
                set(&mut s.process, x);
            }
        }
    }
    (s.process, best)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_log_finds_a_log_parabola_minimum() {
        let (x, v) = golden_log(|x: f64| (x.ln() - 0.3f64.ln()).powi(2), 1e-4, 1e3, 40);
        assert!((x / 0.3 - 1.0).abs() < 1e-4, "{x}");
        assert!(v < 1e-8);
        // A minimum at the bracket's end is returned, not missed.
        let (x, _) = golden_log(|x: f64| x, 1e-2, 1.0, 10);
        assert_eq!(x, 1e-2);
    }
}
