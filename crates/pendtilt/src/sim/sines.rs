//! Sums of sinusoids evaluated on a uniform time grid.
//!
//! Every periodic part of the simulator (sine motion, the band-limited manoeuvres, engine
//! harmonics, angular vibration) is a sum of `amp * sin(omega * t + phase)`. The integrator
//! needs them at many points per sample, so instead of one `sin_cos` per point the grid is
//! anchored with an exact `sin_cos` at its first point and advanced by rotating the phasor
//! (four multiplications per point). Re-anchoring at every sample keeps the rounding drift
//! at a few ulps whatever the run length.

use std::f64::consts::TAU;

/// One sinusoid `amp * sin(omega * t + phase)`, optionally along a direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sinusoid {
    /// Amplitude (unit of the quantity it drives).
    pub amp: f64,
    /// Angular frequency [rad/s].
    pub omega: f64,
    /// Phase at t = 0 [rad].
    pub phase: f64,
    /// Direction in body axes for vector quantities (unit length); unused for scalars.
    pub dir: [f64; 2],
}

impl Sinusoid {
    /// A scalar sinusoid of frequency `hz` [Hz].
    pub fn scalar(amp: f64, hz: f64, phase: f64) -> Self {
        Self {
            amp,
            omega: TAU * hz,
            phase,
            dir: [0.0, 0.0],
        }
    }
}

/// A sum of sinusoids.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SineSum {
    parts: Vec<Sinusoid>,
}

impl SineSum {
    /// The sum of `parts`.
    pub fn new(parts: Vec<Sinusoid>) -> Self {
        Self { parts }
    }

    /// True when there is nothing to add.
    pub fn is_empty(&self) -> bool {
        self.parts.is_empty()
    }

    /// The components.
    pub fn parts(&self) -> &[Sinusoid] {
        &self.parts
    }

    /// Value, first and second time derivative at one instant, exactly.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        let mut out = [0.0; 3];
        for p in &self.parts {
            let (s, c) = (p.omega * t + p.phase).sin_cos();
            out[0] += p.amp * s;
            out[1] += p.amp * p.omega * c;
            out[2] -= p.amp * p.omega * p.omega * s;
        }
        out
    }

    /// Adds value, first and second derivative at `t0 + j * dt`, `j = 0 .. out.len()`.
    pub fn add_kinematics(&self, t0: f64, dt: f64, out: &mut [[f64; 3]]) {
        for p in &self.parts {
            let (mut s, mut c) = (p.omega * t0 + p.phase).sin_cos();
            let (sd, cd) = (p.omega * dt).sin_cos();
            let a1 = p.amp * p.omega;
            let a2 = a1 * p.omega;
            for o in out.iter_mut() {
                o[0] += p.amp * s;
                o[1] += a1 * c;
                o[2] -= a2 * s;
                (s, c) = (s * cd + c * sd, c * cd - s * sd);
            }
        }
    }

    /// Adds the vector value `amp * sin(..) * dir` at `t0 + j * dt`, `j = 0 .. out.len()`.
    pub fn add_vectors(&self, t0: f64, dt: f64, out: &mut [[f64; 2]]) {
        for p in &self.parts {
            let (mut s, mut c) = (p.omega * t0 + p.phase).sin_cos();
            let (sd, cd) = (p.omega * dt).sin_cos();
            let ax = p.amp * p.dir[0];
            let ay = p.amp * p.dir[1];
            for o in out.iter_mut() {
                o[0] += ax * s;
                o[1] += ay * s;
                (s, c) = (s * cd + c * sd, c * cd - s * sd);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_matches_direct_evaluation() {
        let sum = SineSum::new(vec![
            Sinusoid::scalar(0.3, 0.7, 0.4),
            Sinusoid::scalar(1.5, 41.0, -1.0),
        ]);
        let t0 = 3599.123;
        let dt = 1.0 / 8000.0;
        let mut grid = [[0.0; 3]; 9];
        sum.add_kinematics(t0, dt, &mut grid);
        for (j, g) in grid.iter().enumerate() {
            let e = sum.eval(t0 + j as f64 * dt);
            for i in 0..3 {
                let scale = 1.0 + e[i].abs();
                assert!((g[i] - e[i]).abs() < 1e-9 * scale, "j={j} i={i}");
            }
        }
    }
}
