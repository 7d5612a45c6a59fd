//! A second-order Butterworth low-pass (bilinear transform with pre-warping), used to
//! smooth the accelerometer before atan2 (MODEL.md section 4: atan2 rectifies vibration
//! into a bias; a low-pass before it removes most of that).
use crate::Real;

/// Direct-form-I second-order Butterworth low-pass whose coefficients follow the actual
/// time step (recomputed only when it changes).
#[derive(Debug, Clone, Copy)]
pub struct LowPass2<T> {
    cutoff_hz: T,
    step: T,
    b: [T; 3],
    a: [T; 2],
    x: [T; 2],
    y: [T; 2],
    started: bool,
}

impl<T: Real> LowPass2<T> {
    /// A low-pass at `cutoff_hz` (must be finite and positive; otherwise 1 Hz).
    pub fn new(cutoff_hz: T) -> Self {
        let f = if cutoff_hz.is_finite() && cutoff_hz > T::zero() {
            cutoff_hz
        } else {
            T::one()
        };
        Self {
            cutoff_hz: f,
            step: T::zero(),
            b: [T::zero(); 3],
            a: [T::zero(); 2],
            x: [T::zero(); 2],
            y: [T::zero(); 2],
            started: false,
        }
    }

    /// Forgets the state.
    pub fn reset(&mut self) {
        self.started = false;
    }

    /// Filters `u` after a step of `dt` seconds (`dt > 0`, `u` finite; the first call starts
    /// at rest on `u`). Near or above Nyquist the cutoff is capped at 0.45 of the rate.
    #[inline]
    pub fn update(&mut self, u: T, dt: T) -> T {
        if !self.started {
            self.x = [u; 2];
            self.y = [u; 2];
            self.started = true;
            return u;
        }
        if dt != self.step {
            self.design(dt);
        }
        let y = self.b[0] * u + self.b[1] * self.x[0] + self.b[2] * self.x[1]
            - self.a[0] * self.y[0]
            - self.a[1] * self.y[1];
        self.x = [u, self.x[0]];
        self.y = [y, self.y[0]];
        y
    }

    fn design(&mut self, dt: T) {
        let nyq = T::lit(0.45) / dt;
        let f = if self.cutoff_hz < nyq {
            self.cutoff_hz
        } else {
            nyq
        };
        // Pre-warped analog frequency, then the bilinear transform of 1 / (s^2 + sqrt2 s + 1).
        let k = (T::pi() * f * dt).tan();
        let k2 = k * k;
        let sq2 = T::lit(core::f64::consts::SQRT_2);
        let norm = T::one() / (T::one() + sq2 * k + k2);
        self.b = [k2 * norm, T::lit(2.0) * k2 * norm, k2 * norm];
        self.a = [
            T::lit(2.0) * (k2 - T::one()) * norm,
            (T::one() - sq2 * k + k2) * norm,
        ];
        self.step = dt;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn amplitude(f_sig: f64, cutoff: f64) -> f64 {
        let rate = 1000.0;
        let mut lp = LowPass2::new(cutoff);
        let mut peak: f64 = 0.0;
        for k in 0..20_000 {
            let t = k as f64 / rate;
            let y = lp.update((2.0 * core::f64::consts::PI * f_sig * t).sin(), 1.0 / rate);
            if t > 10.0 {
                peak = peak.max(y.abs());
            }
        }
        peak
    }

    #[test]
    fn butterworth_gains() {
        // DC-ish passes, -3 dB at cutoff, -40 dB/decade above.
        assert!((amplitude(0.5, 10.0) - 1.0).abs() < 1e-3);
        assert!((amplitude(10.0, 10.0) - 0.5f64.sqrt()).abs() < 5e-3);
        let g100 = amplitude(100.0, 10.0);
        assert!((g100 - 0.01).abs() < 0.002, "{g100}");
    }
}
