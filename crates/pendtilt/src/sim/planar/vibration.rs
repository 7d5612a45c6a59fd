//! Floor vibration: engine harmonics and broadband random vibration as a translational
//! acceleration of P1 in body axes, and a small angular vibration of the body.
//!
//! Harmonics follow MODEL.md section 6: `amp * sin(2 pi f t + phase)` along a body-axis
//! direction. Broadband vibration is Gaussian white noise at the integration node rate
//! (sample rate x substeps), band-passed by a 2nd-order Butterworth high-pass and low-pass,
//! scaled to the requested RMS, and linear between nodes (so RK4 sees a smooth forcing
//! inside each step). The filters are run in before t = 0 so the RMS is steady from the
//! first sample.

use rand::Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

use super::motion::Kinematics;
use super::sines::{SineGrid, SineSum, Sinusoid};
use super::SimError;

/// One vibration harmonic of P1: `amplitude * sin(2 pi frequency t + phase)` along `axis`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Harmonic {
    /// Frequency \[Hz\].
    pub frequency: f64,
    /// Amplitude (peak) \[m/s^2\].
    pub amplitude: f64,
    /// Direction in body axes \[x, y\]; normalised on use. Default \[0, 1\] (body up).
    #[serde(default = "up")]
    pub axis: [f64; 2],
    /// Phase at t = 0 \[rad\]. Default 0.
    #[serde(default)]
    pub phase: f64,
}

fn up() -> [f64; 2] {
    [0.0, 1.0]
}

/// Broadband random vibration of P1: independent band-limited Gaussian noise on each body axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Broadband {
    /// RMS on body x and y \[m/s^2\]; \[0, 0\] switches it off. Default \[0, 0\] (the `scooter`
    /// scenario sets its own).
    pub rms: [f64; 2],
    /// Pass band \[low, high\] \[Hz\] (2nd-order Butterworth edges; low = 0 means no
    /// high-pass). high must stay below 0.45 x the node rate. Default \[5, 200\] Hz.
    pub band: [f64; 2],
}

impl Default for Broadband {
    fn default() -> Self {
        Self {
            rms: [0.0, 0.0],
            band: [5.0, 200.0],
        }
    }
}

/// One harmonic of the body's angular vibration, added to theta:
/// `amplitude * sin(2 pi frequency t + phase)` \[rad\].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AngularHarmonic {
    /// Frequency \[Hz\].
    pub frequency: f64,
    /// Amplitude \[rad\].
    pub amplitude: f64,
    /// Phase at t = 0 \[rad\]. Default 0.
    #[serde(default)]
    pub phase: f64,
}

/// Everything that shakes the body. Default: nothing.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Vibration {
    /// Translational harmonics of P1 (engine), body axes.
    pub harmonics: Vec<Harmonic>,
    /// Broadband random translational vibration of P1, body axes.
    pub broadband: Broadband,
    /// Angular vibration of the body, added to the prescribed tilt.
    pub angular: Vec<AngularHarmonic>,
}

