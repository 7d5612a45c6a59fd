//! Plausibility at the edge and unit checks.
//!
//! Item 2: an impossible reading (beyond the rig's full scale, or absurd) is missing for
//! every estimator, flagged `implausible` on the estimators that read it, reported once
//! with its line; a long sensor gap restarts the estimators that read the sensor. Each
//! case runs a simulated ride through the log reader and the bank (as `estimate` does),
//! clean and faulty, and measures per estimator when it is back within 0.05 deg of the
//! clean run. Item 3: time in ms or us, degrees read as radians (found from the physics,
//! with the factor), cutoffs above Nyquist or below the floor; each detector also runs on
//! correct logs that must not trigger it. Figures: docs/reliability.md section 7b.
use std::process::Command;

use pendtilt::bank::{Bank, Inputs};
use pendtilt::cli::options::rig_bank_settings;
use pendtilt::config::RigConfig;
use pendtilt::core::filters::diff::Cutoff;
use pendtilt::core::{Estimate, Flags};
use pendtilt::io::{
    AccelUnit, EstimatesWriter, LogReader, LogWarning, ReaderOptions, TimeUnit, WarningKind,
};
use pendtilt::pipeline::{self, PassError, PassSummary};
use pendtilt::sim::{simulate, Scenario, SimRow};

/// A simulated ride and the rig file `simulate` writes for it (with the full scales).
fn ride(name: &str, secs: f64, seed: u64) -> (Vec<SimRow>, RigConfig) {
    let mut s = Scenario::named(name).unwrap();
    s.duration = secs;
    (simulate(&s, seed).unwrap(), s.rig().unwrap())
}

/// The cells of each row as text (t, phi, gyro, ax, ay, theta).
fn cells(rows: &[SimRow]) -> Vec<[String; 6]> {
    rows.iter()
        .map(|r| {
            let s = r.sample();
            [r.t, s.phi, s.gyro, s.ax, s.ay, r.truth.theta].map(|v| format!("{v}"))
        })
        .collect()
}

fn text(cells: &[[String; 6]]) -> String {
    let mut s = String::from("t,phi,gyro,ax,ay,theta\n");
    for c in cells {
        s.push_str(&c.join(","));
        s.push('\n');
    }
    s
}

/// One pass of the reader and the bank over a log text.
struct Run {
    names: Vec<&'static str>,
    t: Vec<f64>,
    est: Vec<Vec<Estimate<f64>>>,
    warnings: Vec<LogWarning>,
    result: Result<PassSummary, PassError>,
    implausible_count: u64,
}

fn run_with(log: &str, rig: &RigConfig, options: ReaderOptions) -> Run {
    let mut r = LogReader::new(log.as_bytes(), "ride.csv", options).unwrap();
    let mut bank = Bank::new(&rig_bank_settings(rig), pipeline::inputs_of(&r), None).unwrap();
    let names = bank.names().to_vec();
    let mut est = Vec::new();
    let mut warnings = Vec::new();
    let result = pipeline::run(
        &mut r,
        &mut bank,
        None::<&mut EstimatesWriter<Vec<u8>>>,
        false,
        Some(0.0),
        |w| warnings.push(w.clone()),
        |_, _, e| est.push(e.to_vec()),
    );
    let t: Vec<f64> = log
        .lines()
        .skip(1)
        .take(est.len())
        .map(|l| l.split(',').next().unwrap().parse().unwrap_or(f64::NAN))
        .collect();
    Run {
        names,
        t,
        est,
        warnings,
        result,
        implausible_count: r.summary().count(WarningKind::Implausible),
    }
}

fn run(log: &str, rig: &RigConfig) -> Run {
    run_with(
        log,
        rig,
        ReaderOptions {
            limits: rig.limits(),
            ..ReaderOptions::default()
        },
    )
}

const TOLERANCE_DEG: f64 = 0.05;

/// How far apart two Madgwick runs can stay for good [deg]: its normalised gradient step
/// moves the tilt by 2 beta dt per sample whatever the error (the quaternion's half angle),
/// so when the accelerometer angle falls between two runs they swap sides by 4 beta dt
/// (0.27 deg at beta = 1.18 rad/s and 1 kHz) and never close the gap below that.
fn madgwick_resolution_deg() -> f64 {
    (4.0 * pendtilt::peers::ahrs_planar::MADGWICK_BETA * 1e-3).to_degrees()
}

/// The best a restart after a gap ending at row `k1` could do for estimator `name`, whose
/// two runs on the same readings close as `exp(-rate t)`: start at the truth plus the
/// fault-free run's mean offset over the next 10 s (an oracle). Returns how far that start
/// is from the fault-free run [deg] and when it is within 0.05 deg of it [s],
/// `ln(|d| / 0.05) / rate`.
fn oracle_restart(clean: &Run, rows: &[SimRow], name: &str, k1: usize, rate: f64) -> (f64, f64) {
    let j = clean.names.iter().position(|n| *n == name).unwrap();
    let err = |k: usize| clean.est[k][j].theta - rows[k].truth.theta;
    let offset = (k1..k1 + 10_000).map(err).sum::<f64>() / 10_000.0;
    let d = (err(k1) - offset).abs().to_degrees();
    (d, ((d / TOLERANCE_DEG).ln() / rate).max(0.0))
}

/// Per estimator: the time after `t_end` from which it stays within 0.05 deg of the clean
/// run (0 when it never left), and the largest difference from `t_end + 2 s` on [deg].
fn recovery(clean: &Run, bad: &Run, t_end: f64) -> Vec<(&'static str, f64, f64)> {
    assert_eq!(clean.est.len(), bad.est.len(), "a row was lost");
    let mut out = Vec::new();
    for (j, name) in clean.names.iter().enumerate() {
        let mut last_out = None;
        let mut worst = 0.0f64;
        for (k, &t) in clean.t.iter().enumerate() {
            if t < t_end {
                continue;
            }
            let (a, b) = (clean.est[k][j].theta, bad.est[k][j].theta);
            let d = if a.is_nan() && b.is_nan() {
                0.0
            } else {
                (a - b).abs().to_degrees()
            };
            let d = if d.is_nan() { f64::INFINITY } else { d };
            if d > TOLERANCE_DEG {
                last_out = Some(t);
            }
            if t >= t_end + 2.0 {
                worst = worst.max(d);
            }
        }
        let back = last_out.map_or(0.0, |t| t - t_end + 1e-3);
        out.push((*name, back, worst));
    }
    out
}

/// The second criterion, for every estimator: from `t_from` on, what the fault left in its
/// output (RMS of the faulty run less the clean one) is no larger than its own error (RMS
/// of the clean run less the truth) over the same rows, or than the 0.05 deg tolerance for
/// an estimator more accurate than that: the fault poisoned nothing even where 0.05 deg of
/// the clean run is out of reach. Returns (name, left, own) [deg].
fn left_against_own_error(
    clean: &Run,
    bad: &Run,
    rows: &[SimRow],
    t_from: f64,
) -> Vec<(&'static str, f64, f64)> {
    let mut out = Vec::new();
    for (j, name) in clean.names.iter().enumerate() {
        let (mut left, mut own, mut n) = (0.0, 0.0, 0usize);
        for (k, &t) in clean.t.iter().enumerate() {
            let (a, b) = (clean.est[k][j].theta, bad.est[k][j].theta);
            if t < t_from || !a.is_finite() {
                continue;
            }
            left += (b - a).powi(2);
            own += (a - rows[k].truth.theta).powi(2);
            n += 1;
        }
        let rms = |x: f64| (x / n.max(1) as f64).sqrt().to_degrees();
        out.push((*name, rms(left), rms(own)));
    }
    out
}

/// Asserts [`left_against_own_error`] and prints it.
fn assert_nothing_poisoned(case: &str, clean: &Run, bad: &Run, rows: &[SimRow], t_from: f64) {
    assert_nothing_poisoned_but(case, clean, bad, rows, t_from, &[]);
}

