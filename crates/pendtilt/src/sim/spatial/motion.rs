//! Prescribed 6-DOF body motion with analytic derivatives (MODEL.md 7.1, 7.7).
//!
//! Roll, pitch and yaw are each a sum of [`Component`]s with exact first and second
//! derivatives; the body rate w and its derivative wd follow from 7.1's formula and its
//! exact time derivative, so the dynamics never see a finite difference. The translation of
//! P1 is a sum of sines per world axis, plus an optional vibration given in body axes.

use crate::sim::planar::motion::logistic;
use std::f64::consts::TAU;

/// One term of an angle's time function; every variant has exact 1st and 2nd derivatives
/// (the subset of MODEL.md 7.7's components the simulator core needs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Component {
    /// A constant \[rad\].
    Const(f64),
    /// rate * t \[rad/s\].
    Ramp(f64),
    /// amp sin(2 pi freq t + phase): amp \[rad\], freq \[Hz\], phase \[rad\].
    Sine {
        /// Amplitude \[rad\].
        amp: f64,
        /// Frequency \[Hz\].
        freq: f64,
        /// Phase at t = 0 \[rad\].
        phase: f64,
    },
    /// amp S((t - t0) / tau), S = 1 / (1 + e^-x).
    Sigmoid {
        /// Total change \[rad\].
        amp: f64,
        /// Mid-point \[s\].
        t0: f64,
        /// Time constant \[s\].
        tau: f64,
    },
    /// 4 amp S(x) (1 - S(x)), x = (t - t0) / tau: a sigmoid's rate shape, peak `amp`.
    Bump {
        /// Peak \[rad\].
        amp: f64,
        /// Centre \[s\].
        t0: f64,
        /// Time constant \[s\].
        tau: f64,
    },
}

impl Component {
    /// (x, x', x'') at time `t` \[rad, rad/s, rad/s^2\].
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match *self {
            Component::Const(c) => [c, 0.0, 0.0],
            Component::Ramp(r) => [r * t, r, 0.0],
            Component::Sine { amp, freq, phase } => {
                let w = TAU * freq;
                let (s, c) = (w * t + phase).sin_cos();
                [amp * s, amp * w * c, -amp * w * w * s]
            }
            Component::Sigmoid { amp, t0, tau } => {
                let s = logistic((t - t0) / tau);
                [amp * s[0], amp * s[1] / tau, amp * s[2] / (tau * tau)]
            }
            Component::Bump { amp, t0, tau } => {
                let s = logistic((t - t0) / tau);
                let k = 4.0 * amp;
                [k * s[1], k * s[2] / tau, k * s[3] / (tau * tau)]
            }
        }
    }
}

/// A sum of components: one Euler angle's time function.
pub type Angle = Vec<Component>;

fn eval_sum(parts: &[Component], t: f64) -> [f64; 3] {
    parts.iter().fold([0.0; 3], |acc, c| {
        let v = c.eval(t);
        [acc[0] + v[0], acc[1] + v[1], acc[2] + v[2]]
    })
}

/// A sinusoidal acceleration amp sin(2 pi freq t + phase) along `axis` \[m/s^2\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelSine {
    /// Amplitude \[m/s^2\] along `axis`.
    pub amp: f64,
    /// Frequency \[Hz\].
    pub freq: f64,
    /// Phase at t = 0 \[rad\].
    pub phase: f64,
    /// Direction (not normalised: the vector multiplies the sine).
    pub axis: [f64; 3],
}

fn accel_sum(parts: &[AccelSine], t: f64) -> [f64; 3] {
    parts.iter().fold([0.0; 3], |acc, a| {
        let s = a.amp * (TAU * a.freq * t + a.phase).sin();
        [
            acc[0] + s * a.axis[0],
            acc[1] + s * a.axis[1],
            acc[2] + s * a.axis[2],
        ]
    })
}

/// The body's state at one instant, everything the joint equations and sensors need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyKinematics {
    /// (roll, pitch, yaw), each as (x, x', x'') \[rad, rad/s, rad/s^2\] (ZYX, MODEL.md 7.1).
    pub euler: [[f64; 3]; 3],
    /// Body rate w, body axes \[rad/s\] (what a gyro reads).
    pub w: [f64; 3],
    /// wd = dw/dt, body axes \[rad/s^2\].
    pub wd: [f64; 3],
    /// Specific force at P1, body axes \[m/s^2\] (what an accelerometer at P1 reads).
    pub f_p1: [f64; 3],
}

