//! The simulator's pendulum against the physics of MODEL.md section 2: energy, free decay,
//! equilibrium, the accelerometer at rest, the paper's Eq (18), and the pivot-offset term.

use pendtilt::sim::planar::motion::{Motion, Sigmoid, Sine, Still};
use pendtilt::sim::planar::{simulate, Scenario, SimRow, Simulator};

mod common;
use common::{fit_sine, ideal};

fn still(angle: f64) -> Motion {
    Motion::Still(Still { angle })
}

fn wrap(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

#[test]
fn energy_is_conserved_without_friction_and_with_the_body_still() {
    let mut s = ideal(still(0.1), 20.0);
    s.pendulum.damping = 0.0;
    let sim = Simulator::new(&s, 1).unwrap().with_initial_state(1.0, 0.5);
    let pend = *sim.pendulum();
    let rows: Vec<SimRow> = sim.collect();
    let e = |r: &SimRow| pend.energy(r.truth.phi, r.truth.phi_dot, r.truth.theta);
    let e0 = e(&rows[0]);
    assert!(e0 > 1e-3);
    let drift = rows
        .iter()
        .map(|r| (e(r) - e0).abs() / e0)
        .fold(0.0, f64::max);
    assert!(drift < 1e-9, "relative energy drift {drift:e}");
    // The pendulum really swings through large angles.
    let span = rows.iter().map(|r| r.truth.beta).fold(0.0, f64::max);
    assert!(span > 1.0, "{span}");
}

#[test]
fn free_decay_gives_the_natural_frequency_and_damping_ratio() {
    for damping in [1.07e-3, 2.0e-4] {
        let mut s = ideal(still(0.0), 3.0);
        s.rate = 10_000.0;
        s.pendulum.damping = damping;
        let p = s.physical();
        let mgl = p.mass * p.gravity * p.length;
        let wn = (mgl / p.inertia).sqrt();
        let zeta = p.damping / (2.0 * (p.inertia * mgl).sqrt());
        let rows: Vec<SimRow> = Simulator::new(&s, 1)
            .unwrap()
            .with_initial_state(0.01, 0.0)
            .collect();
        let x: Vec<f64> = rows.iter().map(|r| r.truth.phi).collect();
        let dt = 1.0 / s.rate;
        // Zero crossings (linear interpolation) are pi / w_d apart.
        let mut zeros = Vec::new();
        for k in 1..x.len() {
            if x[k - 1] != 0.0 && x[k - 1].signum() != x[k].signum() {
                zeros.push((k as f64 - 1.0 + x[k - 1] / (x[k - 1] - x[k])) * dt);
            }
        }
        let zeros = &zeros[..zeros.len().min(8)];
        assert!(zeros.len() >= 6, "{} crossings", zeros.len());
        let half = (zeros[zeros.len() - 1] - zeros[0]) / (zeros.len() - 1) as f64;
        let wd = std::f64::consts::PI / half;
        // Successive extrema (parabolic interpolation) shrink by exp(-zeta w_n pi / w_d).
        let mut peaks = Vec::new();
        for k in 1..x.len() - 1 {
            if x[k].abs() > x[k - 1].abs() && x[k].abs() >= x[k + 1].abs() {
                let (a, b, c) = (x[k - 1], x[k], x[k + 1]);
                let d = 0.5 * (a - c) / (a - 2.0 * b + c);
                peaks.push((b - 0.25 * (a - c) * d).abs());
            }
        }
        let peaks = &peaks[..peaks.len().min(6)];
        let n = (peaks.len() - 1) as f64;
        let delta = (peaks[0] / peaks[peaks.len() - 1]).ln() / n;
        let zeta_m = delta / (std::f64::consts::PI.powi(2) + delta * delta).sqrt();
        let wn_m = wd / (1.0 - zeta_m * zeta_m).sqrt();
        assert!((wn_m / wn - 1.0).abs() < 1e-3, "w_n {wn_m} vs {wn}");
        assert!(
            (zeta_m / zeta - 1.0).abs() < 2e-3,
            "zeta {zeta_m} vs {zeta}"
        );
    }
}

#[test]
fn static_equilibrium_is_phi_equals_theta() {
    for theta in [-0.4, 0.0, 0.2, 1.0] {
        let mut s = ideal(still(theta), 12.0);
        s.pendulum.pivot_offset = 0.1;
        let rows: Vec<SimRow> = Simulator::new(&s, 1)
            .unwrap()
            .with_initial_state(0.3, -1.0)
            .collect();
        let last = rows.last().unwrap();
        assert!((last.truth.phi - theta).abs() < 1e-9, "{}", last.truth.phi);
        assert!((last.phi - theta).abs() < 1e-9);
        // ... and it was not there from the start.
        assert!((rows[0].truth.phi - theta).abs() > 0.1);
    }
    // Started hanging still (MODEL.md section 6), it stays: phi = theta from t = 0.
    let rows = simulate(&ideal(still(0.25), 2.0), 1).unwrap();
    assert!(rows.iter().all(|r| (r.phi - 0.25).abs() < 1e-15));
}

#[test]
fn accelerometer_angle_is_theta_at_rest() {
    for theta in [-1.2, -0.3, 0.0, 0.05, 0.7, 1.4] {
        let mut s = ideal(still(theta), 0.05);
        s.pendulum.pivot_offset = 0.15;
        s.sensors.accel.mount = [0.02, -0.05];
        for r in simulate(&s, 1).unwrap() {
            assert!((r.ax.atan2(r.ay) - theta).abs() < 1e-14);
            assert!((r.ax.hypot(r.ay) - s.pendulum.gravity).abs() < 1e-12);
            assert_eq!(r.gyro, 0.0);
            assert_eq!(r.theta, theta);
        }
    }
}

/// phi' and phi'' by 5-point central differences of the sampled true phi.
fn eq18_residuals(s: &Scenario) -> Vec<f64> {
    let rows = simulate(s, 1).unwrap();
    let p = s.physical();
    let mgl = p.mass * p.gravity * p.length;
    let h = 1.0 / s.rate;
    let x: Vec<f64> = rows.iter().map(|r| r.truth.phi).collect();
    (2..x.len() - 2)
        .map(|k| {
            let d1 = (x[k - 2] - 8.0 * x[k - 1] + 8.0 * x[k + 1] - x[k + 2]) / (12.0 * h);
            let d2 = (-x[k - 2] + 16.0 * x[k - 1] - 30.0 * x[k] + 16.0 * x[k + 1] - x[k + 2])
                / (12.0 * h * h);
            let t = &rows[k].truth;
            (p.damping * d1 + p.inertia * (d2 - t.alpha) + mgl * (x[k] - t.theta).sin()) / mgl
        })
        .collect()
}

#[test]
fn eq18_holds_along_the_trajectory_when_l12_is_zero() {
    let mut s = ideal(Motion::Sigmoid(Sigmoid::default()), 5.0);
    s.rate = 2000.0;
    let worst = eq18_residuals(&s)
        .iter()
        .fold(0.0f64, |m, r| m.max(r.abs()));
    assert!(worst < 1e-8, "Eq 18 residual / (m g l) = {worst:e}");
    // The exact state's phi'' satisfies it to rounding.
    let p = s.physical();
    for r in simulate(&s, 1).unwrap() {
        let t = r.truth;
        let res = pendtilt::sim::planar::dynamics::eq18_residual(
            &p,
            [t.phi, t.phi_dot, t.phi_ddot],
            t.theta,
            t.alpha,
        );
        assert!(res.abs() < 1e-15, "{res:e}");
    }
    // With a pivot offset the paper's Eq 18 no longer holds: the check can fail.
    s.pendulum.pivot_offset = 0.2;
    let worst = eq18_residuals(&s)
        .iter()
        .fold(0.0f64, |m, r| m.max(r.abs()));
    assert!(worst > 1e-3, "{worst:e}");
}

/// An independent integration of the body-form equation of MODEL.md section 2 in phi:
/// I (phi'' - theta'') + C phi' + m g l sin(phi - theta) + m l l12 (theta'' cos phi -
/// theta'^2 sin phi) = 0, RK4 at a 10 times finer step, theta from the motion's own formula.
fn reference_phi(s: &Scenario, fine: usize) -> Vec<f64> {
    let p = s.physical();
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(0);
    let m = s.motion.build(&mut rng);
    let acc = |t: f64, y: [f64; 2]| {
        let [th, w, al] = m.eval(t);
        let (phi, dphi) = (y[0], y[1]);
        let rhs = p.damping * dphi
            + p.mass * p.gravity * p.length * (phi - th).sin()
            + p.mass * p.length * p.pivot_offset * (al * phi.cos() - w * w * phi.sin());
        [dphi, al - rhs / p.inertia]
    };
    let [th0, w0, _] = m.eval(0.0);
    let mut y = [th0, w0];
    let h = 1.0 / (s.rate * fine as f64);
    let mut out = Vec::new();
    for k in 0..s.rows() {
        out.push(y[0]);
        for i in 0..fine {
            let t = k as f64 / s.rate + i as f64 * h;
            let k1 = acc(t, y);
            let k2 = acc(
                t + h / 2.0,
                [y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]],
            );
            let k3 = acc(
                t + h / 2.0,
                [y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]],
            );
            let k4 = acc(t + h, [y[0] + h * k3[0], y[1] + h * k3[1]]);
            for j in 0..2 {
                y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
    }
    out
}

#[test]
fn trajectory_matches_an_independent_integration_of_the_body_form() {
    for l12 in [0.0, 0.25] {
        let mut s = ideal(
            Motion::Sine(Sine {
                amplitude: 0.5,
                frequency: 1.5,
                ..Sine::default()
            }),
            4.0,
        );
        s.pendulum.pivot_offset = l12;
        // 8 steps per sample (the default is 2) so that both integrations are converged
        // far below the tolerance: what is left is any difference in the equations.
        s.substeps = 8;
        let rows = simulate(&s, 1).unwrap();
        let reference = reference_phi(&s, 40);
        let worst = rows
            .iter()
            .zip(&reference)
            .map(|(r, x)| (r.truth.phi - x).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-9,
            "l12 = {l12}: max |phi - reference| = {worst:e}"
        );
    }
}

#[test]
fn pivot_offset_changes_phi_by_the_predicted_amount() {
    let (amp, f, l12) = (0.02, 3.0, 0.2);
    let run = |l12: f64| {
        let mut s = ideal(
            Motion::Sine(Sine {
                amplitude: amp,
                frequency: f,
                ..Sine::default()
            }),
            8.0,
        );
        s.pendulum.pivot_offset = l12;
        (simulate(&s, 1).unwrap(), s.physical())
    };
    let (r0, _) = run(0.0);
    let (r1, p) = run(l12);
    // Steady state (transients decay as exp(-zeta w_n t), w_n zeta = 4.1 /s): last 3 s.
    let diff: Vec<(f64, f64)> = r0
        .iter()
        .zip(&r1)
        .filter(|(a, _)| a.t >= 5.0)
        .map(|(a, b)| (a.t, b.truth.phi - a.truth.phi))
        .collect();
    let w = std::f64::consts::TAU * f;
    let (got_amp, got_phase, _) = fit_sine(&diff, w);
    // Linearised: delta phi / theta = m l l12 w^2 / (m g l - I w^2 + i C w).
    let mgl = p.mass * p.gravity * p.length;
    let (re, im) = (mgl - p.inertia * w * w, p.damping * w);
    let gain = p.mass * p.length * l12 * w * w / re.hypot(im);
    let phase = -im.atan2(re);
    assert!(got_amp > 1e-3, "{got_amp}");
    assert!(
        (got_amp / (gain * amp) - 1.0).abs() < 0.01,
        "amplitude {got_amp} vs {}",
        gain * amp
    );
    assert!(
        wrap(got_phase - phase).abs() < 0.01,
        "phase {got_phase} vs {phase}"
    );
}