/// [`assert_nothing_poisoned`] but for the estimators `except` (printed only).
fn assert_nothing_poisoned_but(
    case: &str,
    clean: &Run,
    bad: &Run,
    rows: &[SimRow],
    t_from: f64,
    except: &[&str],
) {
    for (name, left, own) in left_against_own_error(clean, bad, rows, t_from) {
        println!("  {case}: {name:<14} left {left:.4} deg RMS, own error {own:.4}");
        if except.contains(&name) {
            continue;
        }
        assert!(
            left.is_finite() && left <= own.max(TOLERANCE_DEG),
            "{case}: {name} left {left} deg RMS, more than its own error {own} and 0.05 deg"
        );
    }
}

/// `tail` (a run started at row `k1`) placed at row `k1` of a run like `like`, whose rows
/// before it fill the rest.
fn shifted(tail: &Run, like: &Run, k1: usize) -> Run {
    let mut est = like.est[..k1].to_vec();
    est.extend_from_slice(&tail.est);
    Run {
        names: like.names.clone(),
        t: like.t.clone(),
        est,
        warnings: Vec::new(),
        result: Err(PassError::Settings(String::new())),
        implausible_count: 0,
    }
}

fn print(case: &str, rec: &[(&str, f64, f64)]) {
    println!("{case}:");
    for (n, back, worst) in rec {
        println!(
            "  {n:<14} back within 0.05 deg after {back:.3} s; max diff from +2 s {worst:.4} deg"
        );
    }
}

fn implausible_warnings(r: &Run) -> Vec<&LogWarning> {
    r.warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Implausible)
        .collect()
}

#[test]
fn one_impossible_cell_per_sensor_is_missing_for_every_estimator_flagged_and_told_once() {
    let (rows, rig) = ride("scooter", 8.0, 6);
    let base = cells(&rows);
    let clean = run(&text(&base), &rig);
    assert!(clean.result.is_ok());
    assert!(implausible_warnings(&clean).is_empty());
    // Row 2500 is on line 2502 (the header is line 1).
    let k = 2500;
    let cases: [(usize, &str, &str, Inputs); 6] = [
        (
            2,
            "1e6",
            "gyro 1e6 rad/s exceeds the full scale 8.73 rad/s",
            gyro(),
        ),
        (
            2,
            "1e308",
            "gyro 1e308 rad/s exceeds the full scale 8.73",
            gyro(),
        ),
        (2, "-9", "gyro -9 rad/s exceeds the full scale 8.73", gyro()),
        (
            3,
            "-1e308",
            "ax -1e308 m/s^2 exceeds the full scale 78.5 m/s^2",
            accel(),
        ),
        (
            4,
            "1e6",
            "ay 1e6 m/s^2 exceeds the full scale 78.5",
            accel(),
        ),
        (1, "1e300", "phi 1e300 rad is physically impossible", phi()),
    ];
    for (col, value, says, sensor) in cases {
        let mut c = base.clone();
        c[k][col] = value.to_string();
        let bad = run(&text(&c), &rig);
        assert!(bad.result.is_ok());
        assert_eq!(bad.est.len(), rows.len(), "{value}: a row was lost");
        let w = implausible_warnings(&bad);
        assert_eq!(w.len(), 1, "{value}: told once: {:?}", bad.warnings);
        let shown = w[0].to_string();
        assert!(shown.starts_with("ride.csv:2502: "), "{shown}");
        assert!(shown.contains(says), "{shown}");
        assert!(!shown.contains("--deg"), "{shown}");
        assert!(
            !bad.warnings
                .iter()
                .any(|w| w.kind == WarningKind::LooksLikeDegrees),
            "{value}: the degree hint must not fire: {:?}",
            bad.warnings
        );
        // Flagged on exactly the estimators that read the sensor, on that row only.
        let mut settings_needs = Vec::new();
        for e in pendtilt::bank::REGISTRY {
            if let Some(j) = bad.names.iter().position(|n| *n == e.name) {
                settings_needs.push((j, e.needs()));
            }
        }
        for (j, needs) in settings_needs {
            let f = bad.est[k][j].flags;
            let reads = needs.intersects(sensor);
            assert_eq!(
                f.contains(Flags::IMPLAUSIBLE),
                reads,
                "{value} {}",
                bad.names[j]
            );
            assert!(!bad.est[k + 1][j].flags.contains(Flags::IMPLAUSIBLE));
        }
        let rec = recovery(&clean, &bad, k as f64 * 1e-3);
        print(&format!("one cell {value} in column {col}"), &rec);
        assert_nothing_poisoned(
            &format!("one cell {value}"),
            &clean,
            &bad,
            &rows,
            k as f64 * 1e-3 + 2.0,
        );
        for (n, back, worst) in &rec {
            if *n == "madgwick" {
                // 0.05 deg is below Madgwick's resolution at this gain and rate (measured
                // 0.14 deg after one missing ax, 0.26 after one missing gyro reading).
                let bound = madgwick_resolution_deg();
                assert!(
                    *worst <= bound,
                    "{value}: madgwick {worst} deg off 2 s after"
                );
            } else {
                assert!(*back <= 2.0, "{value}: {n} back only after {back} s");
            }
        }
    }
}

fn gyro() -> Inputs {
    Inputs {
        gyro: true,
        ..Inputs::default()
    }
}
fn accel() -> Inputs {
    Inputs {
        accel: true,
        ..Inputs::default()
    }
}
fn phi() -> Inputs {
    Inputs {
        phi: true,
        ..Inputs::default()
    }
}

#[test]
fn without_a_full_scale_the_physical_bound_applies_and_no_degree_hint_fires() {
    let (rows, _) = ride("scooter", 3.0, 2);
    let mut c = cells(&rows);
    c[1000][2] = "1e6".into();
    let rig = RigConfig::default();
    let r = run(&text(&c), &rig);
    let w = implausible_warnings(&r);
    assert_eq!(w.len(), 1);
    assert!(
        w[0].message
            .contains("exceeds the physical bound 100 rad/s (no [gyro] full_scale in the rig)"),
        "{}",
        w[0]
    );
    assert!(!r
        .warnings
        .iter()
        .any(|w| w.kind == WarningKind::LooksLikeDegrees));
    // A reading exactly at full scale is clipped but real: kept, flagged saturated.
    let (rows, rig) = ride("scooter", 3.0, 2);
    let fs = rig.gyro.full_scale.unwrap();
    let mut c = cells(&rows);
    c[1000][2] = format!("{fs}");
    let r = run(&text(&c), &rig);
    assert!(implausible_warnings(&r).is_empty());
    // Every estimator reading the gyro says so, the peers too; the others do not.
    for (j, name) in r.names.iter().enumerate() {
        let f = r.est[1000][j].flags;
        let reads_gyro = !matches!(*name, "accel" | "pendulum" | "alg1");
        assert_eq!(f.contains(Flags::SATURATED), reads_gyro, "{name}: {f:?}");
        assert!(!f.contains(Flags::IMPLAUSIBLE), "{name}");
    }
}

