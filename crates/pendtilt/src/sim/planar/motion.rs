//! Prescribed body motion: the tilt theta(t) with exact theta' and theta''.
//!
//! The body is driven, not simulated: each [`Motion`] is a closed-form theta(t) whose
//! derivatives are computed analytically, so the only approximation in a run is the
//! integration of the pendulum. Angles in rad, times in s, frequencies in Hz.

use rand::Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

use super::sines::{SineGrid, SineSum, Sinusoid};
use super::SimError;

/// Degrees to radians, for the defaults below.
const DEG: f64 = std::f64::consts::PI / 180.0;

/// Tilt, tilt rate and tilt acceleration at one instant: theta \[rad\], theta' \[rad/s\],
/// theta'' \[rad/s^2\].
pub type Kinematics = [f64; 3];

/// How the body tilts. Selected in a scenario TOML by `kind = "..."` in the `[motion]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Motion {
    /// Held at a constant tilt.
    Still(Still),
    /// The paper's Fig. 5 input: a logistic sigmoid.
    Sigmoid(Sigmoid),
    /// A steep sigmoid standing in for a step (a true step has infinite theta'').
    Step(Step),
    /// theta = offset + amplitude sin(2 pi f t + phase).
    Sine(Sine),
    /// A linear frequency sweep.
    Chirp(Chirp),
    /// Seeded, band-limited random tilting: the slow leaning of a ridden scooter.
    Manoeuvres(Manoeuvres),
}

/// Constant tilt.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Still {
    /// The tilt \[rad\]. Default 0.
    pub angle: f64,
}

impl Default for Still {
    fn default() -> Self {
        Self { angle: 0.0 }
    }
}

/// theta(t) = offset + amplitude S((t - t0) / tau), S(x) = 1 / (1 + e^-x) (MODEL.md section 6).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sigmoid {
    /// Total change A \[rad\]. Default 10 deg = 0.1745 rad.
    pub amplitude: f64,
    /// Mid-point time t0 \[s\]. Default 2 s.
    pub t0: f64,
    /// Time constant tau \[s\] (10-90 % rise = 4.39 tau). Default 0.2 s.
    pub tau: f64,
    /// Tilt before the change \[rad\]. Default 0.
    pub offset: f64,
}

impl Default for Sigmoid {
    fn default() -> Self {
        Self {
            amplitude: 10.0 * DEG,
            t0: 2.0,
            tau: 0.2,
            offset: 0.0,
        }
    }
}

/// A steep sigmoid: the same formula as [`Sigmoid`] with a short time constant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Step {
    /// Step height \[rad\]. Default 10 deg = 0.1745 rad.
    pub amplitude: f64,
    /// Step time (mid-point) \[s\]. Default 1 s.
    pub t0: f64,
    /// Time constant \[s\]: 10-90 % rise of 4.39 tau = 22 ms. Default 5 ms.
    pub tau: f64,
    /// Tilt before the step \[rad\]. Default 0.
    pub offset: f64,
}

impl Default for Step {
    fn default() -> Self {
        Self {
            amplitude: 10.0 * DEG,
            t0: 1.0,
            tau: 0.005,
            offset: 0.0,
        }
    }
}

/// theta = offset + amplitude sin(2 pi frequency t + phase).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sine {
    /// Amplitude \[rad\]. Default 10 deg = 0.1745 rad.
    pub amplitude: f64,
    /// Frequency \[Hz\]. Default 0.5 Hz.
    pub frequency: f64,
    /// Phase at t = 0 \[rad\]. Default 0.
    pub phase: f64,
    /// Mean tilt \[rad\]. Default 0.
    pub offset: f64,
}

impl Default for Sine {
    fn default() -> Self {
        Self {
            amplitude: 10.0 * DEG,
            frequency: 0.5,
            phase: 0.0,
            offset: 0.0,
        }
    }
}

/// theta = offset + amplitude sin(psi(t)), psi' = 2 pi f(t), f rising linearly from `f0` at
/// t = 0 to `f1` at `sweep_time`, then staying at `f1`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Chirp {
    /// Amplitude \[rad\]. Default 5 deg = 0.0873 rad.
    pub amplitude: f64,
    /// Start frequency \[Hz\]. Default 0.1 Hz.
    pub f0: f64,
    /// End frequency \[Hz\]. Default 5 Hz (past the default pendulum's 2.19 Hz).
    pub f1: f64,
    /// Sweep duration \[s\]. Default 20 s (the chirp scenario's duration).
    pub sweep_time: f64,
    /// Mean tilt \[rad\]. Default 0.
    pub offset: f64,
}

