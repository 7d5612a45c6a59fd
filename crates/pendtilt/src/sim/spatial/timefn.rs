//! Scalar time functions with exact derivatives, the building blocks of MODEL.md 7.7's
//! prescribed motion: const, ramp, sigmoid, bump, sine, chirp, engine-locked sine and the
//! lateral-acceleration roll of a turning vehicle.
//!
//! A value travels as a [`Jet`] (x, x', x'', x'''): products (a road-induced sine scaled by
//! v(t) / speed_ref, the turn roll v yaw') then keep exact second derivatives, which is what
//! the body's angular acceleration needs. Nothing here differentiates numerically.

use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

use crate::sim::planar::motion::logistic;

/// (x, x', x'', x''') at one instant.
pub type Jet = [f64; 4];

/// The zero jet.
pub const ZERO: Jet = [0.0; 4];

/// a + b.
#[inline]
pub fn add(a: Jet, b: Jet) -> Jet {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

/// k a.
#[inline]
pub fn scale(a: Jet, k: f64) -> Jet {
    a.map(|x| k * x)
}

/// The product a b with its derivatives (Leibniz's rule).
#[inline]
pub fn mul(a: Jet, b: Jet) -> Jet {
    [
        a[0] * b[0],
        a[1] * b[0] + a[0] * b[1],
        a[2] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[2],
        a[3] * b[0] + 3.0 * a[2] * b[1] + 3.0 * a[1] * b[2] + a[0] * b[3],
    ]
}

/// sin(phi(t)) from the jet of phi (chain rule).
#[inline]
pub fn sin_of(phi: Jet) -> Jet {
    let (s, c) = phi[0].sin_cos();
    let (p1, p2, p3) = (phi[1], phi[2], phi[3]);
    [
        s,
        c * p1,
        c * p2 - s * p1 * p1,
        c * p3 - 3.0 * s * p1 * p2 - c * p1 * p1 * p1,
    ]
}

/// The logistic S(x) = 1 / (1 + e^-x) and its first five derivatives (a bump is S', so its
/// third derivative is S''''). The first four are `sim::motion::logistic`'s; the
/// rest follow from S' = S (1 - S).
pub fn logistic5(x: f64) -> [f64; 6] {
    let [s, d1, d2, d3] = logistic(x);
    let k = 1.0 - 2.0 * s;
    let d4 = d3 * k - 6.0 * d1 * d2;
    let d5 = d4 * k - 8.0 * d1 * d3 - 6.0 * d2 * d2;
    [s, d1, d2, d3, d4, d5]
}

/// ln(1 + e^x) without overflow: the integral of S.
fn softplus(x: f64) -> f64 {
    x.max(0.0) + (-x.abs()).exp().ln_1p()
}

/// One component of a time function (MODEL.md 7.7). Amplitudes are in the quantity's
/// units: degrees for an angle in a scenario file (radians once built), m/s for the speed,
/// m for the heave, m/s^2 for a vibration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// A constant.
    Const {
        /// The value.
        value: f64,
    },
    /// rate t.
    Ramp {
        /// Per second.
        rate: f64,
    },
    /// amp S((t - t0) / tau), S = 1 / (1 + e^-x).
    Sigmoid {
        /// Total change.
        amp: f64,
        /// Mid-point \[s\].
        t0: f64,
        /// Time constant \[s\] (peak rate amp / (4 tau)).
        tau: f64,
    },
    /// 4 amp S(x) (1 - S(x)), x = (t - t0) / tau: a sigmoid's rate shape, peak `amp`.
    Bump {
        /// Peak.
        amp: f64,
        /// Centre \[s\].
        t0: f64,
        /// Time constant \[s\].
        tau: f64,
    },
    /// amp sin(2 pi freq t + phase).
    Sine {
        /// Amplitude.
        amp: f64,
        /// Frequency \[Hz\].
        freq: f64,
        /// Phase at t = 0 \[rad\].
        phase: f64,
    },
    /// amp sin(2 pi (f0 t + (f1 - f0) t^2 / (2 t1)) + phase): a linear sweep from f0 at
    /// t = 0 to f1 at t1.
    Chirp {
        /// Amplitude.
        amp: f64,
        /// Start frequency \[Hz\].
        f0: f64,
        /// Frequency at t1 \[Hz\].
        f1: f64,
        /// Sweep time \[s\].
        t1: f64,
        /// Phase at t = 0 \[rad\].
        phase: f64,
    },
    /// amp sin(k psi_e(t) + phase): locked to the engine's phase psi_e (7.7).
    Engine {
        /// Amplitude.
        amp: f64,
        /// Harmonic k of the engine frequency.
        harmonic: f64,
        /// Phase at t = 0 \[rad\].
        phase: f64,
    },
    /// Roll only: per_g a_lat / g, a_lat = v yaw_path' the vehicle's lateral acceleration
    /// (a car rolls outward in a turn: positive, right side down, in a left turn).
    Lateral {
        /// Roll per g of lateral acceleration.
        per_g: f64,
    },
}