/// Why Madgwick is held to its resolution, not to 0.05 deg: one gyro reading off by ten
/// times the gyro's noise (0.028 rad/s for 1 ms, a tilt step of 0.0016 deg, a fault far
/// smaller than any above) leaves every other estimator within 0.001 deg of the unchanged
/// run, and Madgwick 0.27 deg (4 beta dt) apart from it 6.7 s later: its normalised step
/// never shrinks a difference, it swaps two runs' sides by 4 beta dt whenever the
/// accelerometer angle falls between them (measured: differences of 1e-5 to 5e-4 deg
/// were still there 10 s later). Against the truth it is as accurate as before.
///
/// It is also the twin that proves no bridge or restart can bring Madgwick back within
/// 0.05 deg after the burst of 100 (`a_burst_of_100_impossible_cells`, this ride,
/// rows 3000-3099): the changed reading is the burst's first, so the ride and this twin
/// give one faulty log, yet their fault-free runs stand more than 0.1 deg apart more than
/// 2 s after the burst, and no output is within 0.05 deg of both there.
#[test]
fn madgwick_cannot_come_within_0_05_deg_of_itself() {
    let (rows, rig) = ride("scooter", 14.0, 6);
    let base = cells(&rows);
    let clean = run(&text(&base), &rig);
    let sd = {
        let mut s = pendtilt::sim::Scenario::named("scooter").unwrap();
        s.duration = 1.0;
        s.sensors.gyro.noise_density * 1000f64.sqrt()
    };
    let k = 3000;
    let mut c = base.clone();
    c[k][2] = format!("{}", rows[k].sample().gyro + 10.0 * sd);
    let bad = run(&text(&c), &rig);
    let rec = recovery(&clean, &bad, k as f64 * 1e-3);
    print("one gyro reading + 10 sd", &rec);
    for (n, _, worst) in &rec {
        if *n == "madgwick" {
            assert!(
                *worst > 2.0 * TOLERANCE_DEG && *worst <= madgwick_resolution_deg(),
                "{worst}"
            );
        } else {
            assert!(*worst <= 0.001, "{n}: {worst}");
        }
    }
    // As the burst's twin: apart by more than 0.1 deg from 2 s after the burst's end on.
    let j = clean.names.iter().position(|n| *n == "madgwick").unwrap();
    let apart = (k + 100 + 2000..rows.len())
        .map(|i| {
            (clean.est[i][j].theta - bad.est[i][j].theta)
                .abs()
                .to_degrees()
        })
        .fold(0.0, f64::max);
    println!("madgwick: {apart:.3} deg apart from 2 s after the burst's end on");
    assert!(apart > 2.0 * TOLERANCE_DEG, "{apart}");
    assert_nothing_poisoned(
        "one gyro reading + 10 sd",
        &clean,
        &bad,
        &rows,
        k as f64 * 1e-3 + 2.0,
    );
}

#[test]
fn a_burst_of_100_impossible_cells() {
    let (rows, rig) = ride("scooter", 14.0, 6);
    let base = cells(&rows);
    let clean = run(&text(&base), &rig);
    let (k0, n) = (3000, 100);
    for (col, value, name) in [(2, "1e6", "gyro"), (3, "-1e308", "ax"), (1, "1e300", "phi")] {
        let mut c = base.clone();
        for row in c.iter_mut().skip(k0).take(n) {
            row[col] = value.into();
        }
        let bad = run(&text(&c), &rig);
        assert!(bad.result.is_ok());
        assert_eq!(
            bad.implausible_count, n as u64,
            "{name}: every cell counted"
        );
        assert_eq!(implausible_warnings(&bad).len(), 10, "{name}: ten listed");
        let rec = recovery(&clean, &bad, (k0 + n) as f64 * 1e-3);
        print(&format!("burst of {n} {name} = {value}"), &rec);
        let from = (k0 + n) as f64 * 1e-3 + 2.0;
        assert_nothing_poisoned(&format!("burst of {n} {name}"), &clean, &bad, &rows, from);
        for (est, back, worst) in &rec {
            // Every estimator is back within 2 s but Madgwick, which cannot come closer
            // than its resolution (see docs/reliability.md 7b). Mahony was back after
            // 3.97 s before the gyro's gap was bridged (`InputHold::bridged`), 1.18 s now
            // (the bridge waits for `BRIDGE_WINDOW`, 0.42 s, of readings after the gap).
            match (name, *est) {
                (_, "madgwick") => {
                    let bound = madgwick_resolution_deg();
                    assert!(*worst <= bound, "{name}: {est} {worst} deg off 2 s after");
                }
                _ => assert!(*back <= 2.0, "{name}: {est} back after {back} s"),
            }
        }
    }
}

/// 100 missing gyro readings anywhere in a ride (27 gaps: seeds 1, 3, 6, from 2 s to 10 s):
/// the gyro peers bridge the gap with the angle fitted to the gyro's readings on either
/// side (`InputHold::bridged`, `core::estimators::gap_fit`) and are back within 0.05 deg
/// of the fault-free run within 2 s. Holding the mean alone left the integrated angle up
/// to 1 deg off, which Mahony forgets at kp = 0.45 /s: measured before the bridge, Mahony
/// back after up to 5.5 s, beyond 2 s in most gaps; with the line between the means on
/// either side, within 2 s in 22 of 27, at most 3.74 s; with the fit, 26 of
/// 27, at most 3.02 s (the complementary filter at most 0.96 s). Figures: `cargo test --release -p pendtilt --test plausibility --
/// --nocapture anywhere`.
#[test]
fn a_burst_of_100_missing_gyro_readings_anywhere_is_bridged() {
    let mut backs: Vec<(&str, f64)> = Vec::new();
    for seed in [1, 3, 6] {
        let (rows, rig) = ride("scooter", 14.0, seed);
        let base = cells(&rows);
        let clean = run(&text(&base), &rig);
        for k0 in (2000..=10_000).step_by(1000) {
            let mut c = base.clone();
            for row in c.iter_mut().skip(k0).take(100) {
                row[2].clear();
            }
            let bad = run(&text(&c), &rig);
            let rec = recovery(&clean, &bad, (k0 + 100) as f64 * 1e-3);
            for (name, back, _) in rec {
                if ["mahony", "complementary", "ekf"].contains(&name) {
                    backs.push((name, back));
                }
            }
        }
    }
    let times =
        |name: &str| -> Vec<f64> { backs.iter().filter(|b| b.0 == name).map(|b| b.1).collect() };
    for name in ["mahony", "complementary", "ekf"] {
        println!("{name}: back after {:.2?} s", times(name));
    }
    assert!(times("complementary").iter().all(|b| *b <= 2.0));
    // The EKF re-converges from the pendulum (measured 24 of 27 within 2 s, at most
    // 4.06 s; 24 of 27, at most 3.46 s, with theta' loosened by 3 vibration sigmas).
    let ekf = times("ekf");
    let within = ekf.iter().filter(|b| **b <= 2.0).count();
    assert!(within >= 23, "ekf within 2 s in {within} of 27: {ekf:?}");
    assert!(ekf.iter().all(|b| *b <= 5.0), "{ekf:?}");
    let mahony = times("mahony");
    let within = mahony.iter().filter(|b| **b <= 2.0).count();
    assert!(
        within >= 25,
        "mahony within 2 s in {within} of 27: {mahony:?}"
    );
    assert!(mahony.iter().all(|b| *b <= 3.5), "{mahony:?}");
}

/// One missing accelerometer reading anywhere (27 positions, seeds 1, 3, 6): every
/// estimator is back within 0.05 deg of the fault-free run within 2 s. Madgwick holds the
/// last reading for one sample: it skipped the correction, and its normalised
/// step left it 2 beta dt (0.14 deg) from the fault-free run for 5.5 s on the cell.
#[test]
fn one_missing_accelerometer_reading_anywhere_leaves_no_estimator_off() {
    let mut worst: Vec<(&str, f64)> = Vec::new();
    for seed in [1, 3, 6] {
        let (rows, rig) = ride("scooter", 14.0, seed);
        let base = cells(&rows);
        let clean = run(&text(&base), &rig);
        for k in (2000..=10_000).step_by(1000) {
            let mut c = base.clone();
            c[k][3].clear();
            let bad = run(&text(&c), &rig);
            for (name, back, _) in recovery(&clean, &bad, (k + 1) as f64 * 1e-3) {
                match worst.iter_mut().find(|w| w.0 == name) {
                    Some(w) => w.1 = w.1.max(back),
                    None => worst.push((name, back)),
                }
            }
        }
    }
    println!("back after, the worst of 27: {worst:.3?}");
    for (name, back) in worst {
        assert!(back <= 2.0, "{name}: {back} s");
    }
}

