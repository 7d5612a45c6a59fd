//! The 3-D simulator core against physics (MODEL.md 7.2-7.4): energy, equilibrium,
//! small-angle frequencies, the planar reduction, and a residual check of the vector form.

use nalgebra::{Matrix3, Rotation3, Vector3};
use pendtilt::sim::planar::motion::{Chirp, Motion, MotionFn, Sine};
use pendtilt::sim::planar::{PendulumTable, Scenario, Simulator};
use pendtilt::sim::spatial::motion::{AccelSine, Component};
use pendtilt::sim::spatial::{
    BodyKinematics, BodyMotion, JointState, Pendulum3d, Simulator3d, SineMotion, Truth3d,
};
use rand::SeedableRng;

/// A rig whose inertias all differ, so that every term of 7.3 is exercised.
fn asymmetric_rig() -> Pendulum3d {
    Pendulum3d {
        inertia_xx: 1.3e-4,
        inertia_yy: 1.0e-4,
        inertia_zz: 3.0e-5,
        ring_inertia: 2.0e-5,
        ..Pendulum3d::default()
    }
}

fn run<M: BodyMotion>(
    p: Pendulum3d,
    m: M,
    rate: f64,
    substeps: u32,
    secs: f64,
    s: Option<JointState>,
) -> Vec<Truth3d> {
    let sim = Simulator3d::new(p, m, rate, substeps, secs).unwrap();
    match s {
        Some(s) => sim.with_joint_state(s).collect(),
        None => sim.collect(),
    }
}

/// (a) With no damping on a still body the pendulum + ring energy is conserved through a
/// big swing about both axes (60 deg and 40 deg from the hanging position).
#[test]
fn energy_is_conserved_on_a_still_body() {
    let p = Pendulum3d {
        damping_x: 0.0,
        damping_y: 0.0,
        pivot_offset: [0.02, -0.03, 0.1],
        ..asymmetric_rig()
    };
    let (r, pi) = (0.2, -0.1);
    let s0 = JointState {
        a: -r + 60f64.to_radians(),
        b: -pi + 40f64.to_radians(),
        a_dot: 1.0,
        b_dot: -2.0,
    };
    let rows = run(
        p,
        SineMotion::at_rest(r, pi, 0.5),
        1000.0,
        4,
        10.0,
        Some(s0),
    );
    let energy = |row: &Truth3d| {
        p.kinetic_energy(&row.joint, row.body.w) + p.potential_energy(&row.joint, row.f_pivot)
    };
    let e0 = energy(&rows[0]);
    // The swing's energy above the hanging rest state (-m g l).
    let swing = e0 + p.mgl();
    assert!(swing > 0.5 * p.mgl(), "a big swing: {swing}");
    let drift = rows
        .iter()
        .map(|r| (energy(r) - e0).abs())
        .fold(0.0, f64::max)
        / swing;
    assert!(drift < 1e-10, "relative energy drift {drift:e}");
    // Both joints really swing through large angles.
    let (amax, bmax) = rows.iter().fold((0f64, 0f64), |(x, y), row| {
        (
            x.max((row.joint.a + r).abs()),
            y.max((row.joint.b + pi).abs()),
        )
    });
    assert!(amax > 0.9 && bmax > 0.6, "{amax} {bmax}");
    eprintln!("energy drift over 10 s, 1 kHz x 4: {drift:e} of the swing energy");
}

/// (b) On a body at rest with roll r, pitch p and any yaw, the encoders read phi_x = r,
/// phi_y = p: exactly at the start (with zero a'', b'') and after settling from a push.
#[test]
fn equilibrium_encoders_equal_roll_and_pitch_for_any_yaw() {
    let p = asymmetric_rig();
    for (r, pi) in [(0.3, -0.2), (-0.5, 0.4), (0.0, 0.7), (1.0, -1.1)] {
        for yaw in [0.0, 1.0, -2.0, 3.0] {
            let m = SineMotion::at_rest(r, pi, yaw);
            let rows = run(p, m.clone(), 1000.0, 2, 0.01, None);
            let [px, py] = rows[0].encoders();
            assert!((px - r).abs() < 1e-15 && (py - pi).abs() < 1e-15);
            for row in &rows {
                assert!(row.joint_acc.iter().all(|x| x.abs() < 1e-12), "{row:?}");
                let [px, py] = row.encoders();
                assert!((px - r).abs() < 1e-14 && (py - pi).abs() < 1e-14);
            }
            // Pushed off the equilibrium, it settles back to the same readings.
            let push = JointState {
                a: -r + 0.3,
                b: -pi - 0.25,
                a_dot: 2.0,
                b_dot: 1.0,
            };
            let rows = run(p, m, 1000.0, 2, 15.0, Some(push));
            let [px, py] = rows.last().unwrap().encoders();
            assert!(
                (px - r).abs() < 1e-9 && (py - pi).abs() < 1e-9,
                "r {r} p {pi} yaw {yaw}: {px} {py}"
            );
        }
    }
}