/// What a component may depend on besides t: the vehicle's speed, the engine's phase and
/// the lateral acceleration, each as a jet.
#[derive(Debug, Clone, Copy, Default)]
pub struct Context {
    /// v(t) \[m/s\].
    pub speed: Jet,
    /// psi_e(t) \[rad\].
    pub engine: Jet,
    /// a_lat / g = v yaw_path' / g (the third derivative is not kept: 0).
    pub lateral_g: Jet,
}

impl Shape {
    /// This shape with every amplitude-like value multiplied by `k` (degrees to radians).
    pub fn scaled(self, k: f64) -> Self {
        use Shape::*;
        match self {
            Const { value } => Const { value: k * value },
            Ramp { rate } => Ramp { rate: k * rate },
            Sigmoid { amp, t0, tau } => Sigmoid {
                amp: k * amp,
                t0,
                tau,
            },
            Bump { amp, t0, tau } => Bump {
                amp: k * amp,
                t0,
                tau,
            },
            Sine { amp, freq, phase } => Sine {
                amp: k * amp,
                freq,
                phase,
            },
            Chirp {
                amp,
                f0,
                f1,
                t1,
                phase,
            } => Chirp {
                amp: k * amp,
                f0,
                f1,
                t1,
                phase,
            },
            Engine {
                amp,
                harmonic,
                phase,
            } => Engine {
                amp: k * amp,
                harmonic,
                phase,
            },
            Lateral { per_g } => Lateral { per_g: k * per_g },
        }
    }

