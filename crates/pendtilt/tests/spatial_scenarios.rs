//! The targets on the named 3-D scenarios of MODEL.md 7.8 (shortened to 40 s to keep
//! the suite quick; seeds fixed): ekf3d against the 3-D peers, each tuned by the same
//! search, scored by the inclination error (MODEL.md 7.9) from the scenario's `score_from`.
//! Run with `-- --nocapture` for the table (`cargo test --release -p pendtilt --test
//! spatial_scenarios -- --nocapture`).
//!
//! Measured (seed 1, 40 s): scooter3d VQF 0.209 deg RMS (tau_acc 0.71 s), Madgwick 0.99,
//! Mahony 1.30, pendulum3d 0.54; ekf3d 0.069 at its defaults, 0.055 tuned (3.8x better
//! than VQF). The target (1/5 of the best peer and 0.05 deg) is NOT reached. The
//! scooter turns about a point O 0.25 m below the IMU; ekf3d carries the lever arm from O
//! (`[mounting] speed_at`) to the pivot with the gyro's smoothed derivative (without it:
//! 0.097 tuned). Before the encoders' variance carried the vibration's jitter
//! (`encoder_jitter`) ekf3d was 0.156 at its defaults and 0.066 tuned. ship3d: VQF 1.80,
//! Madgwick 1.90, Mahony 1.90; ekf3d 0.43 at its defaults, 0.165 tuned (the roll centre
//! 5 m below and the ship's surge from the speed). ride3d (120 s): ekf3d 0.174 at its
//! defaults, 0.71 max; 7.2 without the speed; VQF 4.2 tuned. still3d: ekf3d
//! 0.0026 deg RMS, ukf3d 0.0028 (target 0.01).
//!
//! The Fusion-style peer (`fusion3d`), its gain searched the same way: scooter3d 9.0 deg
//! (gain 10: its 10 deg acceleration rejection refuses 87 % of the vibrating
//! accelerometer's readings, too few for its recovery, which needs 90 %, so it runs on the
//! gyro; without rejection 1.30 at gain 2.87, as Mahony); ship3d 1.95; still3d 0.0047 at
//! its defaults.
use pendtilt::bank::spatial::score::Inclination;
use pendtilt::bank::spatial::Settings3d;
use pendtilt::core::spatial::attitude::inclination_error;
use pendtilt::core::spatial::ekf::{Ekf, Settings, Ukf};
use pendtilt::core::spatial::pendulum::{Pendulum, PendulumSettings};
use pendtilt::core::spatial::SpatialEstimator;
use pendtilt::core::StepGate;
use pendtilt::peers::fusion::FusionSettings;
use pendtilt::peers::spatial::{fusion3d, madgwick3d, mahony3d, vqf};
use pendtilt::peers::tune::golden_log;
use pendtilt::sim::spatial::scenario::Scenario3d;
use pendtilt::sim::spatial::LogRow3d;

fn run(name: &str, secs: f64, seed: u64) -> (Scenario3d, Vec<LogRow3d>) {
    let mut s = Scenario3d::named(name, seed).unwrap();
    s.duration = secs;
    let rows = s.run(seed).unwrap().map(|(_, r)| r).collect();
    (s, rows)
}

/// RMS and max inclination error [deg] from `from` seconds on.
fn score(rows: &[LogRow3d], e: &mut dyn SpatialEstimator<f64>, from: f64) -> (f64, f64) {
    let mut gate = StepGate::new();
    let mut inc = Inclination::default();
    for r in rows {
        let a = e.update(&r.sample(gate.step(r.t)));
        if r.t >= from {
            inc.add((a.roll, a.pitch), (r.roll, r.pitch));
        }
    }
    (inc.rms().to_degrees(), inc.max().to_degrees())
}

/// ekf3d's settings from the scenario as `estimate --scenario` builds them: its pendulum,
/// its mounting and its sensors' data-sheet figures.
fn settings(s: &Scenario3d) -> Settings<f64> {
    Settings3d::of_scenario(s).ekf
}

/// ekf3d tuned the same way: 20 golden steps of its one environment figure, the density of
/// the specific force that forces the pendulum (its process noise).
fn tuned_ekf(s: &Scenario3d, rows: &[LogRow3d], from: f64) -> (f64, f64) {
    golden_log(
        |d| {
            let mut st = settings(s);
            st.environment.vibration_density = d;
            score(rows, &mut Ekf::new(st), from).0
        },
        1e-4,
        10.0,
        20,
    )
}

