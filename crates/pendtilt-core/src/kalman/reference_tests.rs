//! The paper's filter on the engine against a copy of the arithmetic it had before the
//! engine (the linear Kalman filter of `kalman/filter.rs`: `K = P H^T (H P H^T + R)^-1`,
//! `x += K (z - H x)`, `P = (I - K H) P`): the engine's symmetric scalar update changes
//! the rounding only.
use super::tilt::{KalmanSettings, TiltKalman};
use crate::Flags;
use nalgebra::{Matrix1x2, Matrix2, Vector1, Vector2};

/// The filter as it was: state, covariance, start and time conventions of `TiltKalman`.
struct Old {
    s: KalmanSettings<f64>,
    x: Vector2<f64>,
    p: Matrix2<f64>,
    t_prev: Option<f64>,
    last_gyro: f64,
}

impl Old {
    fn new(s: KalmanSettings<f64>) -> Self {
        Self {
            s,
            x: Vector2::zeros(),
            p: Matrix2::new(s.p0_angle, 0.0, 0.0, s.p0_bias),
            t_prev: None,
            last_gyro: 0.0,
        }
    }

    fn step(&mut self, t: f64, gyro: f64, ms: &[(f64, f64)]) -> f64 {
        let u = if gyro.is_finite() {
            self.last_gyro = gyro;
            gyro
        } else {
            self.last_gyro
        };
        let Some(tp) = self.t_prev else {
            let z0 = ms.iter().find(|m| m.0.is_finite()).unwrap().0;
            self.x = Vector2::new(z0, 0.0);
            self.t_prev = Some(t);
            return z0;
        };
        let dt = t - tp;
        self.t_prev = Some(t);
        let f = Matrix2::new(1.0, -dt, 0.0, 1.0);
        let q = Matrix2::new(self.s.q_angle * dt, 0.0, 0.0, self.s.q_bias * dt);
        self.x = f * self.x + Vector2::new(dt * u, 0.0);
        self.p = f * self.p * f.transpose() + q;
        let h = Matrix1x2::new(1.0, 0.0);
        for &(z, r) in ms.iter().filter(|m| m.0.is_finite()) {
            let s = h * self.p * h.transpose() + Vector1::new(r);
            let k = self.p * h.transpose() * s.try_inverse().unwrap();
            self.x += k * (Vector1::new(z) - h * self.x);
            self.p = (Matrix2::identity() - k * h) * self.p;
        }
        self.x[0]
    }
}

#[test]
fn equals_the_filter_before_the_engine_to_1e_12() {
    // 200 s at 1 kHz with jittered steps, a drifting gyro bias, two measurement sources
    // (the accelerometer's noisy angle, a pendulum algorithm's) and missing readings.
    let s = KalmanSettings::<f64>::default();
    let (mut new, mut old) = (TiltKalman::new(s), Old::new(s));
    let mut seed = 7u64;
    let mut unif = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (mut t, mut worst, mut worst_bias) = (0.0, 0.0f64, 0.0f64);
    let mut gate = crate::StepGate::new();
    for k in 0..200_000 {
        t += 1e-3 * (1.0 + 0.2 * unif());
        let theta = 0.4 * (0.7 * t).sin() + 0.1 * (3.1 * t).sin();
        let rate = 0.28 * (0.7 * t).cos() + 0.31 * (3.1 * t).cos();
        let gyro = rate + 0.02 + 1e-4 * t + 0.01 * unif();
        let accel = if k % 97 == 5 {
            f64::NAN
        } else {
            theta + 0.3 * unif()
        };
        let pend = if k % 13 == 0 {
            f64::NAN
        } else {
            theta + 0.01 * unif()
        };
        let ms = [(accel, s.r_accel), (pend, s.r_pendulum)];
        let e = new.step(gate.step(t), gyro, &ms);
        let o = old.step(t, gyro, &ms);
        assert!(!e.flags.contains(Flags::BAD_TIME_STEP));
        worst = worst.max((e.theta - o).abs());
        worst_bias = worst_bias.max((new.bias() - old.x[1]).abs());
    }
    assert!(worst < 1e-12, "angle differs by {worst}");
    assert!(worst_bias < 1e-12, "bias differs by {worst_bias}");
    // It is the rounding, not the same arithmetic: the two do differ somewhere.
    assert!(worst > 0.0);
}