/// The mean frequency of a signal from its zero crossings (linear interpolation) \[rad/s\].
fn crossing_frequency(t: &[f64], x: &[f64]) -> f64 {
    let mut c = Vec::new();
    for k in 1..x.len() {
        if x[k - 1] != 0.0 && x[k - 1].signum() != x[k].signum() {
            c.push(t[k - 1] + (t[k] - t[k - 1]) * x[k - 1] / (x[k - 1] - x[k]));
        }
    }
    assert!(c.len() > 20, "{} crossings", c.len());
    let half_periods = (c.len() - 1) as f64;
    std::f64::consts::PI * half_periods / (c.last().unwrap() - c[0])
}

/// Free small swing (no damping) about one axis on a body at rest; returns the measured
/// frequency \[rad/s\].
fn free_swing(p: Pendulum3d, roll: f64, pitch: f64, axis: usize) -> f64 {
    let mut s = JointState::hanging_still(roll, pitch, [0.0; 3]);
    if axis == 0 {
        s.a += 1e-3;
    } else {
        s.b += 1e-3;
    }
    let rows = run(
        p,
        SineMotion::at_rest(roll, pitch, 0.7),
        1000.0,
        2,
        10.0,
        Some(s),
    );
    let t: Vec<f64> = rows.iter().map(|r| r.t).collect();
    let x: Vec<f64> = rows
        .iter()
        .map(|r| {
            if axis == 0 {
                r.joint.a + roll
            } else {
                r.joint.b + pitch
            }
        })
        .collect();
    crossing_frequency(&t, &x)
}

/// (c) Small-angle natural frequencies equal sqrt(K / M) of MODEL.md 7.2, on a level body
/// and, for the outer axis, at 30 and -50 deg of pitch (where cos^2 p and Izz sin^2 p enter).
#[test]
fn small_angle_frequencies_match_the_linearisation() {
    let p = Pendulum3d {
        damping_x: 0.0,
        damping_y: 0.0,
        ..asymmetric_rig()
    };
    let level = p.natural_frequencies(0.0);
    for (roll, pitch, axis) in [
        (0.0, 0.0, 0),
        (0.0, 0.0, 1),
        (0.4, 0.0, 0),
        (0.2, 30f64.to_radians(), 0),
        (-0.3, -50f64.to_radians(), 0),
        (0.2, 30f64.to_radians(), 1),
    ] {
        let expect = p.natural_frequencies(pitch)[axis];
        let got = free_swing(p, roll, pitch, axis);
        let err = (got / expect - 1.0).abs();
        assert!(
            err < 1e-4,
            "roll {roll} pitch {pitch} axis {axis}: {got} vs {expect} ({err:e})"
        );
        if pitch != 0.0 && axis == 0 {
            // The pitched frequency differs from the level one by far more than the bound.
            assert!((expect / level[0] - 1.0).abs() > 0.05);
        }
    }
    // The level formulas of 7.2, written out.
    let mgl = p.mass * p.gravity * p.length;
    assert!((level[0] - (mgl / (p.inertia_xx + p.ring_inertia)).sqrt()).abs() < 1e-12);
    assert!((level[1] - (mgl / p.inertia_yy).sqrt()).abs() < 1e-12);
}

/// Pure roll theta(t) from the planar simulator's own motion, fed to the 3-D dynamics:
/// w = (theta', 0, 0), f_P1 = g (0, sin theta, cos theta) (MODEL.md 7.4).
struct PlanarRoll(MotionFn);