impl BodyKinematics {
    /// From the Euler angles with their derivatives and the specific force at P1: w and wd
    /// by MODEL.md 7.1's formula and its exact derivative.
    pub fn from_euler(euler: [[f64; 3]; 3], f_p1: [f64; 3]) -> Self {
        let (w, wd) = body_rate(euler);
        Self { euler, w, wd, f_p1 }
    }
}

/// (w, wd) from (roll, pitch, yaw) and their 1st and 2nd derivatives (MODEL.md 7.1):
/// w = (r' - y' sp, p' cr + y' cp sr, -p' sr + y' cp cr) and its time derivative.
pub fn body_rate(euler: [[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let [[r, rd, rdd], [p, pd, pdd], [_, yd, ydd]] = euler;
    let (sr, cr) = r.sin_cos();
    let (sp, cp) = p.sin_cos();
    let w = [
        rd - yd * sp,
        pd * cr + yd * cp * sr,
        -pd * sr + yd * cp * cr,
    ];
    let wd = [
        rdd - ydd * sp - yd * pd * cp,
        pdd * cr - pd * rd * sr + ydd * cp * sr - yd * pd * sp * sr + yd * rd * cp * cr,
        -pdd * sr - pd * rd * cr + ydd * cp * cr - yd * pd * sp * cr - yd * rd * cp * sr,
    ];
    (w, wd)
}

/// R = Rz(yaw) Ry(pitch) Rx(roll), world <- body (MODEL.md 7.1), rows of the matrix.
pub fn attitude(roll: f64, pitch: f64, yaw: f64) -> [[f64; 3]; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// R^T v: a world vector in body axes.
pub fn world_to_body(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    core::array::from_fn(|j| r[0][j] * v[0] + r[1][j] * v[1] + r[2][j] * v[2])
}

/// What the simulator asks of a body motion: the body's kinematics at time `t` under gravity
/// `g` (g enters the specific force).
pub trait BodyMotion {
    /// The body's state at `t` \[s\].
    fn kinematics(&self, t: f64, g: f64) -> BodyKinematics;

    /// The kinematics at t0 + j dt for each j < out.len() (the RK4 nodes of one sample).
    /// Default: [`BodyMotion::kinematics`] at each; a motion may share work between them.
    fn fill(&self, t0: f64, dt: f64, g: f64, out: &mut [BodyKinematics]) {
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.kinematics(t0 + j as f64 * dt, g);
        }
    }

    /// The true forward speed at `t` that the `speed` column reads (MODEL.md 7.5, 7.7)
    /// \[m/s\]. Default 0: a body that does not travel.
    fn speed(&self, _t: f64, _g: f64) -> f64 {
        0.0
    }
}

/// A prescribed 6-DOF motion: Euler angles as sums of components, P1's acceleration as sums
/// of sines in world axes, and a vibration in body axes (MODEL.md 7.7 without the vehicle
/// and engine parts): f_P1 = R^T (a_P1 - g_w) + a_vib.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SineMotion {
    /// Roll \[rad\].
    pub roll: Angle,
    /// Pitch \[rad\].
    pub pitch: Angle,
    /// Yaw \[rad\].
    pub yaw: Angle,
    /// Acceleration of P1, world axes \[m/s^2\].
    pub accel_world: Vec<AccelSine>,
    /// Vibration acceleration of P1, body axes \[m/s^2\].
    pub accel_body: Vec<AccelSine>,
}

impl SineMotion {
    /// A body at rest with constant roll, pitch and yaw \[rad\].
    pub fn at_rest(roll: f64, pitch: f64, yaw: f64) -> Self {
        Self {
            roll: vec![Component::Const(roll)],
            pitch: vec![Component::Const(pitch)],
            yaw: vec![Component::Const(yaw)],
            ..Self::default()
        }
    }
}

impl BodyMotion for SineMotion {
    fn kinematics(&self, t: f64, g: f64) -> BodyKinematics {
        let euler = [
            eval_sum(&self.roll, t),
            eval_sum(&self.pitch, t),
            eval_sum(&self.yaw, t),
        ];
        let r = attitude(euler[0][0], euler[1][0], euler[2][0]);
        let a = accel_sum(&self.accel_world, t);
        let f = world_to_body(&r, [a[0], a[1], a[2] + g]);
        let v = accel_sum(&self.accel_body, t);
        BodyKinematics::from_euler(euler, [f[0] + v[0], f[1] + v[1], f[2] + v[2]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_motion() -> SineMotion {
        SineMotion {
            roll: vec![
                Component::Const(0.1),
                Component::Sine {
                    amp: 0.4,
                    freq: 0.7,
                    phase: 0.3,
                },
                Component::Bump {
                    amp: 0.2,
                    t0: 1.0,
                    tau: 0.3,
                },
            ],
            pitch: vec![
                Component::Sigmoid {
                    amp: 0.5,
                    t0: 1.5,
                    tau: 0.4,
                },
                Component::Sine {
                    amp: 0.2,
                    freq: 1.3,
                    phase: 1.0,
                },
            ],
            yaw: vec![
                Component::Ramp(0.3),
                Component::Sine {
                    amp: 0.6,
                    freq: 0.4,
                    phase: -0.5,
                },
            ],
            accel_world: vec![AccelSine {
                amp: 2.0,
                freq: 3.0,
                phase: 0.1,
                axis: [1.0, 0.5, -0.2],
            }],
            accel_body: vec![],
        }
    }

    /// Central differences of each angle and of w agree with the analytic derivatives.
    #[test]
    fn derivatives_are_exact() {
        let m = sample_motion();
        let h = 1e-5;
        for i in 0..300 {
            let t = 0.01 * i as f64;
            let k = m.kinematics(t, 9.81);
            let (kp, km) = (m.kinematics(t + h, 9.81), m.kinematics(t - h, 9.81));
            for a in 0..3 {
                let d1 = (kp.euler[a][0] - km.euler[a][0]) / (2.0 * h);
                let d2 = (kp.euler[a][1] - km.euler[a][1]) / (2.0 * h);
                assert!((d1 - k.euler[a][1]).abs() < 1e-7, "angle {a} t {t}");
                assert!((d2 - k.euler[a][2]).abs() < 1e-6, "angle {a} t {t}");
                let dw = (kp.w[a] - km.w[a]) / (2.0 * h);
                assert!(
                    (dw - k.wd[a]).abs() < 1e-6,
                    "wd {a} t {t}: {dw} {}",
                    k.wd[a]
                );
            }
        }
    }

    /// w from 7.1's formula is the body rate of R: skew(w) = R^T R' (central differences).
    #[test]
    fn body_rate_matches_the_attitude_matrix() {
        let m = sample_motion();
        let h = 1e-6;
        for i in 0..50 {
            let t = 0.057 * i as f64;
            let e = |t: f64| {
                let k = m.kinematics(t, 9.81);
                attitude(k.euler[0][0], k.euler[1][0], k.euler[2][0])
            };
            let (r, rp, rm) = (e(t), e(t + h), e(t - h));
            // (R^T R')_{ij} = sum_k R_ki R'_kj.
            let s = |i: usize, j: usize| {
                (0..3)
                    .map(|k| r[k][i] * (rp[k][j] - rm[k][j]) / (2.0 * h))
                    .sum::<f64>()
            };
            let w = m.kinematics(t, 9.81).w;
            let fd = [s(2, 1), s(0, 2), s(1, 0)];
            for a in 0..3 {
                assert!((fd[a] - w[a]).abs() < 1e-8, "t {t} axis {a}: {fd:?} {w:?}");
            }
        }
    }

    /// At rest f_P1 = g u, u = (-sin p, cos p sin r, cos p cos r) for any yaw (MODEL.md 7.1).
    #[test]
    fn at_rest_specific_force_is_g_up() {
        let (r, p) = (0.3, -0.4);
        for yaw in [0.0, 1.0, -2.5] {
            let k = SineMotion::at_rest(r, p, yaw).kinematics(0.7, 9.8);
            let u = [-p.sin(), p.cos() * r.sin(), p.cos() * r.cos()];
            for (f, u) in k.f_p1.iter().zip(u) {
                assert!((f - 9.8 * u).abs() < 1e-14);
            }
            assert_eq!(k.w, [0.0; 3]);
        }
    }
}