/// A 450 ms gap in the gyro in the middle of a turn (the scooter ride, 12 s, seed 6, from
/// 8.2 s, where the body turns at 0.5 rad/s): the EKF and UKF coast on the gyro's 25 ms
/// mean and the pendulum. With theta' loosened by three vibration sigmas
/// (`MISSING_RATE_SIGMAS` before) the encoder's readings, swung by the pivot's
/// unknown translation, turned theta 5.7 deg off the truth; now 1.8 deg at most (the
/// fault-free run 0.10 over the same second).
#[test]
fn a_gyro_gap_in_a_turn_leaves_the_model_based_filters_on_the_pendulum() {
    let (rows, rig) = ride("scooter", 12.0, 6);
    let mut c = cells(&rows);
    for row in c.iter_mut().skip(8200).take(450) {
        row[2].clear();
    }
    let r = run(&text(&c), &rig);
    assert_eq!(r.result.as_ref().unwrap().restarts, 0);
    for name in ["ekf", "ukf"] {
        let j = r.names.iter().position(|n| *n == name).unwrap();
        let worst = (8200..9200)
            .map(|k| (r.est[k][j].theta - rows[k].truth.theta).abs().to_degrees())
            .fold(0.0, f64::max);
        println!("{name}: at most {worst:.2} deg from the truth over the gap and 0.55 s after");
        assert!(worst < 2.5, "{name}: {worst} deg");
    }
}

#[test]
fn a_10_s_gap_of_every_sensor_restarts_every_estimator_as_if_started_there() {
    let (rows, rig) = ride("scooter", 30.0, 3);
    let base = cells(&rows);
    let clean = run(&text(&base), &rig);
    let (k0, k1) = (5000, 15000);
    let mut c = base.clone();
    for row in c.iter_mut().take(k1).skip(k0) {
        for cell in row.iter_mut().take(5).skip(1) {
            cell.clear();
        }
    }
    let bad = run(&text(&c), &rig);
    assert!(bad.result.is_ok());
    assert_eq!(bad.est.len(), rows.len());
    let restarts: Vec<_> = bad
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Restarted)
        .collect();
    assert_eq!(restarts.len(), 1, "{:?}", bad.warnings);
    assert_eq!(restarts[0].line, k1 as u64 + 2);
    assert!(
        restarts[0].message.contains("after a gap of 10.0"),
        "{}",
        restarts[0]
    );
    assert_eq!(bad.result.as_ref().unwrap().restarts, 1);
    // Beyond the restart gap (0.5 s) no estimator gives an estimate: each reads a sensor
    // that is gone (they gave the gyro's last mean integrated, the EKF 170 deg off by the
    // gap's end, and the summary counted it: 58 deg RMS).
    for (k, row) in bad.est.iter().enumerate().take(k1).skip(k0 + 502) {
        for (j, e) in row.iter().enumerate() {
            assert!(
                e.theta.is_nan() && e.flags.contains(Flags::SAMPLE_MISSING),
                "{} at row {k}: {e:?}",
                bad.names[j]
            );
        }
    }

    // After the gap every estimator gives exactly what it gives when started there, but
    // the EKF and the UKF, which resume: they keep their gyro bias (a gap cannot change it
    // beyond its random walk) and start the rest afresh.
    let resumes = |name: &str| matches!(name, "ekf" | "ukf" | "complementary" | "mahony");
    let tail = run(&text(&base[k1..]), &rig);
    for (k, row) in tail.est.iter().enumerate() {
        for (j, e) in row.iter().enumerate() {
            if resumes(tail.names[j]) {
                continue;
            }
            let b = bad.est[k1 + k][j];
            // Equal to rounding: a restarted differentiator may keep its filter design
            // for the same step (1 ulp).
            assert!(
                (e.theta - b.theta).abs() <= 1e-12 && e.flags == b.flags,
                "{} at row {}: {:?} against {:?}",
                tail.names[j],
                k1 + k,
                b,
                e
            );
        }
    }
    let rec = recovery(&clean, &bad, k1 as f64 * 1e-3);
    print("10 s gap of every sensor", &rec);
    let fresh = recovery(&clean, &shifted(&tail, &bad, k1), k1 as f64 * 1e-3);
    print("the same rows started afresh", &fresh);
    assert_nothing_poisoned("10 s gap", &clean, &bad, &rows, k1 as f64 * 1e-3 + 2.0);
    for ((est, back, worst), (_, back_fresh, _)) in rec.iter().zip(&fresh) {
        // Bounds measured (docs/reliability.md 7b). The complementary filter and Mahony
        // restart as a running mean of the accelerometer angle (after the prefilter has
        // settled) and keep their steady offset, the gyro bias times their time constant:
        // the complementary filter is back after 1.98 s (2.36 s started afresh); Mahony
        // (kp = 0.45 /s) after 7.24 s (10.95 s afresh, from one reading): what its clean
        // run remembers of the accelerometer over the last seconds fades at kp, 0.41 of
        // it in 2 s, and no restart can know it (the twins of
        // `no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap`). Madgwick: its
        // resolution.
        match *est {
            "madgwick" => assert!(*worst <= madgwick_resolution_deg(), "{est}: {worst} deg"),
            "mahony" => assert!(
                *back <= 9.0 && *worst <= 0.8,
                "{est}: back after {back} s, {worst} deg off 2 s after the gap"
            ),
            _ => assert!(*back <= 2.0, "{est} back after {back} s"),
        }
        match *est {
            // Keeping the bias: back within 1.01 s; started afresh the bias re-converges
            // over 5.6 s.
            "ekf" | "ukf" => assert!(
                *back <= 1.1 && *back_fresh > 5.0,
                "{est}: {back} s, afresh {back_fresh} s"
            ),
            // Keeping the steady offset.
            "complementary" | "mahony" => assert!(
                *back < 0.9 * back_fresh,
                "{est}: {back} s, afresh {back_fresh} s"
            ),
            _ => assert!(!resumes(est)),
        }
    }

    // The same gap as missing rows (the time jumps by 10 s).
    let mut c = base[..k0].to_vec();
    c.extend_from_slice(&base[k1..]);
    let jumped = run(&text(&c), &rig);
    assert_eq!(jumped.result.as_ref().unwrap().restarts, 1);
    for (k, row) in bad.est[k1..].iter().enumerate() {
        for (j, e) in row.iter().enumerate() {
            let d = (e.theta - jumped.est[k0 + k][j].theta).abs();
            // The resuming filters grow the bias variance by its walk over the gap either
            // way (predicted through the empty rows, or added for the jump).
            let tol = if resumes(bad.names[j]) { 1e-6 } else { 1e-12 };
            assert!(d <= tol, "{} at row {}: {d}", bad.names[j], k1 + k);
        }
    }
}

#[test]
fn a_gap_shorter_than_the_restart_gap_is_bridged_not_restarted() {
    let (rows, rig) = ride("scooter", 4.0, 6);
    let mut c = cells(&rows);
    for row in c.iter_mut().skip(1000).take(400) {
        row[2].clear();
    }
    let r = run(&text(&c), &rig);
    assert_eq!(r.result.as_ref().unwrap().restarts, 0);
    for row in c.iter_mut().skip(1000).take(600) {
        row[2].clear();
    }
    let r = run(&text(&c), &rig);
    assert_eq!(r.result.as_ref().unwrap().restarts, 1);
    let w = r
        .warnings
        .iter()
        .find(|w| w.kind == WarningKind::Restarted)
        .unwrap();
    assert!(
        w.message.starts_with("gyro back after a gap of 0.60"),
        "{w}"
    );
    // Only the estimators reading the gyro restarted: accel and pendulum did not.
    let n_gyro = pendtilt::bank::REGISTRY
        .iter()
        .filter(|e| r.names.contains(&e.name) && e.needs().gyro)
        .count();
    // alg1 shares its front end with alg2, so it restarts with it.
    assert!(
        w.message.contains(&format!("{} estimators", n_gyro + 1)),
        "{w}"
    );
}