/// The peers, each tuned by 20 golden steps of its main gain against the truth.
fn tuned_peers(rows: &[LogRow3d], from: f64) -> Vec<(&'static str, f64, f64)> {
    let rms = |e: &mut dyn SpatialEstimator<f64>| score(rows, e, from).0;
    let v = golden_log(|t| rms(&mut vqf(t)), 0.05, 100.0, 20);
    let m = golden_log(|b| rms(&mut madgwick3d(b)), 1e-4, 10.0, 20);
    let h = golden_log(|k| rms(&mut mahony3d(k, 0.0)), 1e-3, 100.0, 20);
    let f = golden_log(|k| rms(&mut fusion3d(fusion(k, true))), 1e-3, 100.0, 20);
    let g = golden_log(|k| rms(&mut fusion3d(fusion(k, false))), 1e-3, 100.0, 20);
    vec![
        ("vqf", v.0, v.1),
        ("madgwick3d", m.0, m.1),
        ("mahony3d", h.0, h.1),
        ("fusion3d", f.0, f.1),
        ("fusion3d, no rejection", g.0, g.1),
    ]
}

/// The Fusion-style filter with feedback gain `gain` [1/s], its acceleration rejection at
/// its default (10 deg) or off, its other settings at their defaults.
fn fusion(gain: f64, rejection: bool) -> FusionSettings {
    let d = FusionSettings::default();
    FusionSettings {
        gain,
        accel_rejection: if rejection {
            d.accel_rejection
        } else {
            f64::INFINITY
        },
        ..d
    }
}

#[test]
fn scooter3d_ekf3d_against_the_fairly_tuned_peers() {
    let (s, rows) = run("scooter3d", 40.0, 1);
    let from = s.score_from;
    let peers = tuned_peers(&rows, from);
    let ekf = score(&rows, &mut Ekf::new(settings(&s)), from);
    let pend = score(&rows, &mut Pendulum::new(PendulumSettings {}), from);
    for (n, g, e) in &peers {
        println!("scooter3d {n:<22} gain {g:.4}: {e:.4} deg RMS");
    }
    println!("scooter3d pendulum3d: {:.4} / {:.4} deg", pend.0, pend.1);
    println!(
        "scooter3d ekf3d (defaults): {:.4} / {:.4} deg",
        ekf.0, ekf.1
    );
    let t = tuned_ekf(&s, &rows, from);
    println!(
        "scooter3d ekf3d tuned: density {:.4}: {:.4} deg RMS",
        t.0, t.1
    );
    // Without rejection the Fusion-style law is Mahony's proportional one (ki = 0): two
    // implementations, the same best figure.
    let by = |n: &str| peers.iter().find(|p| p.0 == n).unwrap().2;
    let (fus, mah) = (by("fusion3d, no rejection"), by("mahony3d"));
    assert!((fus - mah).abs() < 0.02 * mah, "{fus} {mah}");
    let best = peers.iter().map(|p| p.2).fold(f64::INFINITY, f64::min);
    assert!(
        t.1 < best / 3.5 && ekf.0 < best / 2.5,
        "{t:?} {ekf:?} vs {best}"
    );
    // The lever arm from the stand is what the scenario's [mounting] buys: with the body
    // taken to turn about P1, ekf3d tuned the same way is worse (0.12 deg).
    let mut blind = s.clone();
    blind.rig.mounting = Default::default();
    let blind = tuned_ekf(&blind, &rows, from);
    println!(
        "scooter3d ekf3d tuned without the lever arm: {:.4} deg",
        blind.1
    );
    assert!(blind.1 > 1.2 * t.1, "{blind:?} vs {t:?}");
}