    /// The short name written in a scenario file.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Const { .. } => "const",
            Shape::Ramp { .. } => "ramp",
            Shape::Sigmoid { .. } => "sigmoid",
            Shape::Bump { .. } => "bump",
            Shape::Sine { .. } => "sine",
            Shape::Chirp { .. } => "chirp",
            Shape::Engine { .. } => "engine",
            Shape::Lateral { .. } => "lateral",
        }
    }

    /// The numbers that must be finite, and the ones that must also be > 0, with names.
    pub fn check(&self) -> Result<(), String> {
        type Named = Vec<(&'static str, f64)>;
        let (all, positive): (Named, Named) = match *self {
            Shape::Const { value } => (vec![("value", value)], vec![]),
            Shape::Ramp { rate } => (vec![("rate", rate)], vec![]),
            Shape::Sigmoid { amp, t0, tau } | Shape::Bump { amp, t0, tau } => {
                (vec![("amp", amp), ("t0", t0)], vec![("tau", tau)])
            }
            Shape::Sine { amp, freq, phase } => {
                (vec![("amp", amp), ("freq", freq), ("phase", phase)], vec![])
            }
            Shape::Chirp {
                amp,
                f0,
                f1,
                t1,
                phase,
            } => (
                vec![("amp", amp), ("f0", f0), ("f1", f1), ("phase", phase)],
                vec![("t1", t1)],
            ),
            Shape::Engine {
                amp,
                harmonic,
                phase,
            } => (
                vec![("amp", amp), ("phase", phase)],
                vec![("harmonic", harmonic)],
            ),
            Shape::Lateral { per_g } => (vec![("per_g", per_g)], vec![]),
        };
        for (k, v) in all {
            if !v.is_finite() {
                return Err(format!("{}.{k} must be finite, got {v:?}", self.kind()));
            }
        }
        for (k, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{}.{k} must be > 0, got {v:?}", self.kind()));
            }
        }
        Ok(())
    }

    /// The jet at time `t` \[s\].
    pub fn eval(&self, t: f64, ctx: &Context) -> Jet {
        match *self {
            Shape::Const { value } => [value, 0.0, 0.0, 0.0],
            Shape::Ramp { rate } => [rate * t, rate, 0.0, 0.0],
            Shape::Sigmoid { amp, t0, tau } => {
                let s = logistic5((t - t0) / tau);
                core::array::from_fn(|i| amp * s[i] / tau.powi(i as i32))
            }
            Shape::Bump { amp, t0, tau } => {
                let s = logistic5((t - t0) / tau);
                core::array::from_fn(|i| 4.0 * amp * s[i + 1] / tau.powi(i as i32))
            }
            Shape::Sine { amp, freq, phase } => {
                let w = TAU * freq;
                scale(sin_of([w * t + phase, w, 0.0, 0.0]), amp)
            }
            Shape::Chirp {
                amp,
                f0,
                f1,
                t1,
                phase,
            } => {
                let k = (f1 - f0) / t1;
                let phi = [
                    TAU * (f0 * t + 0.5 * k * t * t) + phase,
                    TAU * (f0 + k * t),
                    TAU * k,
                    0.0,
                ];
                scale(sin_of(phi), amp)
            }
            Shape::Engine {
                amp,
                harmonic,
                phase,
            } => {
                let mut phi = scale(ctx.engine, harmonic);
                phi[0] += phase;
                scale(sin_of(phi), amp)
            }
            Shape::Lateral { per_g } => scale(ctx.lateral_g, per_g),
        }
    }

    /// The integral from 0 to `t` of a speed component (const, ramp, sigmoid, bump, sine);
    /// the engine's phase needs it. `None` for the other shapes.
    pub fn integral(&self, t: f64) -> Option<f64> {
        Some(match *self {
            Shape::Const { value } => value * t,
            Shape::Ramp { rate } => 0.5 * rate * t * t,
            Shape::Sigmoid { amp, t0, tau } => {
                amp * tau * (softplus((t - t0) / tau) - softplus(-t0 / tau))
            }
            Shape::Bump { amp, t0, tau } => {
                4.0 * amp * tau * (logistic((t - t0) / tau)[0] - logistic(-t0 / tau)[0])
            }
            Shape::Sine { amp, freq, phase } => {
                let w = TAU * freq;
                amp / w * (phase.cos() - (w * t + phase).cos())
            }
            _ => return None,
        })
    }
}

