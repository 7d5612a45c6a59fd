//! Impossible readings (beyond the rig's full scale, or absurd): missing for every
//! estimator, flagged `implausible` on the estimators that read them, told once with
//! their line; the truth's absurd cells left unscored.
use crate::common::plausibility::{
    assert_nothing_poisoned, cells, gyro, madgwick_resolution_deg, phi, print, recovery, retimed,
    ride, run, text, Run, TOLERANCE_DEG,
};
use pendtilt::config::RigConfig;
use pendtilt::core::Flags;
use pendtilt::io::{LogWarning, WarningKind};
use pendtilt::sensors::Inputs;

use std::process::Command;

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
        told_once(&bad, value, says);
        flagged_where_read(&bad, k, sensor, value);
        let rec = recovery(&clean, &bad, k as f64 * 1e-3);
        print(&format!("one cell {value} in column {col}"), &rec);
        assert_nothing_poisoned(
            &format!("one cell {value}"),
            &clean,
            &bad,
            &rows,
            k as f64 * 1e-3 + 2.0,
        );
        back_within_2_s(value, &rec);
    }
}

/// The impossible cell `value` is told once, on its line, with what it `says`, and not
/// taken for degrees.
fn told_once(bad: &Run, value: &str, says: &str) {
    let w = implausible_warnings(bad);
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
}

/// Flagged on exactly the estimators that read `sensor`, on row `k` only.
fn flagged_where_read(bad: &Run, k: usize, sensor: Inputs, value: &str) {
    let mut settings_needs = Vec::new();
    for e in pendtilt::bank::planar::REGISTRY {
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
}

/// Every estimator back within 0.05 deg of the clean run 2 s after the cell, Madgwick
/// within its resolution.
fn back_within_2_s(value: &str, rec: &[(&str, f64, f64)]) {
    for (n, back, worst) in rec {
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

fn accel() -> Inputs {
    Inputs::ACCEL
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
        let mut s = pendtilt::sim::planar::Scenario::named("scooter").unwrap();
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
