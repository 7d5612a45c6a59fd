//! Min/max decimation for the page's plots: a trace of any length becomes at most
//! `2 * buckets + 2` points that draw the same envelope at screen resolution.
//!
//! The first and the last sample are kept as they are; the samples between them are split
//! into `buckets` runs of (nearly) equal count, and each run gives two points: at its first
//! and last abscissa, its lowest and highest finite ordinate in the order they occur. The
//! bucket edges depend only on the number of samples, so every trace on one time axis shares
//! the same decimated abscissae (one x array per plot, as the plotting library wants).
use std::ops::Range;

/// The sample ranges of the buckets for `n` samples: `None` when there are few enough
/// samples (`n <= 2 * buckets + 2`) to keep them all.
pub fn buckets(n: usize, buckets: usize) -> Option<Vec<Range<usize>>> {
    if buckets == 0 || n <= 2 * buckets + 2 {
        return None;
    }
    let inner = n - 2;
    Some(
        (0..buckets)
            .map(|b| (1 + b * inner / buckets)..(1 + (b + 1) * inner / buckets))
            .collect(),
    )
}

/// The decimated abscissae: the first sample's, each bucket's first and last, the last
/// sample's; `x` itself when `bounds` is `None`.
pub fn abscissae(x: &[f64], bounds: Option<&[Range<usize>]>) -> Vec<f64> {
    let Some(bounds) = bounds else {
        return x.to_vec();
    };
    let mut out = Vec::with_capacity(2 * bounds.len() + 2);
    out.push(x[0]);
    for r in bounds {
        out.push(x[r.start]);
        out.push(x[r.end - 1]);
    }
    out.push(x[x.len() - 1]);
    out
}

/// The decimated ordinates, point for point with [`abscissae`]: the first sample, each
/// bucket's lowest and highest finite value in their order (NaN twice, a gap, when the
/// bucket has no finite value), the last sample; `y` itself when `bounds` is `None`.
pub fn ordinates(y: &[f64], bounds: Option<&[Range<usize>]>) -> Vec<f64> {
    let Some(bounds) = bounds else {
        return y.to_vec();
    };
    let mut out = Vec::with_capacity(2 * bounds.len() + 2);
    out.push(y[0]);
    for r in bounds {
        let (mut lo, mut hi): (Option<usize>, Option<usize>) = (None, None);
        for i in r.clone() {
            let v = y[i];
            if !v.is_finite() {
                continue;
            }
            if lo.is_none_or(|j| v < y[j]) {
                lo = Some(i);
            }
            if hi.is_none_or(|j| v > y[j]) {
                hi = Some(i);
            }
        }
        match (lo, hi) {
            (Some(a), Some(b)) => {
                let (first, second) = if a <= b { (a, b) } else { (b, a) };
                out.push(y[first]);
                out.push(y[second]);
            }
            _ => out.extend([f64::NAN, f64::NAN]),
        }
    }
    out.push(y[y.len() - 1]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_traces_are_kept_whole() {
        assert!(buckets(10, 4).is_none());
        let x = [0.0, 1.0, 2.0];
        assert_eq!(abscissae(&x, None), x);
        assert_eq!(ordinates(&x, None), x);
    }

    #[test]
    fn every_buckets_min_and_max_survive_in_order_with_both_ends() {
        let n = 100_001;
        let x: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
        let y: Vec<f64> = (0..n).map(|k| ((k * 7919) % 1000) as f64).collect();
        let b = buckets(n, 500).unwrap();
        let (dx, dy) = (abscissae(&x, Some(&b)), ordinates(&y, Some(&b)));
        assert_eq!(dx.len(), 2 * 500 + 2);
        assert_eq!(dy.len(), dx.len());
        assert_eq!((dx[0], dy[0]), (x[0], y[0]));
        assert_eq!((dx[dx.len() - 1], dy[dy.len() - 1]), (x[n - 1], y[n - 1]));
        // the buckets tile the samples between the ends
        assert_eq!(b[0].start, 1);
        assert_eq!(b[b.len() - 1].end, n - 1);
        assert!(b.windows(2).all(|w| w[0].end == w[1].start));
        for (k, r) in b.iter().enumerate() {
            let s = &y[r.clone()];
            let lo = s.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let pair = (dy[1 + 2 * k], dy[2 + 2 * k]);
            let i_lo = r.start + s.iter().position(|v| *v == lo).unwrap();
            let i_hi = r.start + s.iter().position(|v| *v == hi).unwrap();
            let want = if i_lo <= i_hi { (lo, hi) } else { (hi, lo) };
            assert_eq!(pair, want, "bucket {k}");
        }
        assert!(dx.windows(2).all(|w| w[1] >= w[0]));
    }

    #[test]
    fn the_output_is_bounded_whatever_the_length() {
        for n in [7, 1_000, 10_007, 1_000_003] {
            let x: Vec<f64> = (0..n).map(|k| k as f64).collect();
            let b = buckets(n, 2000);
            assert!(abscissae(&x, b.as_deref()).len() <= 2 * 2000 + 2, "{n}");
        }
    }

    #[test]
    fn nan_is_skipped_and_an_all_nan_bucket_is_a_gap() {
        let mut y: Vec<f64> = (0..1000).map(|k| (k % 10) as f64).collect();
        // bucket 0 covers samples 1..100: all NaN there; a NaN beside the peak of bucket 1
        for v in &mut y[1..100] {
            *v = f64::NAN;
        }
        y[150] = f64::NAN;
        y[151] = 50.0;
        let b = buckets(y.len(), 10).unwrap();
        assert_eq!(b[0], 1..100);
        let d = ordinates(&y, Some(&b));
        assert!(d[1].is_nan() && d[2].is_nan());
        assert_eq!((d[3], d[4]), (0.0, 50.0));
        assert!(d[5..].iter().all(|v| v.is_finite()));
    }
}
