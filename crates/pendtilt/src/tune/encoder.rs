//! Encoder noise from the `phi` column alone.
//!
//! - Quantisation step: the readings of a quantised encoder are whole multiples of one
//!   step, so the gaps between distinct values are too. The smallest gap is the candidate
//!   step `q`, refined as the median of `gap / round(gap / q)`; it is accepted when at
//!   least 90 % of the gaps are whole multiples of it (within 1 %) and values repeat (fewer
//!   distinct values than half the readings). The resolution in bits follows when
//!   `2 pi / q` is a power of two.
//! - White noise: the pendulum moves smoothly at the sample rate (its mechanical low-pass
//!   filters the vibration), so the second difference `phi_(k+1) - 2 phi_k + phi_(k-1)` is
//!   almost all noise, with variance `6 s^2` for white noise of variance `s^2` (on the
//!   simulated scooter ride the vibration's share is about 1 %). That `s^2` includes the
//!   rounding error `q^2 / 12` when the noise dithers it; the encoder's own noise is what
//!   is left, `sigma^2 = s^2 - q^2 / 12` (0 if negative). A clean encoder's rounding error
//!   is not white on a slow signal, so a small remainder can show without any noise.

/// What the log tells of its encoder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EncoderNoise {
    /// The quantisation step \[rad\], if the readings are quantised.
    pub step: Option<f64>,
    /// The resolution in bits, if the step is `2 pi / 2^bits`.
    pub bits: Option<u32>,
    /// Standard deviation of the high-frequency residual \[rad\] (rounding included).
    pub white: f64,
    /// The encoder's noise beyond the rounding, standard deviation \[rad\].
    pub noise: f64,
    /// Second differences used.
    pub samples: usize,
}

/// Fewest readings the estimate is made from.
pub const MIN_READINGS: usize = 500;

/// Estimates the encoder's noise from its readings (NaN for missing). `Err` says why not.
pub fn estimate(phi: &[f64]) -> Result<EncoderNoise, String> {
    let finite = phi.iter().filter(|v| v.is_finite()).count();
    if finite < MIN_READINGS {
        return Err(format!(
            "only {finite} encoder readings (at least {MIN_READINGS} needed)"
        ));
    }
    let step = quantisation_step(phi);
    let bits = step.and_then(|q| {
        let b = (std::f64::consts::TAU / q).log2();
        ((b - b.round()).abs() < 0.01 && (1.0..=52.0).contains(&b.round()))
            .then(|| b.round() as u32)
    });
    let (mut sum, mut n) = (0.0, 0usize);
    for w in phi.windows(3) {
        let d2 = w[2] - 2.0 * w[1] + w[0];
        if d2.is_finite() {
            sum += d2 * d2;
            n += 1;
        }
    }
    if n < MIN_READINGS {
        return Err(format!(
            "only {n} runs of three consecutive encoder readings"
        ));
    }
    let white_var = sum / n as f64 / 6.0;
    let q2 = step.map_or(0.0, |q| q * q / 12.0);
    Ok(EncoderNoise {
        step,
        bits,
        white: white_var.sqrt(),
        noise: (white_var - q2).max(0.0).sqrt(),
        samples: n,
    })
}

/// The quantisation step of the readings, if they are quantised (module documentation).
pub fn quantisation_step(phi: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = phi.iter().copied().filter(|x| x.is_finite()).collect();
    let n = v.len();
    v.sort_by(f64::total_cmp);
    v.dedup();
    if v.len() < 2 || v.len() * 2 > n {
        return None;
    }
    let gaps: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    let g0 = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    if g0.is_nan() || g0 <= 0.0 {
        return None;
    }
    let mut unit: Vec<f64> = gaps.iter().map(|g| g / (g / g0).round()).collect();
    unit.sort_by(f64::total_cmp);
    let q = unit[unit.len() / 2];
    let whole = gaps
        .iter()
        .filter(|&&g| {
            let m = g / q;
            (m - m.round()).abs() < 0.01 * m.round().max(1.0)
        })
        .count();
    (whole * 10 >= gaps.len() * 9).then_some(q)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_of_a_twelve_bit_ramp() {
        let q = std::f64::consts::TAU / 4096.0;
        let phi: Vec<f64> = (0..2000)
            .map(|k| ((0.3 * (k as f64 * 0.002).sin()) / q).round() * q)
            .collect();
        let got = quantisation_step(&phi).unwrap();
        assert!((got / q - 1.0).abs() < 1e-9);
        let e = estimate(&phi).unwrap();
        assert_eq!(e.bits, Some(12));
        // A clean encoder: little beyond the rounding (its error is not quite white on a
        // slow ramp, so not exactly nothing).
        let rounding = q / 12f64.sqrt();
        assert!(e.noise < 0.5 * rounding, "{} vs {rounding}", e.noise);
        // Not quantised: every value distinct.
        let smooth: Vec<f64> = (0..2000).map(|k| (k as f64 * 0.001).sin()).collect();
        assert_eq!(quantisation_step(&smooth), None);
    }

    #[test]
    fn too_few_readings_say_so() {
        let e = estimate(&[0.0; 100]).unwrap_err();
        assert!(e.contains("100 encoder readings"), "{e}");
    }
}