#[test]
fn still3d_steps() {
    let (s, rows) = run("still3d", 6.0, 1);
    let from = s.score_from;
    let ekf = score(&rows, &mut Ekf::new(settings(&s)), from);
    let ukf = score(&rows, &mut Ukf::new(settings(&s)), from);
    let pend = score(&rows, &mut Pendulum::new(PendulumSettings {}), from);
    let fus = score(&rows, &mut fusion3d(FusionSettings::default()), from);
    println!(
        "still3d pendulum3d {:.5} / {:.5}; ekf3d {:.5} / {:.5}; ukf3d {:.5} / {:.5}; \
         fusion3d {:.5} / {:.5} deg",
        pend.0, pend.1, ekf.0, ekf.1, ukf.0, ukf.1, fus.0, fus.1
    );
    assert!(ekf.0 < 0.005 && ekf.1 < 0.01, "{ekf:?}");
    assert!(ukf.0 < 0.005 && ukf.1 < 0.01, "{ukf:?}");
    // The Fusion-style filter on noise-free steps: the accelerometer is exact between the
    // steps and the start-up ramp (gain 10 -> 0.5 over 3 s) overlaps them, so it follows
    // the truth closely; 0.05 deg bounds its lag behind a step.
    assert!(fus.0 < 0.05, "{fus:?}");
    // With ideal sensors pendulum3d is exact on a body at rest (still3d's sigmoids are
    // never quite still: 8e-6 rad of motion at t = 0), at any roll, pitch and yaw.
    use pendtilt::sim::spatial::{Pendulum3d, SensorBank3d, Sensors3d, Simulator3d, SineMotion};
    let mut worst = 0.0f64;
    for (r0, p0, y0) in [(0.3, -0.2, 1.0), (-0.7, 0.4, -2.5), (0.0, 0.0, 0.0)] {
        let sim = Simulator3d::new(
            Pendulum3d::default(),
            SineMotion::at_rest(r0, p0, y0),
            1000.0,
            2,
            1.0,
        )
        .unwrap();
        let mut bank = SensorBank3d::new(Sensors3d::default(), 1000.0, 1);
        let mut p = Pendulum::<f64>::new(PendulumSettings {});
        let mut gate = StepGate::new();
        for x in sim {
            let r = bank.read(&x);
            let a = pendtilt::core::Estimator::update(&mut p, &r.sample(gate.step(r.t)));
            worst = worst.max(inclination_error(a.roll, a.pitch, r.roll, r.pitch));
        }
    }
    println!("ideal sensors, body at rest: pendulum3d within {worst:.2e} rad");
    assert!(worst < 1e-6, "{worst}");
}

#[test]
fn ship3d_ekf3d_against_the_fairly_tuned_peers() {
    let (s, rows) = run("ship3d", 40.0, 1);
    let from = s.score_from;
    let peers = tuned_peers(&rows, from);
    let ekf = score(&rows, &mut Ekf::new(settings(&s)), from);
    for (n, g, e) in &peers {
        println!("ship3d {n:<22} gain {g:.4}: {e:.4} deg RMS");
    }
    println!("ship3d ekf3d (defaults): {:.4} / {:.4} deg", ekf.0, ekf.1);
    let t = tuned_ekf(&s, &rows, from);
    println!("ship3d ekf3d tuned: density {:.4}: {:.4} deg RMS", t.0, t.1);
    let best = peers.iter().map(|p| p.2).fold(f64::INFINITY, f64::min);
    // No worse than the best tuned peer even at its defaults (the target), and
    // with the lever arm from the roll centre well better once tuned.
    assert!(ekf.0 <= best && t.1 < best / 3.0, "{t:?} {ekf:?} vs {best}");
}

/// On ride3d (MODEL.md 7.8; braking at 4.2 m/s^2, turns at 0.28-0.50
/// rad/s, speed scale 1.01) ekf3d uses the `speed` column for O's acceleration
/// (`v' x_b + w_p x v x_b`) and the lever arm from `[mounting] speed_at`. Without the
/// speed it reads the vehicle's accelerations as tilt, as every peer does.
/// Measured (seed 1, 120 s, inclination): with the speed 0.174 deg RMS (max 0.71) at its
/// defaults; without it 7.2 (max 32); VQF tuned 4.2 (max 7.68, so ekf3d is 10.8x better in
/// max: the target is 10x against the best tuned peer). The other seeds and the variants:
/// `ride3d_on_three_seeds_and_with_a_yaw_rate_bias`.
#[test]
fn ride3d_ekf3d_with_the_speed() {
    let (s, rows) = run("ride3d", 120.0, 1);
    let from = s.score_from;
    let with = score(&rows, &mut Ekf::new(settings(&s)), from);
    let tuned = tuned_ekf(&s, &rows, from);
    let blind: Vec<LogRow3d> = rows
        .iter()
        .map(|r| LogRow3d {
            speed: f64::NAN,
            ..*r
        })
        .collect();
    let without = score(&blind, &mut Ekf::new(settings(&s)), from);
    let vqf_tuned = golden_log(|t| score(&blind, &mut vqf(t), from).0, 0.05, 100.0, 20);
    // VQF's max error at its RMS-tuned gain (the compensated ekf3d 10x better).
    let vqf_max = score(&blind, &mut vqf(vqf_tuned.0), from).1;
    println!(
        "ride3d ekf3d with the speed {:.3} / {:.3} deg (tuned {:.3}); without {:.3} / {:.3}; \
         VQF tuned {:.3} / {:.3}",
        with.0, with.1, tuned.1, without.0, without.1, vqf_tuned.1, vqf_max
    );
    assert!(vqf_max > 10.0 * with.1, "{vqf_max} vs {with:?}");
    assert!(
        with.0 < 0.3 && with.1 < 1.0 && tuned.1 < 0.3,
        "{with:?} {tuned:?}"
    );
    assert!(without.0 > 5.0 * with.0, "{without:?} vs {with:?}");
    assert!(vqf_tuned.1 > 4.0 * tuned.1, "{vqf_tuned:?} vs {tuned:?}");
}