impl Vibration {
    /// Checks every value for a run whose integration nodes are `node_rate` apart \[Hz\].
    pub fn validate(&self, node_rate: f64) -> Result<(), SimError> {
        for (i, h) in self.harmonics.iter().enumerate() {
            let key = |f: &str| format!("vibration.harmonics[{i}].{f}");
            if !(h.frequency.is_finite() && h.frequency >= 0.0) {
                return Err(SimError::invalid(
                    key("frequency"),
                    format!("must be >= 0, got {:?}", h.frequency),
                ));
            }
            if !h.amplitude.is_finite() {
                return Err(SimError::invalid(key("amplitude"), "must be finite"));
            }
            if !h.phase.is_finite() {
                return Err(SimError::invalid(key("phase"), "must be finite"));
            }
            let n = h.axis[0].hypot(h.axis[1]);
            if !(n.is_finite() && n > 0.0) {
                return Err(SimError::invalid(
                    key("axis"),
                    format!("must be a non-zero direction [x, y], got {:?}", h.axis),
                ));
            }
        }
        for (i, h) in self.angular.iter().enumerate() {
            let key = |f: &str| format!("vibration.angular[{i}].{f}");
            if !(h.frequency.is_finite() && h.frequency >= 0.0) {
                return Err(SimError::invalid(
                    key("frequency"),
                    format!("must be >= 0, got {:?}", h.frequency),
                ));
            }
            if !h.amplitude.is_finite() || !h.phase.is_finite() {
                return Err(SimError::invalid(
                    key("amplitude"),
                    "amplitude and phase must be finite",
                ));
            }
        }
        let b = &self.broadband;
        if b.rms.iter().any(|r| !(r.is_finite() && *r >= 0.0)) {
            return Err(SimError::invalid(
                "vibration.broadband.rms",
                format!("must be [x, y] with both >= 0, got {:?}", b.rms),
            ));
        }
        if b.rms != [0.0, 0.0] {
            let [lo, hi] = b.band;
            if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo) {
                return Err(SimError::invalid(
                    "vibration.broadband.band",
                    format!("must be [low, high] with 0 <= low < high, got {:?}", b.band),
                ));
            }
            if hi >= 0.45 * node_rate {
                return Err(SimError::invalid(
                    "vibration.broadband.band",
                    format!(
                        "high edge {hi} Hz must be below 0.45 x the integration node rate \
                         ({node_rate} Hz = rate x substeps); raise substeps or lower the band"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Multiplies every vibration amplitude (translational and angular) by `k`.
    pub fn scale(&mut self, k: f64) {
        self.harmonics.iter_mut().for_each(|h| h.amplitude *= k);
        self.angular.iter_mut().for_each(|h| h.amplitude *= k);
        self.broadband.rms.iter_mut().for_each(|r| *r *= k);
    }

    /// Moves the engine to fundamental `hz`: every harmonic (translational and angular)
    /// keeps its ratio to the first translational harmonic's frequency.
    pub fn set_engine_frequency(&mut self, hz: f64) {
        let Some(f0) = self.harmonics.first().map(|h| h.frequency) else {
            return;
        };
        if f0 <= 0.0 {
            return;
        }
        let k = hz / f0;
        self.harmonics.iter_mut().for_each(|h| h.frequency *= k);
        self.angular.iter_mut().for_each(|h| h.frequency *= k);
    }

    /// True when nothing vibrates.
    pub fn is_quiet(&self) -> bool {
        self.harmonics.iter().all(|h| h.amplitude == 0.0)
            && self.angular.iter().all(|h| h.amplitude == 0.0)
            && self.broadband.rms == [0.0, 0.0]
    }
}

/// A direct-form-II-transposed biquad.
#[derive(Debug, Clone, Copy)]
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
    z: [f64; 2],
}

impl Biquad {
    /// 2nd-order Butterworth by the bilinear transform (RBJ cookbook, Q = 1/sqrt 2).
    fn butterworth(fc: f64, fs: f64, high_pass: bool) -> Self {
        let w = TAU * fc / fs;
        let (s, c) = w.sin_cos();
        let alpha = s / (2.0 * std::f64::consts::FRAC_1_SQRT_2);
        let a0 = 1.0 + alpha;
        let b = if high_pass {
            [(1.0 + c) / 2.0, -(1.0 + c), (1.0 + c) / 2.0]
        } else {
            [(1.0 - c) / 2.0, 1.0 - c, (1.0 - c) / 2.0]
        };
        Self {
            b: [b[0] / a0, b[1] / a0, b[2] / a0],
            a: [-2.0 * c / a0, (1.0 - alpha) / a0],
            z: [0.0; 2],
        }
    }

    #[inline]
    fn step(&mut self, x: f64) -> f64 {
        let y = self.b[0] * x + self.z[0];
        self.z[0] = self.b[1] * x - self.a[0] * y + self.z[1];
        self.z[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// A band-pass chain (high-pass then low-pass) for one axis.
#[derive(Debug, Clone)]
struct BandPass {
    stages: Vec<Biquad>,
}

impl BandPass {
    fn new(lo: f64, hi: f64, fs: f64) -> Self {
        let mut stages = Vec::new();
        if lo > 0.0 {
            stages.push(Biquad::butterworth(lo, fs, true));
        }
        stages.push(Biquad::butterworth(hi, fs, false));
        Self { stages }
    }

    #[inline]
    fn step(&mut self, x: f64) -> f64 {
        self.stages.iter_mut().fold(x, |v, s| s.step(v))
    }

    /// Sum of the squared impulse response: the output variance for unit-variance input.
    fn noise_gain(&self, n: usize) -> f64 {
        let mut f = self.clone();
        (0..n)
            .map(|i| {
                let y = f.step(if i == 0 { 1.0 } else { 0.0 });
                y * y
            })
            .sum()
    }
}

/// Broadband noise generator on one axis, producing one node per integration step.
#[derive(Debug, Clone)]
struct NoiseAxis {
    filter: BandPass,
    scale: f64,
}

/// The vibration of a run, with its random parts drawn.
#[derive(Debug, Clone)]
pub struct VibrationGen {
    harmonics: SineGrid,
    angular: SineGrid,
    broadband: Vec<(usize, NoiseAxis)>,
    /// Broadband acceleration at the last node \[m/s^2\], body axes.
    last_node: [f64; 2],
}

impl VibrationGen {
    /// Builds the generator for integration nodes at `node_rate` \[Hz\], warming the broadband
    /// filters up with draws from `rng` so that t = 0 is already in steady state.
    pub fn new<R: Rng>(v: &Vibration, node_rate: f64, rng: &mut R) -> Self {
        let harmonics = SineGrid::new(&SineSum::new(
            v.harmonics
                .iter()
                .map(|h| {
                    let n = h.axis[0].hypot(h.axis[1]);
                    Sinusoid {
                        dir: [h.axis[0] / n, h.axis[1] / n],
                        ..Sinusoid::scalar(h.amplitude, h.frequency, h.phase)
                    }
                })
                .collect(),
        ));
        let angular = SineGrid::new(&SineSum::new(
            v.angular
                .iter()
                .map(|h| Sinusoid::scalar(h.amplitude, h.frequency, h.phase))
                .collect(),
        ));
        let [lo, hi] = v.broadband.band;
        // Only used when the broadband part is on, and then validated: 0 <= lo < hi.
        // Long enough for the slowest pole (about 1 / (2 pi lo)) to die out many times over.
        let slow = if lo > 0.0 { lo } else { hi };
        let span = ((node_rate * 40.0 / (PI * slow)).ceil() as usize).clamp(1000, 4_000_000);
        let mut broadband = Vec::new();
        for (axis, &rms) in v.broadband.rms.iter().enumerate() {
            if rms > 0.0 {
                let filter = BandPass::new(lo, hi, node_rate);
                let scale = rms / filter.noise_gain(span).sqrt();
                broadband.push((axis, NoiseAxis { filter, scale }));
            }
        }
        let mut gen = Self {
            harmonics,
            angular,
            broadband,
            last_node: [0.0; 2],
        };
        if !gen.broadband.is_empty() {
            for _ in 0..span / 4 {
                gen.next_node(rng);
            }
        }
        gen
    }

    /// Draws the broadband acceleration at the next node.
    fn next_node<R: Rng>(&mut self, rng: &mut R) -> [f64; 2] {
        let mut a = [0.0; 2];
        for (axis, n) in self.broadband.iter_mut() {
            let x: f64 = rng.sample(StandardNormal);
            a[*axis] = n.scale * n.filter.step(x);
        }
        self.last_node = a;
        a
    }

    /// Fills the translational acceleration of P1 (body axes) at `t0 + j * dt` for
    /// `j = 0 .. out.len()`, where `dt` is half an integration step: even `j` are nodes
    /// (new broadband draws after the first), odd `j` are mid-points (linear interpolation).
    /// Consecutive calls must continue in time: `out[0]` repeats the previous call's last node.
    /// `block` numbers the calls (the sample index).
    pub fn fill_accel<R: Rng>(
        &mut self,
        block: u64,
        t0: f64,
        dt: f64,
        rng: &mut R,
        out: &mut [[f64; 2]],
    ) {
        out.iter_mut().for_each(|o| *o = [0.0; 2]);
        if !self.broadband.is_empty() {
            let mut prev = self.last_node;
            out[0] = prev;
            let mut j = 2;
            while j < out.len() {
                let next = self.next_node(rng);
                out[j] = next;
                out[j - 1] = [0.5 * (prev[0] + next[0]), 0.5 * (prev[1] + next[1])];
                prev = next;
                j += 2;
            }
        }
        self.harmonics.add_vectors(block, t0, dt, out);
    }

    /// Adds the angular vibration to theta, theta', theta'' at `t0 + j * dt`.
    pub fn add_angular(&mut self, block: u64, t0: f64, dt: f64, out: &mut [Kinematics]) {
        self.angular.add_kinematics(block, t0, dt, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn broadband_has_requested_rms() {
        let v = Vibration {
            broadband: Broadband {
                rms: [1.5, 2.5],
                band: [5.0, 200.0],
            },
            ..Vibration::default()
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut g = VibrationGen::new(&v, 4000.0, &mut rng);
        let mut out = [[0.0; 2]; 9];
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
        for k in 0..50_000 {
            g.fill_accel(k, k as f64 * 1e-3, 1.25e-4, &mut rng, &mut out);
            for o in &out[1..] {
                sx += o[0] * o[0];
                sy += o[1] * o[1];
                n += 1.0;
            }
        }
        let (rx, ry) = ((sx / n).sqrt(), (sy / n).sqrt());
        // Mid-points are averages, which lowers the RMS a little at the top of the band.
        assert!((rx / 1.5 - 1.0).abs() < 0.05, "rx {rx}");
        assert!((ry / 2.5 - 1.0).abs() < 0.05, "ry {ry}");
    }

    #[test]
    fn band_above_node_rate_is_rejected() {
        let v = Vibration {
            broadband: Broadband {
                rms: [1.0, 0.0],
                band: [5.0, 2000.0],
            },
            ..Vibration::default()
        };
        let e = v.validate(4000.0).unwrap_err().to_string();
        assert!(e.contains("vibration.broadband.band"), "{e}");
    }
}
