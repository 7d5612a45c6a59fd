//! Gyro white-noise density and bias from the `gyro` column (and `phi` for the bias when
//! the body never keeps still).
//!
//! - Density, high band: the median of the gyro's spectrum over 0.3-0.45 of the sample
//!   rate, where a body's motion has no power left but the sensor's white noise keeps its
//!   level (engine harmonics raise a few bins, not the median). The one-sided density
//!   `P` of white noise is `2 d^2` for the density `d` of MODEL.md section 6.
//! - Still stretches: half-second windows whose spread is within 1.5x the high band's
//!   per-sample noise and whose phi shows no tilt change (its fitted slope within 3
//!   standard errors of zero) are the body at rest; if they add up to 2 s or more, the density
//!   comes from their pooled variance (`d = s / sqrt(rate)`) and the bias from their mean.
//! - Bias otherwise: the gyro's running integral minus phi (the pendulum reads the tilt,
//!   its swing averaged out) drifts at the bias: the slope of a straight line fitted to
//!   their difference's one-second means. The swing's share averages down over the log.
use super::spectrum::{segment_for, welch};

/// What the log tells of its gyro.
#[derive(Debug, Clone, PartialEq)]
pub struct GyroNoise {
    /// White-noise density \[rad/s/sqrt(Hz)\].
    pub density: f64,
    /// Mean bias over the log \[rad/s\], if it could be told.
    pub bias: Option<f64>,
    /// Seconds of still stretches found.
    pub still_seconds: f64,
    /// How the density and the bias were found.
    pub method: String,
}

/// Estimates the gyro's noise from `gyro` and `phi` (NaN for missing) sampled at `rate`.
pub fn estimate(gyro: &[f64], phi: &[f64], rate: f64) -> Result<GyroNoise, String> {
    let psd = welch(gyro, rate, segment_for(rate))
        .ok_or_else(|| "too short for a gyro spectrum (2 s needed)".to_string())?;
    let floor = psd
        .band_median(0.3 * rate, 0.45 * rate)
        .ok_or_else(|| "no high band in the gyro spectrum".to_string())?;
    let hb_density = (floor / 2.0).sqrt();
    let sigma_hb = hb_density * rate.sqrt();
    let win = ((rate / 2.0).round() as usize).max(8);
    let (mut var_sum, mut mean_sum, mut windows) = (0.0, 0.0, 0usize);
    for (w, p) in gyro.chunks_exact(win).zip(phi.chunks(win)) {
        if !w.iter().all(|v| v.is_finite()) || !tilt_steady(p) {
            continue;
        }
        let m = w.iter().sum::<f64>() / win as f64;
        let v = w.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (win - 1) as f64;
        if v.sqrt() <= 1.5 * sigma_hb {
            var_sum += v;
            mean_sum += m;
            windows += 1;
        }
    }
    let still_seconds = (windows * win) as f64 / rate;
    if still_seconds >= 2.0 {
        let d = (var_sum / windows as f64 / rate).sqrt();
        return Ok(GyroNoise {
            density: d,
            bias: Some(mean_sum / windows as f64),
            still_seconds,
            method: format!(
                "{still_seconds:.1} s of still stretches: their pooled variance and mean"
            ),
        });
    }
    let bias = bias_from_pendulum(gyro, phi, rate);
    Ok(GyroNoise {
        density: hb_density,
        bias,
        still_seconds,
        method: format!(
            "no still stretch ({still_seconds:.1} s): median of the spectrum in {:.0}-{:.0} Hz; \
             bias: slope of the gyro's integral minus phi",
            0.3 * rate,
            0.45 * rate
        ),
    })
}

/// True unless `phi` (one window) shows the tilt changing: the slope of a straight line
/// fitted to its finite readings is more than 3 standard errors (from the fit's own
/// residuals) from zero. A steady gyro alone is not rest: a body turning at a near-constant
/// rate keeps it steady too (the slow start of a chirp, zoo ride 17: 2.5 s taken for
/// still put the bias at 0.0104 rad/s against 0.0015), but the pendulum follows the tilt.
/// Too few readings (no encoder) tell nothing: true.
fn tilt_steady(phi: &[f64]) -> bool {
    let pts: Vec<(f64, f64)> = phi
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .map(|(i, v)| (i as f64, *v))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 8 {
        return true;
    }
    let (mt, mp) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let stt: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
    let slope = pts.iter().map(|p| (p.0 - mt) * (p.1 - mp)).sum::<f64>() / stt;
    let res: f64 = pts
        .iter()
        .map(|p| (p.1 - mp - slope * (p.0 - mt)).powi(2))
        .sum();
    let se = (res / (n - 2.0) / stt).sqrt();
    slope.abs() <= 3.0 * se
}

/// The bias from the gyro's integral and the pendulum's tilt (module documentation).
fn bias_from_pendulum(gyro: &[f64], phi: &[f64], rate: f64) -> Option<f64> {
    let w = rate.round() as usize;
    let n = gyro.len().min(phi.len());
    if n < 4 * w || w == 0 {
        return None;
    }
    // The gyro's running integral (a missing reading takes the last good one) against
    // phi, in one-second windows: their difference drifts at the bias.
    let (mut integral, mut last) = (0.0, 0.0);
    let (mut st, mut sc, mut stt, mut stc, mut m) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k0, (g, p)) in gyro[..n].chunks(w).zip(phi[..n].chunks(w)).enumerate() {
        let (mut sum, mut count) = (0.0, 0usize);
        for (gi, pi) in g.iter().zip(p) {
            if gi.is_finite() {
                last = *gi;
            }
            integral += last / rate;
            if pi.is_finite() {
                sum += integral - pi;
                count += 1;
            }
        }
        if count * 2 > g.len() && g.len() == w {
            let t = (k0 as f64 + 0.5) * w as f64 / rate;
            let c = sum / count as f64;
            st += t;
            sc += c;
            stt += t * t;
            stc += t * c;
            m += 1.0;
        }
    }
    let den = m * stt - st * st;
    (m >= 4.0 && den > 0.0).then(|| (m * stc - st * sc) / den)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    /// A body turning at a steady 0.01 rad/s (as at the slow start of a chirp) with a
    /// noisy gyro: every half-second window's gyro spread is the noise's, but the
    /// pendulum (phi, 12-bit, here the tilt itself) shows the turn, so no window is
    /// taken for rest and the bias (0.002 rad/s) is not the turn rate plus the bias.
    #[test]
    fn a_steady_turn_is_not_rest() {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let noise = Normal::new(0.0, 3.6e-3).unwrap();
        let (rate, bias, turn) = (1000.0, 0.002, 0.01);
        let q = std::f64::consts::TAU / 4096.0;
        let n = 20_000;
        let gyro: Vec<f64> = (0..n)
            .map(|_| turn + bias + noise.sample(&mut rng))
            .collect();
        let phi: Vec<f64> = (0..n)
            .map(|k| (turn * k as f64 / rate / q).round() * q)
            .collect();
        let e = estimate(&gyro, &phi, rate).unwrap();
        assert!(e.still_seconds < 2.0, "{e:?}");
        let b = e.bias.unwrap();
        assert!((b - bias).abs() < 2e-4, "{b}");
        // The same gyro with the pendulum still is rest: the windows' mean is the reading.
        let still = vec![0.1; n];
        let e = estimate(&gyro, &still, rate).unwrap();
        assert!(e.still_seconds >= 19.0, "{e:?}");
        assert!((e.bias.unwrap() - turn - bias).abs() < 2e-4);
    }
}
