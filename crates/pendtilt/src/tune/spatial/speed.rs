//! The vehicle's jerk density from the `speed` column, by maximum likelihood.
//!
//! ekf3d carries O's forward speed and its rate as states, the rate a random walk driven
//! by white jerk of density `q` ([`pendtilt_core::spatial::ekf::SpeedSettings`]), the
//! `speed` column reading the speed with the measured white noise. That model alone, a
//! two-state Kalman filter on the speed readings, gives each reading a predicted mean and
//! variance; `q` is chosen where the readings are most likely (the sum of `ln S + v^2 / S`
//! over the innovations `v` and their variances `S` is least), as the planar tune fits
//! its Kalman noise. It is the vehicle's own: how fast its acceleration changes, measured
//! where the speed sensor sees it. A vehicle that never changes speed drives `q` to the
//! search's floor, which says so.
use crate::peers::tune::golden_log;
use pendtilt_core::spatial::SpatialSample;

/// The search's range of the jerk density \[m/s^3/sqrt(Hz)\]: from a vehicle at a steady
/// speed to one whose acceleration changes by 10 m/s^2 within a second.
pub const JERK_RANGE: [f64; 2] = [1e-3, 1e2];

/// Golden-section steps of the search (the bracket shrinks to 0.618^30 of its five
/// decades: well under 1 %).
pub const JERK_STEPS: usize = 30;

/// Readings at the start left out of the likelihood while the rate's state settles.
const SETTLE_READINGS: usize = 20;

/// The jerk density found, with its evidence.
#[derive(Debug, Clone, PartialEq)]
pub struct Jerk {
    /// The most likely jerk density \[m/s^3/sqrt(Hz)\].
    pub density: f64,
    /// The speed readings the likelihood was taken over.
    pub readings: usize,
    /// The RMS of the normalised innovations at `density` (1 for a consistent model).
    pub normalised_rms: f64,
    /// The density lies at an end of [`JERK_RANGE`]: the log does not bound it.
    pub at_bound: bool,
}

/// The speed readings of `samples` (time \[s\], speed \[m/s\]), rows without one left out.
fn readings(samples: &[SpatialSample<f64>]) -> Vec<(f64, f64)> {
    let mut t = 0.0;
    let mut out = Vec::new();
    for s in samples {
        if s.dt.is_finite() && s.dt > 0.0 {
            t += s.dt;
        }
        if s.speed.is_finite() {
            out.push((t, s.speed));
        }
    }
    out
}

/// `-2 ln` of the readings' likelihood (constants dropped) and the mean normalised
/// innovation squared, for jerk density `q` and reading noise `sigma`.
fn likelihood(r: &[(f64, f64)], q: f64, sigma: f64, initial_rate: f64) -> (f64, f64) {
    let rr = sigma * sigma;
    let (mut v, mut a) = (r[0].1, 0.0);
    let (mut pvv, mut pva, mut paa) = (rr, 0.0, initial_rate * initial_rate);
    let (mut cost, mut nis, mut n) = (0.0, 0.0, 0usize);
    for (k, w) in r.windows(2).enumerate() {
        let dt = w[1].0 - w[0].0;
        // Predict: v += a dt; the white jerk's covariance over dt.
        let q2 = q * q;
        v += a * dt;
        let (vv, va) = (pvv + 2.0 * dt * pva + dt * dt * paa, pva + dt * paa);
        pvv = vv + q2 * dt.powi(3) / 3.0;
        pva = va + q2 * dt * dt / 2.0;
        paa += q2 * dt;
        // Update with the reading.
        let s = pvv + rr;
        let innov = w[1].1 - v;
        if k >= SETTLE_READINGS {
            cost += s.ln() + innov * innov / s;
            nis += innov * innov / s;
            n += 1;
        }
        let (kv, ka) = (pvv / s, pva / s);
        v += kv * innov;
        a += ka * innov;
        let (p_vv, p_va, p_aa) = (pvv, pva, paa);
        pvv = (1.0 - kv) * p_vv;
        pva = (1.0 - kv) * p_va;
        paa = p_aa - ka * p_va;
    }
    (cost, nis / n.max(1) as f64)
}

/// The most likely jerk density for `samples` whose speed readings have white noise
/// `sigma` \[m/s\] (module documentation); `initial_rate` \[m/s^2\] is the rate's start
/// spread (ekf3d's). `Err` says why not.
pub fn jerk(samples: &[SpatialSample<f64>], sigma: f64, initial_rate: f64) -> Result<Jerk, String> {
    let r = readings(samples);
    if r.len() < 10 * SETTLE_READINGS {
        return Err(format!(
            "{} speed readings, too few for the speed's model ({} needed)",
            r.len(),
            10 * SETTLE_READINGS
        ));
    }
    if !(sigma.is_finite() && sigma > 0.0) {
        return Err(format!(
            "the speed's noise is {sigma}: no likelihood without it"
        ));
    }
    let [lo, hi] = JERK_RANGE;
    let (q, _) = golden_log(
        |q| likelihood(&r, q, sigma, initial_rate).0,
        lo,
        hi,
        JERK_STEPS,
    );
    let at_bound = q < lo * 1.05 || q > hi / 1.05;
    Ok(Jerk {
        density: q,
        readings: r.len(),
        normalised_rms: likelihood(&r, q, sigma, initial_rate).1.sqrt(),
        at_bound,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    /// Speed readings of a rate that walks with white jerk of density `q`, at 100 Hz.
    fn walk(q: f64, sigma: f64, seconds: f64, seed: u64) -> Vec<SpatialSample<f64>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let n01 = Normal::new(0.0, 1.0).unwrap();
        let dt = 0.01;
        let (mut v, mut a) = (5.0, 0.0);
        (0..(seconds / dt) as usize)
            .map(|k| {
                if k > 0 {
                    // Exact discretisation of the white jerk over dt.
                    let j1 = n01.sample(&mut rng) * q * dt.sqrt();
                    let j2 = n01.sample(&mut rng) * q * (dt.powi(3) / 12.0).sqrt();
                    v += a * dt + j1 * dt / 2.0 + j2;
                    a += j1;
                }
                SpatialSample {
                    speed: v + sigma * n01.sample(&mut rng),
                    ..SpatialSample::after(if k == 0 { 0.0 } else { dt })
                }
            })
            .collect()
    }

    /// The density a walk was drawn with is found within 15 %, over two decades, and
    /// the innovations come out consistent.
    #[test]
    fn the_drawn_jerk_density_is_found() {
        for (q, seed) in [(0.1, 1), (1.0, 2), (10.0, 3)] {
            let s = walk(q, 0.02, 300.0, seed);
            let j = jerk(&s, 0.02, 2.0).unwrap();
            assert!((j.density / q - 1.0).abs() < 0.15, "{q}: {j:?}");
            assert!((j.normalised_rms - 1.0).abs() < 0.05, "{j:?}");
            assert!(!j.at_bound);
        }
    }

    /// A vehicle at a steady speed has no jerk to find: the floor, said; a log without
    /// speed readings is refused with the count.
    #[test]
    fn a_steady_speed_is_at_the_floor_and_no_speed_is_refused() {
        let s = walk(0.0, 0.05, 60.0, 4);
        let j = jerk(&s, 0.05, 2.0).unwrap();
        assert!(j.at_bound && j.density < 2e-3, "{j:?}");
        let none: Vec<_> = s
            .iter()
            .map(|x| SpatialSample {
                speed: f64::NAN,
                ..*x
            })
            .collect();
        let e = jerk(&none, 0.05, 2.0).unwrap_err();
        assert!(e.starts_with("0 speed readings"), "{e}");
    }
}