/// RMS of the roll and the pitch error and the largest of either \[deg\], from `from` on.
fn roll_pitch(rows: &[LogRow3d], e: &mut dyn SpatialEstimator<f64>, from: f64) -> [f64; 3] {
    let mut gate = StepGate::new();
    let (mut sr, mut sp, mut n, mut max) = (0.0, 0.0, 0.0, 0.0f64);
    for r in rows {
        let a = e.update(&r.sample(gate.step(r.t)));
        if r.t >= from {
            let (er, ep) = (
                (a.roll - r.roll).to_degrees(),
                (a.pitch - r.pitch).to_degrees(),
            );
            sr += er * er;
            sp += ep * ep;
            n += 1.0;
            max = max.max(er.abs()).max(ep.abs());
        }
    }
    [(sr / n).sqrt(), (sp / n).sqrt(), max]
}

/// The bounds (roll and pitch 0.3 deg RMS, 1 deg max) at ekf3d's defaults on ride3d
/// with seeds 2 and 3 (seed 1 above), and on ride3d_yawbias (+0.5 deg/s on the gyro's z)
/// with seeds 1-3; ukf3d within 0.02 deg (RMS inclination) of ekf3d on ride3d seed 2.
/// Measured (roll / pitch RMS, max, deg): ride3d seed 2 0.140 / 0.093, 0.64; seed 3
/// 0.121 / 0.207, 0.49; yawbias 0.121 / 0.080, 0.45; 0.129 / 0.092, 0.69; 0.125 / 0.207,
/// 0.49 (with the speed differentiated rather than a state: 0.167 / 0.133, 0.98;
/// 0.149 / 0.254, 0.67; ...). Before the z bias's Jacobian was the specific force's alone
/// and the path's pitch rate was cut at 0.5 Hz, seeds 2 and 3 gave 0.365 / 0.231, 1.51 and
/// 0.280 / 0.354, 0.94. ukf3d on seed 2: 0.166 against ekf3d's 0.168 (0.44 before its
/// sigma points took the z bias through the specific force alone).
#[test]
fn ride3d_on_three_seeds_and_with_a_yaw_rate_bias() {
    let runs = [
        ("ride3d", 2),
        ("ride3d", 3),
        ("ride3d_yawbias", 1),
        ("ride3d_yawbias", 2),
        ("ride3d_yawbias", 3),
    ];
    let mut failed = Vec::new();
    for (name, seed) in runs {
        let (s, rows) = run(name, 120.0, seed);
        let e = roll_pitch(&rows, &mut Ekf::new(settings(&s)), s.score_from);
        println!(
            "{name} seed {seed}: roll {:.3} pitch {:.3} deg RMS, max {:.2}",
            e[0], e[1], e[2]
        );
        if !(e[0] <= 0.3 && e[1] <= 0.3 && e[2] <= 1.0) {
            failed.push((name, seed, e));
        }
        if (name, seed) == ("ride3d", 2) {
            let from = s.score_from;
            let (ekf, _) = score(&rows, &mut Ekf::new(settings(&s)), from);
            let (ukf, _) = score(&rows, &mut Ukf::new(settings(&s)), from);
            println!("ride3d seed 2: ekf3d {ekf:.3}, ukf3d {ukf:.3} deg RMS inclination");
            assert!((ukf - ekf).abs() < 0.02, "ukf3d {ukf} ekf3d {ekf}");
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}
