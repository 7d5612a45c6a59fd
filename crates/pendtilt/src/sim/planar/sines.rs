//! Sums of sinusoids evaluated on a uniform time grid.
//!
//! Every periodic part of the simulator (sine motion, the band-limited manoeuvres, engine
//! harmonics, angular vibration) is a sum of `amp * sin(omega * t + phase)`. The integrator
//! needs them at many points per sample, so instead of one `sin_cos` per point a
//! [`SineGrid`] advances each phasor by a rotation (four multiplications per point, all
//! components side by side so the loop vectorises) and re-anchors it with an exact
//! `sin_cos` every [`ANCHOR_EVERY`] blocks: the rounding drift stays below about 1e-13
//! relative whatever the run length.

use std::f64::consts::TAU;

/// One sinusoid `amp * sin(omega * t + phase)`, optionally along a direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sinusoid {
    /// Amplitude (unit of the quantity it drives).
    pub amp: f64,
    /// Angular frequency \[rad/s\].
    pub omega: f64,
    /// Phase at t = 0 \[rad\].
    pub phase: f64,
    /// Direction in body axes for vector quantities (unit length); unused for scalars.
    pub dir: [f64; 2],
}

impl Sinusoid {
    /// A scalar sinusoid of frequency `hz` \[Hz\].
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
}

/// A [`SineGrid`] recomputes its phasors exactly once every this many blocks (samples).
pub const ANCHOR_EVERY: u64 = 16;

/// A [`SineSum`] evaluated block after block on a uniform grid (see the module docs).
/// Structure of arrays: one entry per component.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SineGrid {
    amp: Vec<f64>,
    a1: Vec<f64>,
    a2: Vec<f64>,
    ax: Vec<f64>,
    ay: Vec<f64>,
    omega: Vec<f64>,
    phase: Vec<f64>,
    rot_s: Vec<f64>,
    rot_c: Vec<f64>,
    s: Vec<f64>,
    c: Vec<f64>,
    dt: f64,
    last_block: Option<u64>,
    real: usize,
}

/// Components are processed in groups of this many independent lanes (the sums are
/// reassociated per lane, which lets the compiler vectorise them).
const LANES: usize = 4;

impl SineGrid {
    /// The grid of `sum`.
    pub fn new(sum: &SineSum) -> Self {
        // Pad with silent components (amplitude 0, frequency 0) to whole groups of lanes.
        let mut p = sum.parts.clone();
        let real = p.len();
        p.resize(
            real.div_ceil(LANES) * LANES,
            Sinusoid::scalar(0.0, 0.0, 0.0),
        );
        let n = p.len();
        Self {
            real,
            amp: p.iter().map(|p| p.amp).collect(),
            a1: p.iter().map(|p| p.amp * p.omega).collect(),
            a2: p.iter().map(|p| p.amp * p.omega * p.omega).collect(),
            ax: p.iter().map(|p| p.amp * p.dir[0]).collect(),
            ay: p.iter().map(|p| p.amp * p.dir[1]).collect(),
            omega: p.iter().map(|p| p.omega).collect(),
            phase: p.iter().map(|p| p.phase).collect(),
            rot_s: vec![0.0; n],
            rot_c: vec![1.0; n],
            s: vec![0.0; n],
            c: vec![1.0; n],
            dt: f64::NAN,
            last_block: None,
        }
    }

    /// True when there is nothing to add.
    pub fn is_empty(&self) -> bool {
        self.real == 0
    }

    /// Puts the phasors at `t0` for block `block` with spacing `dt`: exactly (sin_cos) at
    /// the first block, every [`ANCHOR_EVERY`] blocks, and whenever the blocks are not
    /// consecutive or `dt` changes; otherwise they continue from the previous block's
    /// last point, which is this block's first.
    fn start(&mut self, block: u64, t0: f64, dt: f64) {
        if dt != self.dt {
            self.dt = dt;
            for i in 0..self.omega.len() {
                (self.rot_s[i], self.rot_c[i]) = (self.omega[i] * dt).sin_cos();
            }
            self.last_block = None;
        }
        let consecutive = self.last_block.is_some_and(|b| b + 1 == block);
        if !consecutive || block % ANCHOR_EVERY == 0 {
            for i in 0..self.omega.len() {
                (self.s[i], self.c[i]) = (self.omega[i] * t0 + self.phase[i]).sin_cos();
            }
        }
        self.last_block = Some(block);
    }