impl Default for Chirp {
    fn default() -> Self {
        Self {
            amplitude: 5.0 * DEG,
            f0: 0.1,
            f1: 5.0,
            sweep_time: 20.0,
            offset: 0.0,
        }
    }
}

/// Band-limited random tilting, soft-limited to +-amplitude:
/// theta = offset + A tanh(u(t) / A), u = sum of `components` sinusoids of equal amplitude
/// (RMS of u = `rms`), frequencies uniform in `band`, phases uniform; all drawn from the
/// run's seed. tanh keeps |theta - offset| < A while leaving small tilts almost untouched,
/// and its derivatives are exact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Manoeuvres {
    /// Soft limit A \[rad\]. Default 15 deg = 0.2618 rad.
    pub amplitude: f64,
    /// RMS of the signal before limiting \[rad\]. Default 7 deg = 0.1222 rad.
    pub rms: f64,
    /// Frequency band \[Hz\]. Default \[0.05, 0.8\] Hz: below 1 Hz, as a ridden scooter.
    pub band: [f64; 2],
    /// Number of sinusoids. Default 12.
    pub components: u32,
    /// Mean tilt \[rad\]. Default 0.
    pub offset: f64,
}

impl Default for Manoeuvres {
    fn default() -> Self {
        Self {
            amplitude: 15.0 * DEG,
            rms: 7.0 * DEG,
            band: [0.05, 0.8],
            components: 12,
            offset: 0.0,
        }
    }
}

fn check(ok: bool, key: &str, reason: impl Into<String>) -> Result<(), SimError> {
    if ok {
        Ok(())
    } else {
        Err(SimError::invalid(key, reason))
    }
}

fn finite(x: f64, key: &str) -> Result<(), SimError> {
    check(
        x.is_finite(),
        key,
        format!("must be a finite number, got {x:?}"),
    )
}

fn positive(x: f64, key: &str) -> Result<(), SimError> {
    check(
        x.is_finite() && x > 0.0,
        key,
        format!("must be > 0, got {x:?}"),
    )
}

fn non_negative(x: f64, key: &str) -> Result<(), SimError> {
    check(
        x.is_finite() && x >= 0.0,
        key,
        format!("must be >= 0, got {x:?}"),
    )
}

impl Motion {
    /// The `kind` name as written in TOML.
    pub fn kind(&self) -> &'static str {
        match self {
            Motion::Still(_) => "still",
            Motion::Sigmoid(_) => "sigmoid",
            Motion::Step(_) => "step",
            Motion::Sine(_) => "sine",
            Motion::Chirp(_) => "chirp",
            Motion::Manoeuvres(_) => "manoeuvres",
        }
    }

    /// Checks every value; errors name the key (`motion.<field>`) and why.
    pub fn validate(&self) -> Result<(), SimError> {
        match self {
            Motion::Still(m) => finite(m.angle, "motion.angle"),
            Motion::Sigmoid(Sigmoid {
                amplitude,
                t0,
                tau,
                offset,
            })
            | Motion::Step(Step {
                amplitude,
                t0,
                tau,
                offset,
            }) => {
                finite(*amplitude, "motion.amplitude")?;
                finite(*t0, "motion.t0")?;
                positive(*tau, "motion.tau")?;
                finite(*offset, "motion.offset")
            }
            Motion::Sine(m) => {
                finite(m.amplitude, "motion.amplitude")?;
                non_negative(m.frequency, "motion.frequency")?;
                finite(m.phase, "motion.phase")?;
                finite(m.offset, "motion.offset")
            }
            Motion::Chirp(m) => {
                finite(m.amplitude, "motion.amplitude")?;
                non_negative(m.f0, "motion.f0")?;
                non_negative(m.f1, "motion.f1")?;
                positive(m.sweep_time, "motion.sweep_time")?;
                finite(m.offset, "motion.offset")
            }
            Motion::Manoeuvres(m) => {
                positive(m.amplitude, "motion.amplitude")?;
                non_negative(m.rms, "motion.rms")?;
                non_negative(m.band[0], "motion.band")?;
                check(
                    m.band[1].is_finite() && m.band[1] >= m.band[0],
                    "motion.band",
                    format!(
                        "must be [low, high] with 0 <= low <= high, got {:?}",
                        m.band
                    ),
                )?;
                check(
                    (1..=10_000).contains(&m.components),
                    "motion.components",
                    format!("must be 1 ..= 10000, got {}", m.components),
                )?;
                finite(m.offset, "motion.offset")
            }
        }
    }

    /// Scales the motion's size (`amplitude`, or `angle` for [`Motion::Still`]) to `value` \[rad\].
    pub fn set_amplitude(&mut self, value: f64) {
        match self {
            Motion::Still(m) => m.angle = value,
            Motion::Sigmoid(m) => m.amplitude = value,
            Motion::Step(m) => m.amplitude = value,
            Motion::Sine(m) => m.amplitude = value,
            Motion::Chirp(m) => m.amplitude = value,
            Motion::Manoeuvres(m) => {
                // Keep the ratio of rms to limit, so the shape of the ride stays the same.
                if m.amplitude > 0.0 {
                    m.rms *= value / m.amplitude;
                }
                m.amplitude = value;
            }
        }
    }

    /// Builds the time function, drawing any random parts from `rng`.
    pub fn build<R: Rng>(&self, rng: &mut R) -> MotionFn {
        match self {
            Motion::Still(m) => MotionFn::Still(m.angle),
            Motion::Sigmoid(m) => MotionFn::Sigmoid {
                a: m.amplitude,
                t0: m.t0,
                tau: m.tau,
                offset: m.offset,
            },
            Motion::Step(m) => MotionFn::Sigmoid {
                a: m.amplitude,
                t0: m.t0,
                tau: m.tau,
                offset: m.offset,
            },
            Motion::Sine(m) => {
                let sum = SineSum::new(vec![Sinusoid::scalar(m.amplitude, m.frequency, m.phase)]);
                MotionFn::Sines {
                    grid: Box::new(SineGrid::new(&sum)),
                    sum,
                    offset: m.offset,
                    limit: None,
                }
            }
            Motion::Chirp(m) => MotionFn::Chirp(m.clone()),
            Motion::Manoeuvres(m) => {
                let n = m.components.max(1) as usize;
                let amp = m.rms * (2.0 / n as f64).sqrt();
                let parts = (0..n)
                    .map(|_| {
                        let f = m.band[0] + (m.band[1] - m.band[0]) * rng.random::<f64>();
                        let phase = TAU * rng.random::<f64>();
                        Sinusoid::scalar(amp, f, phase)
                    })
                    .collect();
                let sum = SineSum::new(parts);
                MotionFn::Sines {
                    grid: Box::new(SineGrid::new(&sum)),
                    sum,
                    offset: m.offset,
                    limit: Some(m.amplitude),
                }
            }
        }
    }
}

