//! The engine on a state that is not a vector: an angle on the circle stored as the unit
//! vector (cos, sin) with a rate beside it (3 numbers, a 2-dimensional error). Addition
//! would leave the circle; the filters must correct through `retract`.
use super::*;
use core::cell::Cell;
use nalgebra::{Matrix2, SMatrix, Vector1, Vector2};

std::thread_local! {
    static RETRACTS: Cell<usize> = const { Cell::new(0) };
}

/// Angle as a unit vector, and its rate.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Circle {
    c: f64,
    s: f64,
    w: f64,
}

impl Circle {
    fn at(angle: f64, w: f64) -> Self {
        Self {
            c: angle.cos(),
            s: angle.sin(),
            w,
        }
    }

    /// Composition with a rotation by `d`.
    fn rotated(&self, d: f64) -> Self {
        let (sd, cd) = d.sin_cos();
        Self {
            c: self.c * cd - self.s * sd,
            s: self.s * cd + self.c * sd,
            w: self.w,
        }
    }
}

impl ErrorState<f64, 2> for Circle {
    fn retract(&self, dx: &Vector2<f64>) -> Self {
        RETRACTS.with(|n| n.set(n.get() + 1));
        let mut y = self.rotated(dx[0]);
        y.w += dx[1];
        y
    }

    fn local(&self, y: &Self) -> Vector2<f64> {
        let d = (self.c * y.s - self.s * y.c).atan2(self.c * y.c + self.s * y.s);
        Vector2::new(d, y.w - self.w)
    }

    fn is_finite(&self) -> bool {
        self.c.is_finite() && self.s.is_finite() && self.w.is_finite()
    }
}

/// Constant rate: the angle turns by `w dt`; white rate and angle noise.
struct Turning;

impl ProcessModel<f64, 2> for Turning {
    type State = Circle;
    type Input = ();

    fn step(&self, x: &Circle, _u: &(), dt: f64) -> Circle {
        x.rotated(x.w * dt)
    }

    fn jacobian(&self, _x: &Circle, _u: &(), dt: f64) -> Matrix2<f64> {
        Matrix2::new(1.0, dt, 0.0, 1.0)
    }

    fn q(&self, dt: f64) -> Matrix2<f64> {
        Matrix2::new(1e-4 * dt, 0.0, 0.0, 1.0 * dt)
    }
}

/// Reads (cos, sin) of the angle: nonlinear, no wrap-around.
struct CosSin;

impl Measurement<f64, Circle, 2, 2> for CosSin {
    fn predict(&self, x: &Circle) -> Vector2<f64> {
        Vector2::new(x.c, x.s)
    }

    fn jacobian(&self, x: &Circle) -> SMatrix<f64, 2, 2> {
        Matrix2::new(-x.s, 0.0, x.c, 0.0)
    }

    fn variance(&self) -> Vector2<f64> {
        Vector2::repeat(0.05 * 0.05)
    }
}

/// Tracks an angle through more than three turns; returns the largest error after the
/// first second and the number of `retract` calls.
fn track<F: GaussianFilter<f64, Circle, 2>>() -> (f64, f64, usize) {
    let truth = |t: f64| 0.3 + 2.0 * t + 0.5 * t.sin();
    let dt = 0.01;
    let mut f = F::start(Circle::at(0.3, 0.0), Matrix2::new(0.1, 0.0, 0.0, 10.0));
    let q = Turning.q(dt);
    let mut seed = 12345u64;
    let mut noise = || {
        // Uniform in (-0.05, 0.05) (standard deviation 0.029) from a fixed LCG.
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.1
    };
    RETRACTS.with(|n| n.set(0));
    let (mut worst, mut drift) = (0.0f64, 0.0f64);
    for k in 1..=1000 {
        let th = truth(k as f64 * dt);
        assert!(f.predict(&Turning, &(), dt, &q));
        let z = Vector2::new(th.cos() + noise(), th.sin() + noise());
        f.update(&CosSin, &z, Gate::off()).unwrap();
        let x = f.state();
        drift = drift.max((x.c * x.c + x.s * x.s - 1.0).abs());
        if k > 100 {
            let e = (x.s * th.cos() - x.c * th.sin()).atan2(x.c * th.cos() + x.s * th.sin());
            worst = worst.max(e.abs());
        }
    }
    (worst, drift, RETRACTS.with(|n| n.get()))
}

#[test]
fn the_ekf_corrects_a_rotation_by_retract() {
    let (worst, drift, retracts) = track::<ExtendedKalman<f64, Circle, 2>>();
    // One correction per scalar axis: 2 per sample, 1000 samples.
    assert_eq!(retracts, 2000);
    assert!(drift < 1e-12, "left the circle by {drift}");
    assert!(worst < 0.05, "worst angle error {worst} rad");
}

#[test]
fn the_ukf_corrects_and_spreads_a_rotation_by_retract() {
    let (worst, drift, retracts) = track::<UnscentedKalman<f64, Circle, 2>>();
    // Per sample: predict 4 sigma points + the mean, update 4 sigma points + the
    // correction.
    assert_eq!(retracts, 10_000);
    assert!(drift < 1e-12, "left the circle by {drift}");
    assert!(worst < 0.05, "worst angle error {worst} rad");
}

#[test]
fn the_linear_kalman_filter_is_the_textbook_one() {
    // The paper's model on the engine, one step against Eqs 2-8 written out densely.
    use crate::kalman::measurement::AngleMeasurement;
    use crate::kalman::process::AngleBias;
    let m = AngleBias {
        q_angle: 0.001,
        q_bias: 0.003,
    };
    let p0 = Matrix2::new(0.02, 0.001, 0.001, 0.01);
    let x0 = Vector2::new(0.1, 0.02);
    let mut f = ExtendedKalman::<f64, Vector2<f64>, 2>::start(x0, p0);
    let (dt, u, z, r) = (0.01, 0.5, 0.13, 0.03);
    assert!(f.predict(&m, &u, dt, &m.q(dt)));
    f.update(&AngleMeasurement { r }, &Vector1::new(z), Gate::off())
        .unwrap();
    let a = Matrix2::new(1.0, -dt, 0.0, 1.0);
    let xm = a * x0 + Vector2::new(dt * u, 0.0);
    let pm = a * p0 * a.transpose() + Matrix2::new(0.001 * dt, 0.0, 0.0, 0.003 * dt);
    let h = nalgebra::Matrix1x2::new(1.0, 0.0);
    let s = (h * pm * h.transpose())[0] + r;
    let k = pm * h.transpose() / s;
    let x = xm + k * (z - xm[0]);
    let p = (Matrix2::identity() - k * h) * pm;
    assert!((f.x - x).abs().max() < 1e-15, "{} vs {x}", f.x);
    assert!((f.p - p).abs().max() < 1e-15, "{} vs {p}", f.p);
}
