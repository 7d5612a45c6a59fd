//! The encoder's own noise, measured on its readings: the floor of its variance while
//! the adaptation is on.
use super::{ENCODER_NOISE_TAU, NOISE_GATE};
use crate::ekf::sensor::wrap;
use crate::Real;

/// The encoder's noise measured on its readings: the mean square of the second difference
/// of consecutive accepted readings over 6 (white noise of variance `s^2` has a second
/// difference of variance `6 s^2`; the pendulum's own motion adds `phi'' dt^2`, 1e-5 rad at
/// 10 rad/s^2 and 1 kHz, far below a 12-bit encoder's rounding).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct EncoderNoise<T> {
    last: [T; 2],
    // Consecutive accepted readings in `last` (0-2).
    run: u8,
    mean: Option<T>,
    // The smallest change between consecutive readings: a quantised encoder's step.
    step: Option<T>,
    // How long the mean has run \[s\].
    age: T,
}

impl<T: Real> EncoderNoise<T> {
    pub fn new() -> Self {
        Self {
            last: [T::zero(); 2],
            run: 0,
            mean: None,
            step: None,
            age: T::zero(),
        }
    }

    /// A reading `phi`, `dt` after the last row. A second difference beyond
    /// [`NOISE_GATE`] times the variance so far (at least `floor`) is a jump (a glitch, a
    /// re-zero), not noise: it is left out and the run starts again.
    pub fn push(&mut self, phi: T, dt: T, floor: T) {
        if self.run >= 2 {
            // Wrapped, for an encoder that turns past +-pi.
            let d1 = wrap(phi - self.last[1]);
            let d2 = d1 - wrap(self.last[1] - self.last[0]);
            let v = d2 * d2 / T::lit(6.0);
            let so_far = self.mean.unwrap_or(T::zero()).max(floor);
            if v > T::lit(NOISE_GATE) * so_far {
                self.last = [self.last[1], phi];
                self.run = 1;
                return;
            }
            if d1.abs() > T::lit(1e-12) {
                self.step = Some(self.step.map_or(d1.abs(), |q| q.min(d1.abs())));
            }
            let k = (dt / T::lit(ENCODER_NOISE_TAU)).min(T::one());
            self.mean = Some(self.mean.map_or(v, |m| m + k * (v - m)));
            self.age += dt;
        }
        self.last = [self.last[1], phi];
        self.run = (self.run + 1).min(2);
    }

    /// A reading missing or not accepted: the next second difference waits for three in
    /// a row again.
    pub fn interrupt(&mut self) {
        self.run = 0;
    }

    /// The measured variance \[rad^2\]: the second difference's, or the rounding's
    /// (`q^2 / 12`), whichever is larger (a clean encoder's rounding is not white on a
    /// slow signal, and its second difference reads less); `None` until it has run for
    /// [`ENCODER_NOISE_TAU`].
    pub fn variance(&self) -> Option<T> {
        let q = self.step.unwrap_or(T::zero());
        self.mean
            .filter(|_| self.age >= T::lit(ENCODER_NOISE_TAU))
            .map(|m| m.max(q * q / T::lit(12.0)))
    }
}
