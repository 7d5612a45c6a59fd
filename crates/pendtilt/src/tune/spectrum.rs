//! Power spectral densities of a log's columns by Welch's method: Hann-windowed segments
//! of `2^k` samples, half overlapping, each with its mean removed, periodograms averaged.
//! Segments holding a non-finite value are left out (a missing reading must not smear
//! over the spectrum). The FFT is an in-place radix-2 one: a few segments of a thousand
//! samples do not justify a dependency.
use std::f64::consts::PI;

/// A one-sided power spectral density.
#[derive(Debug, Clone, PartialEq)]
pub struct Psd {
    /// Bin spacing \[Hz\]; bin `i` is at `i df`.
    pub df: f64,
    /// One-sided density per bin \[unit^2/Hz\] (white noise of per-sample variance `s^2`
    /// at rate `fs` reads `2 s^2 / fs`).
    pub density: Vec<f64>,
    /// Segments averaged.
    pub segments: usize,
}

impl Psd {
    /// Frequency of bin `i` \[Hz\].
    pub fn freq(&self, i: usize) -> f64 {
        i as f64 * self.df
    }

    /// The bins with `lo <= f < hi`, the DC bin left out.
    fn range(&self, lo: f64, hi: f64) -> std::ops::Range<usize> {
        let a = ((lo / self.df).ceil().max(1.0)) as usize;
        let b = ((hi / self.df).ceil().max(0.0) as usize).min(self.density.len());
        a.min(b)..b
    }

    /// Power in `[lo, hi)` \[unit^2\] (the variance of the signal in that band).
    pub fn band_power(&self, lo: f64, hi: f64) -> f64 {
        self.density[self.range(lo, hi)].iter().sum::<f64>() * self.df
    }

    /// Median density in `[lo, hi)` \[unit^2/Hz\]: the noise floor under a few lines
    /// (engine harmonics raise a handful of bins, not the median). `None` on an empty band.
    pub fn band_median(&self, lo: f64, hi: f64) -> Option<f64> {
        let mut v: Vec<f64> = self.density[self.range(lo, hi)].to_vec();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        // The average of k periodograms is chi-square with about 2k degrees of freedom
        // (scaled); its median sits below its mean by (1 - 2 / (9 nu))^3, corrected here.
        let nu = (2 * self.segments) as f64;
        let median_over_mean = (1.0 - 2.0 / (9.0 * nu)).powi(3);
        Some(v[v.len() / 2] / median_over_mean)
    }
}

/// In-place radix-2 FFT of `(re, im)`; the length must be a power of two.
pub fn fft(re: &mut [f64], im: &mut [f64]) {
    let n = re.len();
    debug_assert!(n.is_power_of_two() && im.len() == n);
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -2.0 * PI / len as f64;
        let (ws, wc) = ang.sin_cos();
        for start in (0..n).step_by(len) {
            let (mut cr, mut ci) = (1.0, 0.0);
            for k in 0..len / 2 {
                let (a, b) = (start + k, start + k + len / 2);
                let tr = re[b] * cr - im[b] * ci;
                let ti = re[b] * ci + im[b] * cr;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
                let nr = cr * wc - ci * ws;
                ci = cr * ws + ci * wc;
                cr = nr;
            }
        }
        len <<= 1;
    }
}

/// Segment length for a rate: the power of two nearest one second of samples (1 Hz
/// resolution), at least 64.
pub fn segment_for(rate: f64) -> usize {
    let n = rate.max(64.0).round() as usize;
    let up = n.next_power_of_two();
    if up - n > n - up / 2 {
        up / 2
    } else {
        up
    }
}

/// Welch PSD of `x` sampled at `rate` \[Hz\] with segments of `seg` samples (a power of two).
/// `None` if fewer than 2 usable segments.
pub fn welch(x: &[f64], rate: f64, seg: usize) -> Option<Psd> {
    if !seg.is_power_of_two() || seg < 8 || rate.is_nan() || rate <= 0.0 {
        return None;
    }
    let w: Vec<f64> = (0..seg)
        .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / seg as f64).cos())
        .collect();
    let u: f64 = w.iter().map(|v| v * v).sum();
    let half = seg / 2;
    let mut acc = vec![0.0; half + 1];
    let mut count = 0;
    let (mut re, mut im) = (vec![0.0; seg], vec![0.0; seg]);
    let mut start = 0;
    while start + seg <= x.len() {
        let s = &x[start..start + seg];
        start += half;
        if !s.iter().all(|v| v.is_finite()) {
            continue;
        }
        let mean = s.iter().sum::<f64>() / seg as f64;
        for i in 0..seg {
            re[i] = (s[i] - mean) * w[i];
            im[i] = 0.0;
        }
        fft(&mut re, &mut im);
        for (k, a) in acc.iter_mut().enumerate() {
            let p = re[k] * re[k] + im[k] * im[k];
            // One-sided: the bins between DC and Nyquist carry both signs of frequency.
            *a += if k == 0 || k == half { p } else { 2.0 * p };
        }
        count += 1;
    }
    if count < 2 {
        return None;
    }
    let scale = 1.0 / (rate * u * count as f64);
    Some(Psd {
        df: rate / seg as f64,
        density: acc.into_iter().map(|a| a * scale).collect(),
        segments: count,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    #[test]
    fn fft_of_a_cosine_is_two_lines() {
        let n = 64;
        let mut re: Vec<f64> = (0..n)
            .map(|i| (2.0 * PI * 5.0 * i as f64 / n as f64).cos())
            .collect();
        let mut im = vec![0.0; n];
        fft(&mut re, &mut im);
        for k in 0..n {
            let mag = re[k].hypot(im[k]);
            let want = if k == 5 || k == n - 5 { 32.0 } else { 0.0 };
            assert!((mag - want).abs() < 1e-9, "bin {k}: {mag}");
        }
    }

    #[test]
    fn white_noise_density_and_sine_power() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let fs = 1000.0;
        let sigma = 0.3;
        let n = 60_000;
        let noise = Normal::new(0.0, sigma).unwrap();
        let x: Vec<f64> = (0..n)
            .map(|i| noise.sample(&mut rng) + 2.0 * (2.0 * PI * 50.0 * i as f64 / fs).sin())
            .collect();
        let p = welch(&x, fs, segment_for(fs)).unwrap();
        // The floor 2 sigma^2 / fs under the 50 Hz line.
        let floor = p.band_median(100.0, 450.0).unwrap();
        assert!(
            (floor / (2.0 * sigma * sigma / fs) - 1.0).abs() < 0.05,
            "{floor}"
        );
        // The sine's power 2^2 / 2 = 2 around 50 Hz.
        let line = p.band_power(45.0, 55.0) - 10.0 * floor;
        assert!((line - 2.0).abs() < 0.05, "{line}");
    }
}