// ---------------------------------------------------------------------------------------
// Item 3: units.

fn retimed(rows: &[SimRow], scale: f64) -> String {
    let mut c = cells(rows);
    for (row, r) in c.iter_mut().zip(rows) {
        row[0] = format!("{}", (r.t * scale * 1e6).round() / 1e6);
    }
    text(&c)
}

#[test]
fn time_in_ms_or_us_is_an_error_with_the_fix_and_the_fix_works() {
    let (rows, rig) = ride("step", 2.0, 1);
    for (scale, unit, fix) in [
        (1e3, TimeUnit::Ms, "--time-unit ms (1000 Hz)"),
        (1e6, TimeUnit::Us, "--time-unit us (1000 Hz)"),
    ] {
        let log = retimed(&rows, scale);
        let r = run(&log, &rig);
        let err = r.result.unwrap_err().to_string();
        assert!(err.starts_with("ride.csv:17: column 1 (`t`): "), "{err}");
        assert!(err.contains(fix), "{err}");
        // No restart warnings before the error (each step would be a "gap").
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        let fixed = run_with(
            &log,
            &rig,
            ReaderOptions {
                limits: rig.limits(),
                time_unit: Some(unit),
                ..ReaderOptions::default()
            },
        );
        let s = fixed.result.unwrap();
        assert_eq!((s.rows, s.restarts), (rows.len() as u64, 0));
    }
    // Correct logs at 1 kHz, 100 Hz and 20 Hz, and a short one, pass.
    for (rate, secs) in [(1000.0, 2.0), (100.0, 3.0), (20.0, 5.0), (1000.0, 0.005)] {
        let mut s = Scenario::named("step").unwrap();
        s.rate = rate;
        s.duration = secs;
        let rows = simulate(&s, 1).unwrap();
        let r = run(&text(&cells(&rows)), &s.rig().unwrap());
        assert!(
            r.result.is_ok(),
            "{rate} Hz: {:?}",
            r.result.err().map(|e| e.to_string())
        );
    }
}

fn degrees(rows: &[SimRow], cols: &[usize]) -> String {
    let mut c = cells(rows);
    for row in &mut c {
        for &i in cols {
            row[i] = format!("{}", row[i].parse::<f64>().unwrap().to_degrees());
        }
    }
    text(&c)
}

fn findings(r: &Run) -> Vec<(&'static str, f64, String)> {
    r.result
        .as_ref()
        .unwrap()
        .unit_findings
        .iter()
        .map(|f| (f.column, f.fit.factor, f.message.clone()))
        .collect()
}

/// The scenarios the degree detector must stay quiet on when the units are right.
fn scenarios() -> Vec<(&'static str, Vec<SimRow>, RigConfig)> {
    let mut v = Vec::new();
    for (name, secs) in [
        ("still", 6.0),
        ("step", 5.0),
        ("scooter", 12.0),
        ("sine", 10.0),
    ] {
        let (rows, rig) = ride(name, secs, 4);
        v.push((name, rows, rig));
    }
    // The case: a small motion, 2.3 deg and about 8 deg/s.
    let mut s = Scenario::named("sine").unwrap();
    s.motion.set_amplitude(0.04);
    s.duration = 12.0;
    v.push(("small sine", simulate(&s, 4).unwrap(), s.rig().unwrap()));
    v
}

#[test]
fn degrees_are_found_from_the_physics_with_the_factor_and_correct_logs_are_quiet() {
    for (name, rows, rig) in scenarios() {
        let clean = run(&text(&cells(&rows)), &rig);
        assert!(
            findings(&clean).is_empty(),
            "{name}: {:?}",
            findings(&clean)
        );
        if name == "still" {
            // Nothing moves: no fit, nothing to tell (and nothing claimed).
            let r = run(&degrees(&rows, &[2]), &rig);
            assert!(findings(&r).is_empty(), "{name}: {:?}", findings(&r));
            continue;
        }
        // The gyro in deg/s: 57.3x the encoder's derivative.
        let r = run(&degrees(&rows, &[2]), &rig);
        let f = findings(&r);
        assert_eq!(f.len(), 1, "{name}: {f:?}");
        assert_eq!(f[0].0, "gyro", "{name}: {f:?}");
        assert!(
            (f[0].1 / 57.3 - 1.0).abs() < 0.1,
            "{name}: factor {}",
            f[0].1
        );
        assert!(f[0].2.contains("the encoder's derivative") && f[0].2.contains("--deg gyro"));
        println!("{name}, gyro in deg/s: {}", f[0].2);
        // Every angle in degrees: each column named against the accelerometer.
        let r = run(&degrees(&rows, &[1, 2, 5]), &rig);
        let mut cols: Vec<_> = findings(&r).iter().map(|f| f.0).collect();
        cols.sort();
        assert_eq!(cols, ["gyro", "phi", "theta"], "{name}: {:?}", findings(&r));
        for f in findings(&r) {
            // Found directly (57.3 within the accelerometer's vibration bias), or by
            // following phi, itself found in degrees.
            assert!(
                (f.1 / 57.3 - 1.0).abs() < 0.3 || f.2.contains("and phi is in degrees"),
                "{name}: {f:?}"
            );
            assert!(f.2.contains(&format!("--deg {}", f.0)), "{name}: {f:?}");
            println!("{name}, all in degrees: {}", f.2);
        }
        // Only phi in degrees: phi' is 57.3x the gyro and phi 57.3x the accelerometer.
        let r = run(&degrees(&rows, &[1]), &rig);
        let f = findings(&r);
        assert_eq!(f.len(), 1, "{name}: {f:?}");
        assert_eq!(f[0].0, "phi", "{name}: {f:?}");
        // Read with --deg, the same logs are quiet again.
        let fixed = run_with(
            &degrees(&rows, &[1, 2, 5]),
            &rig,
            ReaderOptions {
                limits: rig.limits(),
                degrees: "phi,gyro,theta".parse().unwrap(),
                ..ReaderOptions::default()
            },
        );
        assert!(
            findings(&fixed).is_empty(),
            "{name}: {:?}",
            findings(&fixed)
        );
    }
}

/// `rows` as a log text with the accelerometer divided by `per` \[m/s^2 per unit\].
fn accel_in(rows: &[SimRow], per: f64) -> String {
    let mut c = cells(rows);
    for (row, r) in c.iter_mut().zip(rows) {
        row[3] = format!("{}", r.ax / per);
        row[4] = format!("{}", r.ay / per);
    }
    text(&c)
}