/// A [`Motion`] ready to evaluate (random parts drawn).
#[derive(Debug, Clone, PartialEq)]
pub enum MotionFn {
    /// Constant tilt \[rad\].
    Still(f64),
    /// offset + a S((t - t0) / tau).
    Sigmoid {
        /// Total change \[rad\].
        a: f64,
        /// Mid-point \[s\].
        t0: f64,
        /// Time constant \[s\].
        tau: f64,
        /// Initial tilt \[rad\].
        offset: f64,
    },
    /// offset + sum of sines, optionally soft-limited by `limit * tanh(. / limit)`.
    Sines {
        /// The sinusoids.
        sum: SineSum,
        /// The same, for evaluation block by block (boxed: it is large).
        grid: Box<SineGrid>,
        /// Mean tilt \[rad\].
        offset: f64,
        /// Soft limit \[rad\].
        limit: Option<f64>,
    },
    /// Linear sweep.
    Chirp(Chirp),
}

/// S and its first three derivatives of the logistic function, without overflow for large
/// |x| (the 3-D motion, `sim::spatial::motion`, needs the third for the body's angular acceleration).
pub(crate) fn logistic(x: f64) -> [f64; 4] {
    let s = if x >= 0.0 {
        1.0 / (1.0 + (-x).exp())
    } else {
        let e = x.exp();
        e / (1.0 + e)
    };
    let d1 = s * (1.0 - s);
    let d2 = d1 * (1.0 - 2.0 * s);
    [s, d1, d2, d2 * (1.0 - 2.0 * s) - 2.0 * d1 * d1]
}

/// theta = A tanh(u / A) and its derivatives, from u, u', u''.
fn soft_limit(u: [f64; 3], a: f64) -> [f64; 3] {
    let th = (u[0] / a).tanh();
    let sech2 = 1.0 - th * th;
    [
        a * th,
        sech2 * u[1],
        sech2 * u[2] - 2.0 / a * sech2 * th * u[1] * u[1],
    ]
}