    #[inline]
    fn rotate(&mut self) {
        let rot = self.rot_s.iter().zip(&self.rot_c);
        for ((s, c), (rs, rc)) in self.s.iter_mut().zip(self.c.iter_mut()).zip(rot) {
            (*s, *c) = (*s * rc + *c * rs, *c * rc - *s * rs);
        }
    }

    /// Adds value, first and second derivative at `t0 + j * dt`, `j = 0 .. out.len()`.
    /// Blocks are numbered by the caller; consecutive blocks must share their end point.
    pub fn add_kinematics(&mut self, block: u64, t0: f64, dt: f64, out: &mut [[f64; 3]]) {
        if self.is_empty() {
            return;
        }
        self.start(block, t0, dt);
        let last = out.len().saturating_sub(1);
        for (j, o) in out.iter_mut().enumerate() {
            let (mut v, mut d1, mut d2) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
            let groups = self
                .amp
                .chunks_exact(LANES)
                .zip(self.a1.chunks_exact(LANES))
                .zip(self.a2.chunks_exact(LANES))
                .zip(self.s.chunks_exact(LANES).zip(self.c.chunks_exact(LANES)));
            for (((amp, a1), a2), (s, c)) in groups {
                for l in 0..LANES {
                    v[l] += amp[l] * s[l];
                    d1[l] += a1[l] * c[l];
                    d2[l] -= a2[l] * s[l];
                }
            }
            o[0] += v.iter().sum::<f64>();
            o[1] += d1.iter().sum::<f64>();
            o[2] += d2.iter().sum::<f64>();
            if j < last {
                self.rotate();
            }
        }
    }

    /// Adds the vector value `amp * sin(..) * dir` at `t0 + j * dt`, `j = 0 .. out.len()`.
    /// Blocks are numbered by the caller; consecutive blocks must share their end point.
    pub fn add_vectors(&mut self, block: u64, t0: f64, dt: f64, out: &mut [[f64; 2]]) {
        if self.is_empty() {
            return;
        }
        self.start(block, t0, dt);
        let last = out.len().saturating_sub(1);
        for (j, o) in out.iter_mut().enumerate() {
            let (mut x, mut y) = ([0.0; LANES], [0.0; LANES]);
            let groups = self
                .ax
                .chunks_exact(LANES)
                .zip(self.ay.chunks_exact(LANES))
                .zip(self.s.chunks_exact(LANES));
            for ((ax, ay), s) in groups {
                for l in 0..LANES {
                    x[l] += ax[l] * s[l];
                    y[l] += ay[l] * s[l];
                }
            }
            o[0] += x.iter().sum::<f64>();
            o[1] += y.iter().sum::<f64>();
            if j < last {
                self.rotate();
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
        let mut g = SineGrid::new(&sum);
        // Errors relative to the size of each derivative (sum of its amplitudes).
        let scale = sum.parts().iter().fold([0.0; 3], |s, p| {
            [
                s[0] + p.amp,
                s[1] + p.amp * p.omega,
                s[2] + p.amp * p.omega * p.omega,
            ]
        });
        let mut worst: f64 = 0.0;
        // 40 blocks of 8 steps: through two re-anchorings.
        for k in 0..40u64 {
            let start = t0 + (8 * k) as f64 * dt;
            let mut grid = [[0.0; 3]; 9];
            g.add_kinematics(k, start, dt, &mut grid);
            for (j, x) in grid.iter().enumerate() {
                let e = sum.eval(start + j as f64 * dt);
                for i in 0..3 {
                    worst = worst.max((x[i] - e[i]).abs() / scale[i]);
                }
            }
        }
        // sin of an argument near 1e6 rad is itself only good to about 1e-10.
        assert!(worst < 1e-9, "{worst:e}");
    }
}