/// An accelerometer in g or mg read as m/s^2 (item 3; found as a new user):
/// the planar estimators read only its direction, so g changed no estimate and said
/// nothing, but mg put every reading beyond the full scale (every accelerometer reader
/// without an estimate, 10 of 103 024 impossible readings listed, no fix). Now the median
/// magnitude against gravity names the unit and the fix, `--accel-unit`, with which the
/// estimates are the m/s^2 log's; read with `--accel-unit g` when in m/s^2 it says to leave
/// it out. Correct logs stay quiet (here and in the two degree tests above, which check
/// every finding).
#[test]
fn an_accelerometer_in_g_or_mg_is_named_from_gravity_and_the_fix_works() {
    let (rows, rig) = ride("scooter", 10.0, 2);
    let right = run(&text(&cells(&rows)), &rig);
    assert!(findings(&right).is_empty(), "{:?}", findings(&right));
    let with_unit = |log: &str, unit: AccelUnit| {
        run_with(
            log,
            &rig,
            ReaderOptions {
                accel_unit: Some(unit),
                ..ReaderOptions::for_rig(&rig)
            },
        )
    };
    for unit in [AccelUnit::G, AccelUnit::MilliG] {
        let log = accel_in(&rows, unit.metres_per_second_squared());
        let wrong = run(&log, &rig);
        let f = findings(&wrong);
        assert_eq!(f.len(), 1, "{unit}: {f:?}");
        assert_eq!(f[0].0, "ax, ay");
        assert!(
            f[0].2.contains(&format!(
                "is the accelerometer in {unit}? read it with --accel-unit {unit}"
            )),
            "{}",
            f[0].2
        );
        println!("{unit}: {}", f[0].2);
        let fixed = with_unit(&log, unit);
        assert!(
            findings(&fixed).is_empty(),
            "{unit}: {:?}",
            findings(&fixed)
        );
        assert_eq!(fixed.implausible_count, 0);
        for (k, (a, b)) in right.est.iter().zip(&fixed.est).enumerate() {
            for (j, (a, b)) in a.iter().zip(b).enumerate() {
                assert!(
                    (a.theta - b.theta).abs() <= 1e-9 || (a.theta.is_nan() && b.theta.is_nan()),
                    "{unit} {} row {k}: {} against {}",
                    right.names[j],
                    a.theta,
                    b.theta
                );
            }
        }
    }
    // m/s^2 read as g.
    let twice = with_unit(&text(&cells(&rows)), AccelUnit::G);
    let f = findings(&twice);
    assert!(
        f.len() == 1
            && f[0]
                .2
                .contains("is it already in m/s^2? leave out --accel-unit g"),
        "{f:?}"
    );
}

/// A sensor that counts the other way from MODEL.md section 1's signs (found as a new
/// user): phi, gyro or ax negated on the scooter ride gave 12.0 deg RMS (alg2), 8.0
/// (ekf) and 3.8 (Mahony) with nothing said. Now the pairs that fit with the sign reversed
/// name the column, the accelerometer's angle the reference and the true angle, when the
/// log has it, telling ax from phi and gyro both; `--negate` fixes it, to the bit.
#[test]
fn a_column_counting_the_other_way_is_named_and_negate_fixes_it() {
    let (rows, rig) = ride("scooter", 10.0, 2);
    let base = cells(&rows);
    let right = run(&text(&base), &rig);
    let without_theta = |c: &[[String; 6]]| {
        let mut t = String::from("t,phi,gyro,ax,ay\n");
        for r in c {
            t.push_str(&r[..5].join(","));
            t.push('\n');
        }
        t
    };
    for (cols, with_theta, named) in [
        (&[1][..], true, "phi"),
        (&[2], true, "gyro"),
        (&[3], true, "ax"),
        (&[5], true, "theta"),
        (&[1, 2], true, "phi, gyro"),
        (&[1], false, "phi"),
        (&[2], false, "gyro"),
        // Without the true angle, ax reversed and phi and gyro both reversed look alike.
        (&[3], false, "phi, gyro"),
    ] {
        let mut c = base.clone();
        for row in c.iter_mut() {
            for &i in cols {
                row[i] = format!("{}", -row[i].parse::<f64>().unwrap());
            }
        }
        let log = if with_theta {
            text(&c)
        } else {
            without_theta(&c)
        };
        let case = format!("{cols:?} negated, theta {with_theta}");
        let wrong = run(&log, &rig);
        let f = findings(&wrong);
        assert_eq!(f.len(), 1, "{case}: {f:?}");
        assert_eq!(f[0].0, named, "{case}: {f:?}");
        println!("{case}: {}", f[0].2);
        let list: Vec<&str> = cols
            .iter()
            .map(|&i| ["t", "phi", "gyro", "ax", "ay", "theta"][i])
            .collect();
        let list = list.join(",");
        assert!(
            f[0].2.contains(&format!("--negate {list}")),
            "{case}: {}",
            f[0].2
        );
        let fixed = run_with(
            &log,
            &rig,
            ReaderOptions {
                negate: list.parse().unwrap(),
                ..ReaderOptions::for_rig(&rig)
            },
        );
        assert!(
            findings(&fixed).is_empty(),
            "{case}: {:?}",
            findings(&fixed)
        );
        for (k, (a, b)) in right.est.iter().zip(&fixed.est).enumerate() {
            for (j, (a, b)) in a.iter().zip(b).enumerate() {
                assert!(
                    a.theta.to_bits() == b.theta.to_bits(),
                    "{case}: {} row {k}: {} against {}",
                    right.names[j],
                    a.theta,
                    b.theta
                );
            }
        }
    }
}

/// Short logs (4 s): the gyro in deg/s and `--deg` given on a log in radians are found
/// (now the filters start on the mean of the first 50 ms and are read from one
/// period of their cutoff on, 1.8 s, where they waited 3.7 s after starting on one reading,
/// and none of these was said), and the correct logs stay quiet, a still one included (a
/// reference moving less than 0.5 deg gives no fit).
#[test]
fn degree_mistakes_on_a_4_s_log_are_found_and_correct_short_logs_are_quiet() {
    for name in ["step", "sine", "sigmoid", "scooter", "chirp", "still"] {
        for seed in [1, 2] {
            let (rows, rig) = ride(name, 4.0, seed);
            let case = format!("{name} seed {seed}");
            let clean = run(&text(&cells(&rows)), &rig);
            assert!(
                findings(&clean).is_empty(),
                "{case}: {:?}",
                findings(&clean)
            );
            if name == "still" {
                continue;
            }
            let r = run(&degrees(&rows, &[2]), &rig);
            let f = findings(&r);
            assert!(
                f.iter()
                    .any(|f| f.0 == "gyro" && f.2.contains("--deg gyro")),
                "{case}: {f:?}"
            );
            // In radians, read with --deg: 1/57.3 of the accelerometer's angle.
            let twice = run_with(
                &text(&cells(&rows)),
                &rig,
                ReaderOptions {
                    limits: rig.limits(),
                    degrees: "phi,gyro,theta".parse().unwrap(),
                    ..ReaderOptions::default()
                },
            );
            let f = findings(&twice);
            assert!(
                f.iter()
                    .any(|f| f.0 == "phi" && f.2.contains("already in radians")),
                "{case}: {f:?}"
            );
        }
    }
}

#[test]
fn cutoffs_above_nyquist_or_below_the_floor_are_refused_with_the_valid_range() {
    let (rows, rig) = ride("step", 2.0, 1);
    let log = text(&cells(&rows));
    let refuse = |edit: &dyn Fn(&mut RigConfig), says: &[&str]| {
        let mut r = rig.clone();
        edit(&mut r);
        let e = run(&log, &r).result.unwrap_err().to_string();
        for s in says {
            assert!(e.contains(s), "{e}");
        }
    };
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::Hz(1000.0),
        &[
            "ride.csv: [differentiator] cutoff_hz = 1000 Hz is at or above the Nyquist frequency 500 Hz",
            "valid range: 1.09",
            "up to below 500 Hz",
        ],
    );
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::Hz(500.0),
        &["Nyquist frequency 500 Hz"],
    );
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::Hz(0.2),
        &["cutoff_hz = 0.2 Hz is below 0.5 f_n", "f_n = 2.186 Hz"],
    );
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::TimesNatural(300.0),
        &["cutoff_times_natural = 300", "Nyquist"],
    );
    refuse(
        &|r| r.accel.prefilter_hz = Some(600.0),
        &["[accel] prefilter_hz = 600 Hz is at or above the Nyquist frequency 500 Hz"],
    );
    // Accepted: anything inside the range.
    for hz in [1.2, 2.8, 40.0, 400.0] {
        let mut r = rig.clone();
        r.differentiator.cutoff = Cutoff::Hz(hz);
        assert!(run(&log, &r).result.is_ok(), "{hz} Hz refused");
    }
    // At 100 Hz, 60 Hz is above Nyquist; 40 Hz is not.
    let mut s = Scenario::named("step").unwrap();
    s.rate = 100.0;
    s.duration = 2.0;
    let slow = text(&cells(&simulate(&s, 1).unwrap()));
    let mut r = rig.clone();
    r.differentiator.cutoff = Cutoff::Hz(60.0);
    assert!(run(&slow, &r)
        .result
        .unwrap_err()
        .to_string()
        .contains("Nyquist frequency 50 Hz"));
    r.differentiator.cutoff = Cutoff::Hz(40.0);
    assert!(run(&slow, &r).result.is_ok());
}