impl MotionFn {
    /// theta, theta', theta'' at time `t`.
    pub fn eval(&self, t: f64) -> Kinematics {
        match self {
            MotionFn::Still(a) => [*a, 0.0, 0.0],
            MotionFn::Sigmoid { a, t0, tau, offset } => {
                let s = logistic((t - t0) / tau);
                [offset + a * s[0], a * s[1] / tau, a * s[2] / (tau * tau)]
            }
            MotionFn::Sines {
                sum, offset, limit, ..
            } => {
                let u = sum.eval(t);
                let k = match limit {
                    Some(a) => soft_limit(u, *a),
                    None => u,
                };
                [offset + k[0], k[1], k[2]]
            }
            MotionFn::Chirp(c) => {
                let k = (c.f1 - c.f0) / c.sweep_time;
                let (psi, dpsi, ddpsi) = if t <= c.sweep_time {
                    (
                        TAU * (c.f0 * t + 0.5 * k * t * t),
                        TAU * (c.f0 + k * t),
                        TAU * k,
                    )
                } else {
                    let ts = c.sweep_time;
                    (
                        TAU * (c.f0 * ts + 0.5 * k * ts * ts + c.f1 * (t - ts)),
                        TAU * c.f1,
                        0.0,
                    )
                };
                let (s, co) = psi.sin_cos();
                let a = c.amplitude;
                [
                    c.offset + a * s,
                    a * co * dpsi,
                    a * (co * ddpsi - s * dpsi * dpsi),
                ]
            }
        }
    }

    /// Writes theta, theta', theta'' at `t0 + j * dt` into `out[j]` (overwriting), for
    /// block number `block`; consecutive blocks share their end point (see
    /// [`SineGrid::add_kinematics`]).
    pub fn fill(&mut self, block: u64, t0: f64, dt: f64, out: &mut [Kinematics]) {
        match self {
            MotionFn::Sines {
                grid,
                offset,
                limit,
                ..
            } => {
                out.iter_mut().for_each(|o| *o = [0.0; 3]);
                grid.add_kinematics(block, t0, dt, out);
                for o in out.iter_mut() {
                    if let Some(a) = limit {
                        *o = soft_limit(*o, *a);
                    }
                    o[0] += *offset;
                }
            }
            _ => {
                for (j, o) in out.iter_mut().enumerate() {
                    *o = self.eval(t0 + j as f64 * dt);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Central differences of theta and theta' agree with the analytic derivatives.
    fn check_derivatives(m: &Motion) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let f = m.build(&mut rng);
        let h = 1e-5;
        for i in 0..200 {
            let t = 0.037 * i as f64;
            let k = f.eval(t);
            let (kp, km) = (f.eval(t + h), f.eval(t - h));
            let d1 = (kp[0] - km[0]) / (2.0 * h);
            let d2 = (kp[1] - km[1]) / (2.0 * h);
            assert!(
                (d1 - k[1]).abs() < 1e-6 * (1.0 + k[1].abs()),
                "{m:?} t={t} {d1} {}",
                k[1]
            );
            assert!(
                (d2 - k[2]).abs() < 1e-5 * (1.0 + k[2].abs()),
                "{m:?} t={t} {d2} {}",
                k[2]
            );
        }
    }

    #[test]
    fn derivatives_are_exact() {
        check_derivatives(&Motion::Sigmoid(Sigmoid::default()));
        check_derivatives(&Motion::Step(Step {
            tau: 0.05,
            ..Step::default()
        }));
        check_derivatives(&Motion::Sine(Sine::default()));
        check_derivatives(&Motion::Chirp(Chirp {
            sweep_time: 4.0,
            ..Chirp::default()
        }));
        check_derivatives(&Motion::Manoeuvres(Manoeuvres::default()));
    }

    #[test]
    fn manoeuvres_stay_within_limit() {
        let m = Manoeuvres::default();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let f = Motion::Manoeuvres(m.clone()).build(&mut rng);
        let mut peak: f64 = 0.0;
        for i in 0..100_000 {
            peak = peak.max(f.eval(i as f64 * 0.01)[0].abs());
        }
        assert!(peak < m.amplitude);
        assert!(peak > 0.5 * m.amplitude, "peak {peak}");
    }

    #[test]
    fn grid_fill_matches_eval() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let mut f = Motion::Manoeuvres(Manoeuvres::default()).build(&mut rng);
        let mut out = [[0.0; 3]; 9];
        for k in 0..40u64 {
            let t0 = 12.5 + k as f64 * 1e-3;
            f.fill(k, t0, 1.25e-4, &mut out);
            for (j, o) in out.iter().enumerate() {
                let e = f.eval(t0 + j as f64 * 1.25e-4);
                for i in 0..3 {
                    assert!((o[i] - e[i]).abs() < 1e-12 * (1.0 + e[i].abs()));
                }
            }
        }
    }
}