impl BodyMotion for PlanarRoll {
    fn kinematics(&self, t: f64, g: f64) -> BodyKinematics {
        let th = self.0.eval(t);
        BodyKinematics::from_euler(
            [th, [0.0; 3], [0.0; 3]],
            [0.0, g * th[0].sin(), g * th[0].cos()],
        )
    }
}

fn planar_vs_3d(motion: Motion, secs: f64, l12: f64) -> f64 {
    let mut sc = Scenario::with_motion(motion, secs);
    sc.pendulum = PendulumTable {
        pivot_offset: l12,
        ..PendulumTable::default()
    };
    let pp = sc.physical();
    let planar: Vec<_> = Simulator::new(&sc, 5).unwrap().collect();
    // Motion::build draws nothing for a sine or a chirp.
    let f = sc
        .motion
        .build(&mut rand_chacha::ChaCha8Rng::seed_from_u64(0));
    let p3 = Pendulum3d {
        mass: pp.mass,
        length: pp.length,
        inertia_xx: pp.inertia,
        inertia_yy: 0.7 * pp.inertia,
        inertia_zz: 3e-5,
        ring_inertia: 0.0,
        damping_x: pp.damping,
        damping_y: 2.0 * pp.damping,
        pivot_offset: [0.0, 0.0, l12],
        gravity: pp.gravity,
    };
    let rows = run(p3, PlanarRoll(f), sc.rate, sc.substeps, secs, None);
    assert_eq!(rows.len(), planar.len());
    let mut worst: f64 = 0.0;
    for (a, b) in planar.iter().zip(&rows) {
        assert_eq!(a.t, b.t);
        let [px, py] = b.encoders();
        assert_eq!(py, 0.0);
        assert_eq!(b.joint.b_dot, 0.0);
        assert_eq!(b.joint_acc[1], 0.0);
        worst = worst.max((px - a.truth.phi).abs());
    }
    // The pendulum really moved relative to the body.
    let swing = planar
        .iter()
        .map(|r| (r.truth.phi - r.truth.theta).abs())
        .fold(0.0, f64::max);
    assert!(swing > 1e-3, "swing {swing}");
    worst
}

/// (d) Pure roll with b = 0, J_ring = 0, Ixx = I_p, C_x = C, r12 = (0, 0, l12): the 3-D
/// simulator's phi_x equals the planar simulator's phi sample for sample, and phi_y, b',
/// b'' stay exactly 0 (whatever Iyy, Izz and C_y are).
#[test]
fn pure_roll_reproduces_the_planar_simulator() {
    for l12 in [0.0, 0.15] {
        let sine = Motion::Sine(Sine {
            amplitude: 20f64.to_radians(),
            frequency: 1.7,
            phase: 0.4,
            offset: 0.1,
        });
        let chirp = Motion::Chirp(Chirp {
            sweep_time: 10.0,
            ..Chirp::default()
        });
        for m in [sine, chirp] {
            let worst = planar_vs_3d(m, 10.0, l12);
            eprintln!("l12 {l12}: max |phi_x - phi_planar| = {worst:e} rad");
            assert!(worst < 1e-9, "l12 {l12}: {worst:e}");
        }
    }
}

/// A moving body with every ingredient: roll, pitch and yaw motion, P1 translation and
/// vibration, a pivot offset, damping and a ring.
fn busy_motion() -> SineMotion {
    let s = |amp: f64, freq: f64, phase: f64| Component::Sine { amp, freq, phase };
    SineMotion {
        roll: vec![Component::Const(0.1), s(0.3, 0.6, 0.2), s(0.05, 3.1, 1.0)],
        pitch: vec![s(0.25, 0.45, -0.3), s(0.04, 2.3, 0.5)],
        yaw: vec![Component::Ramp(0.4), s(0.5, 0.3, 0.0)],
        accel_world: vec![
            AccelSine {
                amp: 1.5,
                freq: 1.1,
                phase: 0.0,
                axis: [1.0, 0.0, 0.0],
            },
            AccelSine {
                amp: 2.0,
                freq: 0.8,
                phase: 1.0,
                axis: [0.0, 0.6, 0.8],
            },
        ],
        accel_body: vec![AccelSine {
            amp: 3.0,
            freq: 7.0,
            phase: 0.2,
            axis: [0.3, -0.5, 1.0],
        }],
    }
}