#[test]
fn estimate_end_to_end_one_absurd_gyro_cell() {
    let dir = tempfile::tempdir().unwrap();
    let (rows, rig) = ride("scooter", 3.0, 6);
    let mut c = cells(&rows);
    c[2501][2] = "1e6".into();
    let log = dir.path().join("ride.csv");
    std::fs::write(&log, text(&c)).unwrap();
    let rig_path = dir.path().join("rig.toml");
    rig.save(&rig_path).unwrap();
    let out = dir.path().join("est.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-p",
            rig_path.to_str().unwrap(),
        ])
        .args(["-o", out.to_str().unwrap(), "--flags"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "ride.csv:2503: column `gyro`: gyro 1e6 rad/s exceeds the full scale 8.73 rad/s"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("looks like degrees"), "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), rows.len() + 1);
    assert!(lines[2502].contains("implausible"), "{}", lines[2502]);
    assert!(!lines[2503].contains("implausible"));

    // The same log with t in ms: refused, the fix named; with it, accepted.
    let ms = dir.path().join("ms.csv");
    std::fs::write(&ms, retimed(&rows, 1e3)).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args([
            "estimate",
            ms.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(stderr.contains("--time-unit ms"), "{stderr}");
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args([
            "estimate",
            ms.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .args(["--time-unit", "ms"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The restarts of the 10 s gap over six rides (seeds 1-6, 30 s) and three gap positions
/// each (5-15 s, 8-18 s, 6-16.5 s): nothing poisoned for every estimator but Mahony in
/// all 18; the
/// complementary filter back within 0.05 deg of the fault-free run within 2 s in at least
/// 14 of them and within 3 s in all (measured: 14, worst 2.82 s; 3 of 18 and 3.05 s
/// before it kept its offset); Mahony within 9 s in all (1.4-8.0 s; 7.1-12.9 s from one
/// reading) and, against the truth from 2 s after the gap, within 0.25 deg of its
/// fault-free run's error in all (measured: at most 0.16 deg worse; up to 1.67 deg worse
/// when it restarted from one reading); and a restart knowing the truth (an oracle) would
/// still be beyond 2 s in at least half of them (measured 11 of 18, up to 4.9 s): the
/// fault-free run's own error at the gap's end, 0.04-0.45 deg, fades only at kp. Figures:
/// `cargo test --release -p pendtilt --test plausibility -- --nocapture over_six`.
#[test]
fn restarts_over_six_rides_and_three_gap_positions() {
    let (mut comp, mut mahony_back, mut mahony_truth) = (Vec::new(), Vec::new(), Vec::new());
    let (mut mahony_oracle, mut comp_oracle) = (Vec::new(), Vec::new());
    let comp_tau = pendtilt::peers::PeerSettings::default()
        .complementary
        .time_constant;
    for seed in 1..=6u64 {
        let (rows, rig) = ride("scooter", 30.0, seed);
        let base = cells(&rows);
        let clean = run(&text(&base), &rig);
        for (k0, k1) in [(5000usize, 15000usize), (8000, 18000), (6000, 16500)] {
            let mut c = base.clone();
            for row in c.iter_mut().take(k1).skip(k0) {
                for cell in row.iter_mut().take(5).skip(1) {
                    cell.clear();
                }
            }
            let bad = run(&text(&c), &rig);
            let from = k1 as f64 * 1e-3 + 2.0;
            let case = format!("seed {seed}, gap rows {k0}-{k1}");
            // Mahony is held to its own bound below: on the rides where its own error is
            // smallest (0.127 deg RMS, seed 1, the gap at 5 s) what its slow memory of the
            // accelerometer leaves over the following 10 s is larger (0.189 deg RMS).
            assert_nothing_poisoned_but(&case, &clean, &bad, &rows, from, &["mahony"]);
            let rec = recovery(&clean, &bad, k1 as f64 * 1e-3);
            let back = |name: &str| rec.iter().find(|r| r.0 == name).unwrap().1;
            comp.push(back("complementary"));
            mahony_back.push(back("mahony"));
            let j = clean.names.iter().position(|n| *n == "mahony").unwrap();
            let truth_rms = |r: &Run| {
                let e: Vec<f64> = ((from * 1000.0).round() as usize..rows.len())
                    .map(|k| (r.est[k][j].theta - rows[k].truth.theta).powi(2))
                    .collect();
                (e.iter().sum::<f64>() / e.len() as f64).sqrt().to_degrees()
            };
            let (b, c) = (truth_rms(&bad), truth_rms(&clean));
            // The best a restart could do: start at the truth plus the fault-free run's
            // mean offset over the next 10 s (an oracle). Two Mahony runs on the same
            // readings differ by their difference at the start times exp(-kp t), so the
            // oracle is back within 0.05 deg after ln(|d| / 0.05) / kp.
            let kp = pendtilt::peers::ahrs_planar::MAHONY_GAINS[0];
            let (d, oracle) = oracle_restart(&clean, &rows, "mahony", k1, kp);
            println!(
                "  mahony: an oracle restart {d:.3} deg from the fault-free run, back after \
                 {oracle:.2} s"
            );
            mahony_oracle.push(oracle);
            let (d, oracle) = oracle_restart(&clean, &rows, "complementary", k1, 1.0 / comp_tau);
            println!(
                "  complementary: an oracle restart {d:.3} deg from the fault-free run, back \
                 after {oracle:.2} s"
            );
            comp_oracle.push(oracle);
            println!(
                "{case}: complementary back after {:.3} s, mahony {:.3} s, mahony against \
                 the truth {b:.3} deg RMS (fault-free {c:.3})",
                back("complementary"),
                back("mahony")
            );
            mahony_truth.push(b - c);
        }
    }
    let within_2 = comp.iter().filter(|b| **b <= 2.0).count();
    assert!(
        within_2 >= 14,
        "complementary within 2 s in {within_2} of 18: {comp:?}"
    );
    assert!(comp.iter().all(|b| *b <= 3.0), "{comp:?}");
    assert!(mahony_back.iter().all(|b| *b <= 9.0), "{mahony_back:?}");
    assert!(mahony_truth.iter().all(|d| *d <= 0.25), "{mahony_truth:?}");
    let comp_beyond: Vec<_> = (0..18).filter(|&i| comp[i] > 2.0).collect();
    println!(
        "complementary: beyond 2 s in {comp_beyond:?}, an oracle restart there {:.2?}; \
         every oracle {comp_oracle:.2?}",
        comp_beyond
            .iter()
            .map(|&i| comp_oracle[i])
            .collect::<Vec<_>>()
    );
    // An oracle restart (knowing the truth and the next 10 s) is back within 1.6 s in all
    // 18. What a restart cannot know is the fault-free run's own error at the gap's end (its
    // accelerometer's error over the gap's last tau): a twin of the ride that brakes in the
    // gap gives the same faulty log and another fault-free run, so no restart meets 2 s on
    // both (`no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap`). Tried
    // earlier, estimating it from the readings after the gap by their uniform
    // mean, or by their mean mirrored with weights exp(-t / T), T = 0.5-4 tau: 4 of 18
    // beyond 2 s in each (at most 2.35-2.79 s).
    assert!(comp_oracle.iter().all(|t| *t <= 2.0), "{comp_oracle:?}");
    let beyond = mahony_oracle.iter().filter(|t| **t > 2.0).count();
    println!("mahony: an oracle restart is beyond 2 s in {beyond} of 18: {mahony_oracle:.2?}");
    // Why 2 s is out of reach for Mahony at kp = 0.45 /s: even a restart knowing the truth
    // misses it in most cases (measured 11 of 18, up to 4.9 s).
    assert!(beyond >= 9, "{mahony_oracle:?}");
}

/// One absurd cell in the truth column (`theta` 1e6) is read as missing, said with its
/// line, and left out of the score (earlier: it was scored, every estimator's RMS
/// printed as 523036 deg on the 12 s ride, with the hint "looks like degrees; read it
/// with --deg theta", which would have made every other truth cell wrong).
#[test]
fn an_absurd_truth_cell_is_not_scored_and_not_called_degrees() {
    let (rows, _) = ride("scooter", 3.0, 2);
    let dir = tempfile::tempdir().unwrap();
    let summary = |name: &str, c: &[[String; 6]]| {
        let log = dir.path().join(name);
        std::fs::write(&log, text(c)).unwrap();
        let out = dir.path().join("est.csv");
        let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
            .args([
                "estimate",
                log.to_str().unwrap(),
                "--score-from",
                "0",
                "-o",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(o.status.success());
        let alg2 = String::from_utf8_lossy(&o.stdout)
            .lines()
            .find(|l| l.starts_with("alg2 "))
            .unwrap()
            .split_whitespace()
            .map(String::from)
            .collect::<Vec<_>>();
        (String::from_utf8_lossy(&o.stderr).into_owned(), alg2)
    };
    let mut c = cells(&rows);
    let (_, clean) = summary("clean.csv", &c);
    c[1000][5] = "1e6".into();
    let (e, bad) = summary("bad.csv", &c);
    assert!(
        e.contains("bad.csv:1002: column `theta`: theta 1e6 rad is no tilt (beyond 10000 rad, 1592 turns): the true angle is read as missing, the row not scored"),
        "{e}"
    );
    assert!(!e.contains("degrees"), "{e}");
    assert_eq!(bad[3], "2999", "{bad:?}");
    assert_eq!(clean[3], "3000", "{clean:?}");
    let rms = |r: &[String]| r[1].parse::<f64>().unwrap();
    assert!((rms(&bad) - rms(&clean)).abs() < 0.01, "{bad:?} {clean:?}");
}

/// The gap's text of a log: every sensor cell of rows `k0..k1` empty.
fn gapped(c: &[[String; 6]], k0: usize, k1: usize) -> String {
    let mut c = c.to_vec();
    for row in c.iter_mut().take(k1).skip(k0) {
        for cell in row.iter_mut().take(5).skip(1) {
            cell.clear();
        }
    }
    text(&c)
}

/// Why no restart can bring the accelerometer peers back within 0.05 deg of their
/// fault-free run 2 s after the 10 s gap (seed 3, 5-15 s), and why the
/// complementary filter's 1.98 s there is its ride's luck. Two twins of the ride differ
/// from it only inside the gap, where the gap took every reading away: one brakes gently
/// over the gap's last 2 s (a horizontal deceleration `1 m/s^2 sin^2`, 0.1 g at its peak,
/// read by the accelerometer as the specific force it makes in the tilted body axes), one
/// rides a smooth road over the gap's last 5 s (the accelerometer as the same ride without
/// vibration gives it). The faulty logs of the three are one log, so any restart gives one
/// output on all three; but their fault-free runs, which remember what the accelerometer
/// read at their own rate, stand up to `D` apart from 2 s after the gap on, and a restart
/// within 0.05 deg of two of them there needs `D <= 0.1 deg`. Measured D (braking /
/// smooth road): Mahony 0.79 / 0.46 deg, the complementary filter 0.17 / 0.01, Madgwick
/// 0.25 / 0.26 (its resolution: the few millidegrees its runs differ by at the gap's end
/// become up to 4 beta dt, 0.27 deg). The same restart is back after 7.24 s on the ride
/// and 1.35 s on the smooth-road twin (Mahony), 1.98 s and 3.11 s on the braking one (the
/// complementary filter): which one meets 2 s is decided by readings no restart sees.
/// The estimators that read the pendulum are compared too, though a braking pendulum
/// would swing: their D is at most 0.03 deg (kf_accel), and they meet 2 s on every twin.
/// Figures: `cargo test --release -p pendtilt --test plausibility -- --nocapture twin`.
#[test]
fn no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap() {
    let (k0, k1) = (5000, 15000);
    let mut scenario = Scenario::named("scooter").unwrap();
    scenario.duration = 30.0;
    let rows = simulate(&scenario, 3).unwrap();
    let rig = scenario.rig().unwrap();
    scenario.vibration = Default::default();
    let smooth = simulate(&scenario, 3).unwrap();
    let base = cells(&rows);
    let mut braking = base.clone();
    let (a, b) = (k1 - 2000, k1);
    for (k, row) in braking.iter_mut().enumerate().take(b).skip(a) {
        let s = ((k - a) as f64 / (b - a) as f64 * std::f64::consts::PI).sin();
        let brake = s * s;
        let th = rows[k].truth.theta;
        // A horizontal deceleration, in the body axes of MODEL.md section 1 (x along
        // the tilted horizontal, y along the tilted vertical).
        row[3] = format!("{}", rows[k].ax + brake * th.cos());
        row[4] = format!("{}", rows[k].ay - brake * th.sin());
    }
    let mut smooth_road = base.clone();
    for (k, row) in smooth_road.iter_mut().enumerate().take(k1).skip(k1 - 5000) {
        row[3] = format!("{}", smooth[k].ax);
        row[4] = format!("{}", smooth[k].ay);
    }
    let g = gapped(&base, k0, k1);
    for t in [&braking, &smooth_road] {
        assert_eq!(g, gapped(t, k0, k1), "the faulty logs differ");
    }
    let clean = run(&text(&base), &rig);
    let twins = [run(&text(&braking), &rig), run(&text(&smooth_road), &rig)];
    let bad = run(&g, &rig);
    let (at, t_end) = (k1 + 2000, k1 as f64 * 1e-3);
    let rec = recovery(&clean, &bad, t_end);
    for (j, name) in clean.names.iter().enumerate() {
        let mut apart = Vec::new();
        for (tw, what) in twins.iter().zip(["brakes", "rides a smooth road"]) {
            // From 2 s after the gap on, the largest difference.
            let d = (at..rows.len())
                .map(|k| (clean.est[k][j].theta - tw.est[k][j].theta).abs())
                .fold(0.0, f64::max)
                .to_degrees();
            let b_twin = recovery(tw, &bad, t_end)[j].1;
            println!(
                "  {name:<14} the ride and its twin that {what}: fault-free runs {d:.3} deg \
                 apart from 2 s after the gap on; the restart back after {:.2} s on the ride, \
                 {b_twin:.2} s on the twin",
                rec[j].1
            );
            apart.push((d, b_twin));
        }
        let (d, b_twin) = apart
            .iter()
            .copied()
            .fold((0.0, 0.0), |a, x| if x.0 > a.0 { x } else { a });
        if ["mahony", "complementary", "madgwick"].contains(name) {
            assert!(d > 2.0 * TOLERANCE_DEG, "{name}: {d} deg");
            // The restart meets 2 s on at most one of the two.
            assert!(
                rec[j].1 > 2.0 || b_twin > 2.0,
                "{name}: {} s, {b_twin} s",
                rec[j].1
            );
        } else {
            // The estimators that meet 2 s: on every twin too.
            assert!(
                d < 2.0 * TOLERANCE_DEG && b_twin <= 2.0,
                "{name}: {d} deg, {b_twin} s"
            );
        }
    }
}
