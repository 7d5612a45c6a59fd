//! The one-pole low-pass `m <- m + (x - m) k`, `k = 1 - exp(-w dt)` (exact for an input
//! held over the step), as the spatial estimators use it per sample: the gyro bridging a
//! missing reading, the path's turn rate, the vibration's mean square, the slip
//! detector's carried speed.
//!
//! The gain costs an `exp`; the step is almost always the same, so it is kept for the
//! last step and recomputed only when the step changes (as the smoothing differentiators
//! keep their discretisation). Same step, same bits: the cache changes no output.
use crate::Real;
use nalgebra::SVector;

/// The gain `1 - exp(-w dt)` of a one-pole low-pass of rate `w`, cached for the last step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnePoleGain<T> {
    rate: T,
    step: T,
    gain: T,
}

impl<T: Real> OnePoleGain<T> {
    /// Cutoff `hz` \[Hz\]: rate `2 pi hz`.
    pub fn from_hz(hz: T) -> Self {
        Self::from_rate(T::two_pi() * hz)
    }

    /// Time constant `tau` \[s\]: rate `1 / tau`.
    pub fn from_time_constant(tau: T) -> Self {
        Self::from_rate(T::one() / tau)
    }

    /// Rate `w` \[rad/s\].
    pub fn from_rate(rate: T) -> Self {
        Self {
            rate,
            // Not a step: the first call computes the gain.
            step: T::nan(),
            gain: T::zero(),
        }
    }

    /// The gain for a step of `dt` seconds (0 for `dt = 0`).
    #[inline]
    pub fn gain(&mut self, dt: T) -> T {
        if dt != self.step {
            self.gain = T::one() - (-(self.rate * dt)).exp();
            self.step = dt;
        }
        self.gain
    }
}

/// A one-pole low-pass of `C` signals ([`OnePoleGain`]); the first input starts it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnePole<T: Real, const C: usize> {
    gain: OnePoleGain<T>,
    value: Option<SVector<T, C>>,
}

impl<T: Real, const C: usize> OnePole<T, C> {
    /// A low-pass with gain `gain`, nothing seen yet.
    pub fn new(gain: OnePoleGain<T>) -> Self {
        Self { gain, value: None }
    }

    /// Takes input `x` `dt` seconds after the last (the first one starts the filter on
    /// it) and returns the output.
    #[inline]
    pub fn update(&mut self, x: &SVector<T, C>, dt: T) -> SVector<T, C> {
        let m = match self.value {
            Some(m) => m + (x - m) * self.gain.gain(dt),
            None => *x,
        };
        self.value = Some(m);
        m
    }

    /// The output, once started.
    #[inline]
    pub fn value(&self) -> Option<SVector<T, C>> {
        self.value
    }

    /// Forgets the signal (the cached gain stays: it depends on the step only).
    pub fn reset(&mut self) {
        self.value = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector1;

    /// A step input reaches `1 - exp(-t / tau)` exactly at every sample, whatever the
    /// step sizes (the gain is exact for a held input), and a cached gain equals a fresh
    /// one bit for bit.
    #[test]
    fn a_step_response_is_exact_and_the_cache_changes_nothing() {
        let tau = 0.2;
        let mut f = OnePole::<f64, 1>::new(OnePoleGain::from_time_constant(tau));
        f.update(&Vector1::new(0.0), 0.0);
        let mut t = 0.0;
        for (k, dt) in [1e-3, 1e-3, 2.5e-3, 1e-3, 0.05, 1e-3]
            .into_iter()
            .enumerate()
        {
            t += dt;
            let y = f.update(&Vector1::new(1.0), dt)[0];
            let exact = 1.0 - (-t / tau).exp();
            assert!((y - exact).abs() < 1e-12, "{k}: {y} vs {exact}");
        }
        let mut cached = OnePoleGain::<f64>::from_hz(5.0);
        for dt in [1e-3, 1e-3, 2e-3, 1e-3] {
            let fresh = 1.0 - (-core::f64::consts::TAU * 5.0 * dt).exp();
            assert_eq!(cached.gain(dt).to_bits(), fresh.to_bits());
        }
        assert_eq!(cached.gain(0.0), 0.0);
    }
}