/// The jet of a sum of shapes.
pub fn eval_sum<'a>(shapes: impl IntoIterator<Item = &'a Shape>, t: f64, ctx: &Context) -> Jet {
    shapes
        .into_iter()
        .fold(ZERO, |acc, s| add(acc, s.eval(t, ctx)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_shapes() -> Vec<Shape> {
        vec![
            Shape::Const { value: 0.3 },
            Shape::Ramp { rate: -0.2 },
            Shape::Sigmoid {
                amp: 1.5,
                t0: 1.0,
                tau: 0.4,
            },
            Shape::Bump {
                amp: 0.7,
                t0: 1.2,
                tau: 0.3,
            },
            Shape::Sine {
                amp: 0.5,
                freq: 0.8,
                phase: 0.4,
            },
            Shape::Chirp {
                amp: 0.2,
                f0: 0.5,
                f1: 2.0,
                t1: 3.0,
                phase: 1.0,
            },
            Shape::Engine {
                amp: 0.1,
                harmonic: 2.0,
                phase: 0.3,
            },
            Shape::Lateral { per_g: 0.07 },
        ]
    }

    /// A context whose jets are themselves consistent (a sine speed, a chirp-like engine).
    fn ctx(t: f64) -> Context {
        let speed = add(
            [5.0, 0.0, 0.0, 0.0],
            Shape::Sine {
                amp: 1.0,
                freq: 0.3,
                phase: 0.0,
            }
            .eval(t, &Context::default()),
        );
        let engine = [TAU * (10.0 * t + 0.5 * t * t), TAU * (10.0 + t), TAU, 0.0];
        let lat = [0.2 * t.sin(), 0.2 * t.cos(), -0.2 * t.sin(), 0.0];
        Context {
            speed,
            engine,
            lateral_g: lat,
        }
    }

    /// Central differences of each derivative agree with the next one (to 1e-6 of that
    /// derivative's largest size over the run).
    #[test]
    fn derivatives_are_exact() {
        let h = 1e-5;
        let times: Vec<f64> = (0..60).map(|i| 0.05 * i as f64).collect();
        for s in all_shapes() {
            // The lateral roll keeps no third derivative.
            let orders = if matches!(s, Shape::Lateral { .. }) {
                2
            } else {
                3
            };
            let size = times.iter().fold([0f64; 4], |m, &t| {
                let j = s.eval(t, &ctx(t));
                core::array::from_fn(|k| m[k].max(j[k].abs()))
            });
            for &t in &times {
                let (j, jp, jm) = (
                    s.eval(t, &ctx(t)),
                    s.eval(t + h, &ctx(t + h)),
                    s.eval(t - h, &ctx(t - h)),
                );
                for k in 0..orders {
                    let fd = (jp[k] - jm[k]) / (2.0 * h);
                    let tol = 1e-6 * (1.0 + size[k + 1]);
                    assert!(
                        (fd - j[k + 1]).abs() < tol,
                        "{s:?} t {t} order {k}: {fd} {}",
                        j[k + 1]
                    );
                }
            }
        }
    }

    /// The integrals of the speed components differentiate to the components.
    #[test]
    fn integrals_differentiate_back() {
        let h = 1e-5;
        for s in &all_shapes()[..5] {
            assert_eq!(s.integral(0.0), Some(0.0));
            for i in 0..40 {
                let t = 0.07 * i as f64 + 0.01;
                let fd = (s.integral(t + h).unwrap() - s.integral(t - h).unwrap()) / (2.0 * h);
                let v = s.eval(t, &Context::default())[0];
                assert!((fd - v).abs() < 1e-8, "{s:?} t {t}: {fd} {v}");
            }
        }
        assert!(all_shapes()[5].integral(1.0).is_none());
    }

    /// The products' derivatives follow Leibniz's rule: (sin t cos t) = sin(2t) / 2.
    #[test]
    fn product_rule_by_hand() {
        let t = 0.7f64;
        let a = sin_of([t, 1.0, 0.0, 0.0]);
        let b = sin_of([t + std::f64::consts::FRAC_PI_2, 1.0, 0.0, 0.0]);
        let p = mul(a, b);
        let e = [
            0.5 * (2.0 * t).sin(),
            (2.0 * t).cos(),
            -2.0 * (2.0 * t).sin(),
            -4.0 * (2.0 * t).cos(),
        ];
        for k in 0..4 {
            assert!((p[k] - e[k]).abs() < 1e-14, "{k}");
        }
    }

    #[test]
    fn check_names_the_field() {
        let e = Shape::Sigmoid {
            amp: 1.0,
            t0: 0.0,
            tau: 0.0,
        }
        .check()
        .unwrap_err();
        assert!(e.contains("sigmoid.tau"), "{e}");
    }
}
