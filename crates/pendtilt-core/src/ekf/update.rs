//! The scalar measurement update both filters share, in symmetric rank-one form.
use super::model::{Cov, State, N};
use crate::Real;

/// Why an update was not applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejected {
    /// The measurement, its variance or the innovation variance was not finite.
    NotFinite,
    /// The innovation variance was not positive.
    NotPositive,
}

/// Applies one scalar measurement with row `h`, innovation `y = z - h(x)` and variance `r`.
///
/// Gain `k = P h / s`, `s = h P h + r`, `v = P h`. The covariance becomes
/// `P - v v^T / s`, computed on the upper triangle and mirrored, so `P` stays exactly
/// symmetric; for this (optimal) gain it equals Joseph's form
/// `(I - k h) P (I - k h)^T + r k k^T = P - k v^T - v k^T + s k k^T`, at a quarter of the
/// multiplications (Joseph's form guards against a suboptimal gain, which this code never
/// applies). Positive definiteness is checked over a one-hour run by the
/// `ekf_covariance` test of the std crate. Returns the innovation variance `s`.
#[inline]
pub fn scalar_update<T: Real>(
    x: &mut State<T>,
    p: &mut Cov<T>,
    h: &State<T>,
    y: T,
    r: T,
) -> Result<T, Rejected> {
    if !(y.is_finite() && r.is_finite()) {
        return Err(Rejected::NotFinite);
    }
    let v = *p * h;
    let s = h.dot(&v) + r;
    if !s.is_finite() {
        return Err(Rejected::NotFinite);
    }
    if s <= T::zero() {
        return Err(Rejected::NotPositive);
    }
    let k = v / s;
    *x += k * y;
    rank_one_downdate(p, &k, &v);
    Ok(s)
}

/// [`scalar_update`] for a row of ones at the indices `idx` (and zeros elsewhere): `P h`
/// is a sum of columns and `h . x` a sum of states. Indices out of range are ignored.
#[inline]
pub fn unit_update<T: Real>(
    x: &mut State<T>,
    p: &mut Cov<T>,
    idx: &[usize],
    z: T,
    r: T,
) -> Result<T, Rejected> {
    let mut v = State::<T>::zeros();
    let mut hx = T::zero();
    for &i in idx.iter().filter(|&&i| i < N) {
        v += p.column(i);
        hx += x[i];
    }
    let y = z - hx;
    if !(y.is_finite() && r.is_finite()) {
        return Err(Rejected::NotFinite);
    }
    let mut s = r;
    for &i in idx.iter().filter(|&&i| i < N) {
        s += v[i];
    }
    if !s.is_finite() {
        return Err(Rejected::NotFinite);
    }
    if s <= T::zero() {
        return Err(Rejected::NotPositive);
    }
    let k = v / s;
    *x += k * y;
    rank_one_downdate(p, &k, &v);
    Ok(s)
}

/// `P - k v^T` (with `k = v / s`, that is `P - v v^T / s`) on the upper triangle, mirrored:
/// exactly symmetric, one multiplication per entry.
#[inline]
fn rank_one_downdate<T: Real>(p: &mut Cov<T>, k: &State<T>, v: &State<T>) {
    for j in 0..N {
        for i in 0..=j {
            let val = p[(i, j)] - k[i] * v[j];
            p[(i, j)] = val;
            p[(j, i)] = val;
        }
    }
}

/// `(P + P^T) / 2`.
#[inline]
pub fn symmetrise<T: Real>(p: &mut Cov<T>) {
    let half = T::lit(0.5);
    for i in 0..N {
        for j in (i + 1)..N {
            let m = (p[(i, j)] + p[(j, i)]) * half;
            p[(i, j)] = m;
            p[(j, i)] = m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_textbook_update() {
        // A random SPD P and the textbook K = P h / s, P = (I - k h) P.
        let a = Cov::<f64>::from_fn(|i, j| ((i * 7 + j * 3) % 5) as f64 * 0.1 + 0.01 * i as f64);
        let p0 = a * a.transpose() + Cov::<f64>::identity() * 0.1;
        let h = State::<f64>::from([0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        let mut x = State::<f64>::zeros();
        let mut p = p0;
        let s = scalar_update(&mut x, &mut p, &h, 0.5, 0.2).unwrap();
        let s_ref = (h.transpose() * p0 * h)[0] + 0.2;
        assert!((s - s_ref).abs() < 1e-12);
        let k = p0 * h / s_ref;
        let p_ref = (Cov::<f64>::identity() - k * h.transpose()) * p0;
        assert!((p - p_ref).abs().max() < 1e-12);
        assert!((x - k * 0.5).abs().max() < 1e-15);
        assert_eq!(p, p.transpose());
    }

    #[test]
    fn unit_update_equals_the_general_one() {
        let a = Cov::<f64>::from_fn(|i, j| ((i * 7 + j * 3) % 5) as f64 * 0.1 + 0.01 * i as f64);
        let p0 = a * a.transpose() + Cov::<f64>::identity() * 0.1;
        let x0 = State::<f64>::from([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
        let h = State::<f64>::from([0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        let (mut x1, mut p1) = (x0, p0);
        let (mut x2, mut p2) = (x0, p0);
        scalar_update(&mut x1, &mut p1, &h, 0.9 - h.dot(&x0), 0.2).unwrap();
        unit_update(&mut x2, &mut p2, &[1, 5], 0.9, 0.2).unwrap();
        assert!((x1 - x2).abs().max() < 1e-15);
        assert!((p1 - p2).abs().max() < 1e-15);
    }

    #[test]
    fn rejects_bad_input() {
        let mut x = State::<f64>::zeros();
        let mut p = Cov::<f64>::identity();
        let h = State::<f64>::from([1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(
            scalar_update(&mut x, &mut p, &h, f64::NAN, 1.0),
            Err(Rejected::NotFinite)
        );
        p = Cov::<f64>::zeros();
        assert_eq!(
            scalar_update(&mut x, &mut p, &h, 1.0, 0.0),
            Err(Rejected::NotPositive)
        );
        assert_eq!(x, State::<f64>::zeros());
    }
}
