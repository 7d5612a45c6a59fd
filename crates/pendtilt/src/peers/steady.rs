//! A peer's steady offset from the accelerometer, kept through a restart: with a gyro bias
//! `b`, a filter whose accelerometer feedback has the gain `k` (Mahony's kp) settles where
//! its disagreement with the accelerometer cancels the bias, `e = b / k` (about 1 deg on
//! the scooter rides), which a gap cannot change. Its first start hides that steady value
//! under a transient from one reading for several time constants, so it is fitted with
//! the transient rather than averaged. Used by Mahony in the tilt plane
//! ([`super::ahrs_planar::Planar`], one axis) and in 3-D ([`super::spatial::Imu6`], the
//! vector `a_hat x up_est`).

/// How long \[s\] a filter's steady disagreement with the accelerometer is averaged over
/// for its restart: the fit forgets at this time constant, so that it follows a bias that
/// drifts with temperature. 5 s, 10 s and no forgetting measured alike (Mahony after the
/// 10 s gap of tests/faults3d/: 0.36, 0.38, 0.40 deg from the fault-free run 2 s on).
pub const RESTART_OFFSET_WINDOW: f64 = 30.0;

/// A least-squares fit of `e(t) = c + A exp(-k t)` per component to a filter's
/// disagreement with the accelerometer since its start (`t`, `k` its gain), weighted by
/// the time step and forgetting over [`RESTART_OFFSET_WINDOW`]: `c` is the steady state,
/// which the start transient hides for several time constants (8 s after a start from one
/// reading on the scooter3d ride, a plain 3 s mean of `e` was still 2 deg from it).
#[derive(Debug, Clone, Copy)]
pub struct SteadyFit<const D: usize> {
    /// Time since the filter's start \[s\].
    t: f64,
    /// Weighted sums of 1, x, x^2 (x = exp(-k t)).
    s: [f64; 3],
    /// Weighted sums of e and e x.
    b0: [f64; D],
    b1: [f64; D],
}

impl<const D: usize> Default for SteadyFit<D> {
    fn default() -> Self {
        Self {
            t: 0.0,
            s: [0.0; 3],
            b0: [0.0; D],
            b1: [0.0; D],
        }
    }
}

impl<const D: usize> SteadyFit<D> {
    /// Adds the disagreement `e` over a step of `dt` \[s\], the filter's gain being `k` \[1/s\].
    pub fn add(&mut self, e: [f64; D], dt: f64, k: f64) {
        self.t += dt;
        // The transient's term is gone to rounding after 40 time constants: no exp per
        // sample for the rest of a log.
        let x = if k * self.t < 40.0 {
            (-k * self.t).exp()
        } else {
            0.0
        };
        let keep = 1.0 - (dt / RESTART_OFFSET_WINDOW).min(1.0);
        for (v, add) in self.s.iter_mut().zip([dt, dt * x, dt * x * x]) {
            *v = *v * keep + add;
        }
        for ((b0, b1), e) in self.b0.iter_mut().zip(&mut self.b1).zip(e) {
            *b0 = *b0 * keep + dt * e;
            *b1 = *b1 * keep + dt * e * x;
        }
    }

    /// `c`, once the filter has run for two time constants (before, `c` and `A` cannot be
    /// told apart).
    pub fn steady(&self, k: f64) -> Option<[f64; D]> {
        let [s0, s1, s2] = self.s;
        let det = s0 * s2 - s1 * s1;
        if self.t * k < 2.0 || det <= 0.0 || det.is_nan() {
            return None;
        }
        Some(core::array::from_fn(|i| {
            (self.b0[i] * s2 - self.b1[i] * s1) / det
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A disagreement that starts 12 deg off and decays at k onto a steady 1 deg: the fit
    /// finds the 1 deg after two time constants, where a mean of the same span is still
    /// degrees off; nothing before.
    #[test]
    fn the_fit_sees_the_steady_value_through_the_start_transient() {
        let (k, c, a, dt) = (0.45, 1f64.to_radians(), 11f64.to_radians(), 1e-3);
        let mut fit = SteadyFit::<1>::default();
        let (mut sum, mut n) = (0.0, 0.0);
        for i in 1..=6000 {
            let t = i as f64 * dt;
            let e = c + a * (-k * t).exp();
            fit.add([e], dt, k);
            sum += e;
            n += 1.0;
            if t * k < 2.0 {
                assert!(fit.steady(k).is_none());
            }
        }
        let got = fit.steady(k).unwrap()[0];
        assert!((got - c).abs() < 1e-6, "{} deg", got.to_degrees());
        assert!((sum / n - c).to_degrees() > 2.0);
    }
}