/// The largest residual of the vector form of MODEL.md 7.3 along a trajectory sampled at
/// `rate`, derivatives by central differences, and the largest |I W'| (both in N m).
fn vector_form_residual(p: Pendulum3d, rate: f64) -> (f64, f64) {
    let rows = run(p, busy_motion(), rate, 2, 4.0, None);
    let h = 1.0 / rate;
    let inertia = Matrix3::from_diagonal(&Vector3::new(p.inertia_xx, p.inertia_yy, p.inertia_zz));
    let rc = Vector3::new(0.0, 0.0, -p.length);
    let v = |a: [f64; 3]| Vector3::new(a[0], a[1], a[2]);
    let q = |s: &JointState| {
        Rotation3::from_axis_angle(&Vector3::x_axis(), s.a)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), s.b)
    };
    let big_w = |row: &Truth3d| {
        let s = &row.joint;
        q(s).inverse() * v(row.body.w)
            + Vector3::new(s.a_dot * s.b.cos(), s.b_dot, s.a_dot * s.b.sin())
    };
    let (mut worst, mut scale) = (0f64, 0f64);
    let mut acc_err = 0f64;
    for k in 1..rows.len() - 1 {
        let row = &rows[k];
        let s = &row.joint;
        let wdot = (big_w(&rows[k + 1]) - big_w(&rows[k - 1])) / (2.0 * h);
        let add = (rows[k + 1].joint.a_dot - rows[k - 1].joint.a_dot) / (2.0 * h);
        let bdd = (rows[k + 1].joint.b_dot - rows[k - 1].joint.b_dot) / (2.0 * h);
        acc_err = acc_err.max(
            (add - row.joint_acc[0])
                .abs()
                .max((bdd - row.joint_acc[1]).abs()),
        );
        // Specific force at P2 from P1's, independently of the code under test.
        let r12 = v(p.pivot_offset);
        let (w, wd) = (v(row.body.w), v(row.body.wd));
        let f = v(row.body.f_p1) + wd.cross(&r12) + w.cross(&w.cross(&r12));
        let bw = big_w(row);
        let iw = inertia * bw;
        let tau = inertia * wdot + bw.cross(&iw) + p.mass * rc.cross(&(q(s).inverse() * f));
        let inner = tau.y + p.damping_y * s.b_dot;
        let outer = s.b.cos() * tau.x
            + s.b.sin() * tau.z
            + p.ring_inertia * (wd.x + add)
            + p.damping_x * s.a_dot;
        worst = worst.max(inner.abs()).max(outer.abs());
        scale = scale.max((inertia * wdot).amax());
    }
    eprintln!("rate {rate}: |a'', b'' - central differences of a', b'| {acc_err:e} rad/s^2");
    (worst, scale)
}

/// (e) Finite differences of a simulated trajectory satisfy the vector form of MODEL.md
/// 7.3, computed independently with nalgebra: W = Q^T w + nu,
/// tau = I W' + W x (I W) + m r_c x (Q^T f); tau_y = -C_y b'; cb tau_x + sb tau_z + J_ring (wd_x + a'') = -C_x a'.
/// The residual is the differences' O(h^2) error: small, and 4x smaller at twice the rate
/// (a wrong term would leave a residual that does not fall with h).
#[test]
fn trajectory_satisfies_the_vector_form() {
    let p = Pendulum3d {
        pivot_offset: [0.03, -0.02, 0.1],
        ..asymmetric_rig()
    };
    let mgl = p.mgl();
    let (r1, scale) = vector_form_residual(p, 1000.0);
    let (r2, _) = vector_form_residual(p, 2000.0);
    eprintln!(
        "vector-form residual {:e} (1 kHz), {:e} (2 kHz) of m g l; largest I W' {:e} of m g l",
        r1 / mgl,
        r2 / mgl,
        scale / mgl
    );
    assert!(scale > 0.5 * mgl, "the pendulum moves: {scale:e}");
    assert!(r2 < 5e-5 * mgl, "residual {:e} of m g l", r2 / mgl);
    let ratio = r1 / r2;
    assert!(
        (3.5..4.5).contains(&ratio),
        "residual ratio {ratio}, not O(h^2)"
    );
}
