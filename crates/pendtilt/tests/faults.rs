//! Reliability.
//!
//! Item 1, end to end: every bad-file case of docs/bad-input.md through `pendtilt estimate`:
//! the exit code is never 101 (a panic), an accepted file gives exactly one output row per
//! input data row, a rejected one names the file and the line.
//!
//! Item 2, in process: sensor faults injected into a simulated scooter ride, run through
//! every estimator of the bank. For each fault: one output per input, no NaN unless
//! flagged `sample_missing`, the right flag on the faulty samples, and recovery: the
//! largest difference from the fault-free run, from a stated time after the fault on, is
//! within a stated bound. The figures are in docs/reliability.md.
use std::path::Path;
use std::process::{Command, Output};

use pendtilt::bank::planar::{Bank, BankSettings, Inputs};
use pendtilt::core::{Estimate, Flags, Sample};
use pendtilt::sensors::Sensor;
use pendtilt::sim::planar::{simulate, Scenario};

// ---------------------------------------------------------------------------------------
// Item 1: bad files through `pendtilt estimate`.

fn estimate(dir: &Path, name: &str, text: &[u8], extra: &[&str]) -> (Output, Option<String>) {
    let log = dir.join(name);
    std::fs::write(&log, text).unwrap();
    let out = dir.join(format!("{name}.out.csv"));
    let _ = std::fs::remove_file(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .arg("estimate")
        .arg(&log)
        .arg("-o")
        .arg(&out)
        .arg("--flags")
        .args(extra)
        .output()
        .unwrap();
    (o, std::fs::read_to_string(&out).ok())
}

/// Data rows in a log text: lines after the header that are neither blank nor comments.
fn data_rows(text: &str) -> usize {
    let text = text.trim_start_matches('\u{feff}');
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .count()
        .saturating_sub(1)
}

const HEADER: &str = "t,phi,gyro,ax,ay,theta\n";

fn row(t: f64, phi: f64) -> String {
    format!(
        "{t},{phi},0.0,{},{},{phi}\n",
        9.80665 * phi.sin(),
        9.80665 * phi.cos()
    )
}

fn rows(n: usize) -> String {
    let mut s = String::from(HEADER);
    for k in 0..n {
        s.push_str(&row(k as f64 * 1e-3, 0.05));
    }
    s
}

#[test]
fn bad_files_end_to_end_never_panic_never_drop_a_row() {
    let dir = tempfile::tempdir().unwrap();
    let good = rows(40);
    for (name, text) in &accepted_files() {
        check_accepted(dir.path(), name, text);
    }
    for (name, bytes, line) in &rejected_files() {
        check_rejected(dir.path(), name, bytes, *line);
    }

    // An impossible rig file: the error names the file and the key.
    let rig = dir.path().join("rig.toml");
    std::fs::write(&rig, "[pendulum]\nmass = -0.05\n").unwrap();
    let (o, _) = estimate(
        dir.path(),
        "good.csv",
        good.as_bytes(),
        &["--params", rig.to_str().unwrap()],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(101), "{stderr}");
    assert!(!o.status.success());
    assert!(
        stderr.contains("rig.toml") && stderr.contains("pendulum.mass"),
        "{stderr}"
    );
}

/// Files the reader accepts: (name, text). Every data row must come out.
fn accepted_files() -> Vec<(&'static str, String)> {
    let mut accepted: Vec<(&str, String)> = Vec::new();
    let good = rows(40);
    accepted.push(("nan_inf.csv", {
        let mut s = rows(10);
        s.push_str("0.010,nan,0,0.49,9.79,0.05\n0.011,0.05,inf,0.49,9.79,0.05\n");
        s.push_str("0.012,0.05,0,-Infinity,9.79,0.05\n0.013,,0,0.49,9.79,0.05\n");
        s.push_str(&row(0.014, 0.05));
        s
    }));
    accepted.push(("time_back.csv", {
        let mut s = rows(10);
        s.push_str(&row(0.009, 0.05)); // repeated
        s.push_str(&row(0.005, 0.05)); // backwards
        s.push_str(&row(0.010, 0.05));
        s.push_str("nan,0.05,0,0.49,9.79,0.05\n"); // time missing
        s.push_str(&row(0.011, 0.05));
        s
    }));
    accepted.push(("gap.csv", {
        let mut s = rows(20);
        s.push_str(&row(0.5, 0.05));
        s.push_str(&row(0.501, 0.05));
        s
    }));
    accepted.push(("jitter.csv", {
        let mut s = String::from(HEADER);
        let mut t = 0.0;
        for k in 0..60 {
            t += if k % 3 == 0 { 1.9e-3 } else { 0.4e-3 };
            s.push_str(&row(t, 0.05));
        }
        s
    }));
    accepted.push(("crlf.csv", good.replace('\n', "\r\n")));
    accepted.push(("bom.csv", format!("\u{feff}{good}")));
    accepted.push((
        "comments.csv",
        format!(
            "# rig 7\n\n{HEADER}# start\n{}\n# end\n",
            &good[HEADER.len()..]
        ),
    ));
    accepted.push(("truncated.csv", format!("{good}0.040,0.05,0.0,0.4")));
    accepted.push(("degrees.csv", {
        let mut s = String::from(HEADER);
        for k in 0..30 {
            s.push_str(&format!("{},5.0,0.0,0.85,9.77,5.0\n", k as f64 * 1e-3));
        }
        s
    }));
    accepted.push(("missing_columns.csv", {
        let mut s = String::from("t,phi\n");
        for k in 0..25 {
            s.push_str(&format!("{},0.01\n", k as f64 * 1e-3));
        }
        s
    }));
    accepted.push(("duplicate_unused.csv", {
        let mut s = String::from("t,phi,temp,temp\n");
        for k in 0..25 {
            s.push_str(&format!("{},0.01,20,21\n", k as f64 * 1e-3));
        }
        s
    }));
    accepted
}

/// Estimates accepted file `name`: no panic, one output row per data row, the degrees
/// hint and the missing sample flagged where the file asks for them.
fn check_accepted(dir: &Path, name: &str, text: &str) {
    let (o, out) = estimate(dir, name, text.as_bytes(), &[]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(101), "{name}: panicked: {stderr}");
    assert!(o.status.success(), "{name}: {stderr}");
    let out = out.unwrap();
    assert_eq!(
        out.lines().count() - 1,
        data_rows(text),
        "{name}: output rows != input data rows"
    );
    if name == "degrees.csv" {
        assert!(
            stderr.contains("phi") && stderr.contains("--deg"),
            "{stderr}"
        );
    }
    if name == "nan_inf.csv" {
        // The NaN phi row is flagged on every phi estimator.
        let header: Vec<&str> = out.lines().next().unwrap().split(',').collect();
        let line: Vec<&str> = out.lines().nth(11).unwrap().split(',').collect();
        let col = header.iter().position(|h| *h == "alg1_flags").unwrap();
        assert!(line[col].contains("sample_missing"), "{out}");
    }
}

/// Files the reader refuses: (name, bytes, line expected in the message).
fn rejected_files() -> Vec<(&'static str, Vec<u8>, Option<&'static str>)> {
    vec![
        ("empty.csv", Vec::new(), None),
        ("header_only.csv", HEADER.as_bytes().to_vec(), Some(":1:")),
        ("no_time.csv", b"time,phi\n0,0.1\n".to_vec(), Some(":1:")),
        (
            "dup.csv",
            b"t,phi,gyro,phi\n0,0.1,0,0.1\n".to_vec(),
            Some(":1:"),
        ),
        (
            "text_cell.csv",
            format!("{HEADER}0,0.1,0,0,9.8,0\n0.001,abc,0,0,9.8,0\n").into_bytes(),
            Some(":3:"),
        ),
        (
            "too_many.csv",
            format!("{HEADER}0,0.1,0,0,9.8,0,7,8\n").into_bytes(),
            Some(":2:"),
        ),
        (
            "not_utf8.csv",
            [HEADER.as_bytes(), b"0,\xff\xfe,0,0,9.8,0\n"].concat(),
            Some(":2:"),
        ),
    ]
}

/// Estimates refused file `name`: no panic, an error naming the file and, if given, the
/// line.
fn check_rejected(dir: &Path, name: &str, bytes: &[u8], line: Option<&str>) {
    let (o, _) = estimate(dir, name, bytes, &[]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(101), "{name}: panicked: {stderr}");
    assert!(!o.status.success(), "{name} accepted");
    assert!(
        stderr.contains(name),
        "{name}: the error does not name the file: {stderr}"
    );
    if let Some(line) = line {
        assert!(
            stderr.contains(&format!("{name}{line}")),
            "{name}: {stderr}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Item 2: sensor faults in a simulated scooter ride.

const RATE: f64 = 1000.0;
const SECS: f64 = 12.0;

fn ride() -> (Vec<Sample<f64>>, Vec<f64>) {
    let mut s = Scenario::named("scooter").unwrap();
    s.duration = SECS;
    let rows = simulate(&s, 6).unwrap();
    (
        rows.iter().map(|r| r.sample()).collect(),
        rows.iter().map(|r| r.truth.theta).collect(),
    )
}

/// The bank for the scooter rig, told the gyro's full scale if given.
fn bank(gyro_full_scale: Option<f64>) -> Bank {
    let p = Scenario::named("scooter").unwrap().physical().normalised();
    let mut s = BankSettings::from_params(p);
    s.rig.gyro.full_scale = gyro_full_scale;
    Bank::new(&s, Inputs::ALL, None).unwrap()
}

/// Runs the whole bank; `[row][estimator]`.
fn run(
    samples: &[Sample<f64>],
    gyro_full_scale: Option<f64>,
) -> (Vec<&'static str>, Vec<Vec<Estimate<f64>>>) {
    let mut b = bank(gyro_full_scale);
    let mut out = Vec::new();
    let mut all = Vec::with_capacity(samples.len());
    for s in samples {
        b.update(s, &mut out);
        assert_eq!(
            out.len(),
            b.names().len(),
            "one output per estimator per input"
        );
        all.push(out.clone());
    }
    (b.names().to_vec(), all)
}

/// Which sensors each estimator reads, directly or through its Kalman sources.
fn needs(name: &str) -> Inputs {
    let p = name.contains("alg") || name == "pendulum" || name == "kf_fused";
    let g = name.starts_with("kf_") || name.starts_with("alg2") || name == "alg3";
    let a = name == "accel" || name == "kf_accel" || name == "kf_fused";
    [(p, Sensor::Encoder), (g, Sensor::Gyro), (a, Sensor::Accel)]
        .into_iter()
        .filter(|(on, _)| *on)
        .fold(Inputs::NONE, |set, (_, s)| set.with(s))
}

/// A fault: which rows it touches and how.
struct Fault {
    name: &'static str,
    /// First and one-past-last faulty row.
    rows: (usize, usize),
    apply: fn(&mut Sample<f64>),
    /// Sensors affected.
    sensors: Inputs,
    /// The flags the affected estimators must show on the faulty rows.
    expect: fn(&str) -> Flags,
    /// Recovery: from `settle` seconds after the fault on, every affected estimator is
    /// within `bound_deg` of its fault-free output.
    settle: f64,
    bound_deg: f64,
    /// The gyro full scale the bank is told ([gyro] full_scale), if any.
    gyro_full_scale: Option<f64>,
}

fn missing_flag(name: &str) -> Flags {
    // A Kalman filter whose measurement is missing skips it; one whose gyro is missing
    // flags the sample missing; everything else flags it missing.
    if name.starts_with("kf_") {
        Flags::SAMPLE_MISSING | Flags::MEASUREMENT_SKIPPED
    } else {
        Flags::SAMPLE_MISSING
    }
}

fn check(fault: &Fault) -> Vec<(String, f64, f64)> {
    let (clean, truth) = ride();
    let mut faulty = clean.clone();
    for s in &mut faulty[fault.rows.0..fault.rows.1] {
        (fault.apply)(s);
    }
    let (names, ref_out) = run(&clean, fault.gyro_full_scale);
    let (_, out) = run(&faulty, fault.gyro_full_scale);
    assert_eq!(out.len(), faulty.len(), "one output row per input row");
    let mut report = Vec::new();
    for (j, name) in names.iter().enumerate() {
        let need = needs(name);
        let affected = need.intersects(fault.sensors);
        for (k, row) in out.iter().enumerate() {
            let e = row[j];
            assert!(
                e.theta.is_finite() || e.flags.contains(Flags::SAMPLE_MISSING),
                "{}: {name} row {k}: NaN without sample_missing ({:?})",
                fault.name,
                e.flags
            );
            // After the first second every estimator has an estimate, fault or not.
            if k >= 1000 {
                assert!(
                    e.theta.is_finite(),
                    "{}: {name} row {k}: no estimate",
                    fault.name
                );
            }
        }
        if affected {
            let want = (fault.expect)(name);
            if !want.is_empty() {
                let hits = (fault.rows.0..fault.rows.1)
                    .filter(|&k| out[k][j].flags.intersects(want))
                    .count();
                assert!(
                    hits > 0,
                    "{}: {name} never flagged {want:?} on the faulty rows",
                    fault.name
                );
            }
        }
        let from = fault.rows.1 + (fault.settle * RATE) as usize;
        let diff = (from..out.len())
            .map(|k| (out[k][j].theta - ref_out[k][j].theta).abs())
            .fold(0.0, f64::max)
            .to_degrees();
        // The recovery bound holds for the paper's estimators and their Kalman filters;
        // the bank's other entries (EKF/UKF, peers) are measured and printed only.
        let paper = name == &"accel"
            || name == &"pendulum"
            || name.starts_with("alg")
            || name.starts_with("kf_");
        assert!(
            !paper || diff <= fault.bound_deg,
            "{}: {name} still {diff:.4} deg off the fault-free run {} s after the fault",
            fault.name,
            fault.settle
        );
        // The error against the truth after recovery, for the record.
        let from_err = from.min(out.len() - 1000);
        let err = (from_err..out.len())
            .map(|k| (out[k][j].theta - truth[k]).powi(2))
            .sum::<f64>()
            / (out.len() - from_err) as f64;
        report.push((name.to_string(), diff, err.sqrt().to_degrees()));
    }
    println!(
        "{}: (estimator, max |faulty - clean| deg after settle, RMS err deg)",
        fault.name
    );
    for r in &report {
        println!("  {:<12} {:>10.5} {:>8.4}", r.0, r.1, r.2);
    }
    report
}

const PHI_ONLY: Inputs = Inputs::PHI;
const GYRO_ONLY: Inputs = Inputs::GYRO;
const ACCEL_ONLY: Inputs = Inputs::ACCEL;

#[test]
fn single_missing_phi_sample() {
    check(&Fault {
        name: "phi NaN, 1 sample",
        rows: (4000, 4001),
        apply: |s| s.phi = f64::NAN,
        sensors: PHI_ONLY,
        expect: missing_flag,
        settle: 1.0,
        bound_deg: 0.01,
        gyro_full_scale: None,
    });
}

#[test]
fn burst_of_missing_phi() {
    check(&Fault {
        name: "phi NaN, 50 ms burst",
        rows: (4000, 4050),
        apply: |s| s.phi = f64::NAN,
        sensors: PHI_ONLY,
        expect: missing_flag,
        settle: 2.0,
        bound_deg: 0.01,
        gyro_full_scale: None,
    });
}

#[test]
fn missing_gyro_single_and_burst() {
    for (rows, settle, bound) in [((4000, 4001), 1.0, 0.01), ((4000, 4100), 3.0, 0.01)] {
        check(&Fault {
            name: "gyro NaN",
            rows,
            apply: |s| s.gyro = f64::NAN,
            sensors: GYRO_ONLY,
            expect: |n| {
                if n.starts_with("alg") || n.starts_with("kf_") {
                    Flags::SAMPLE_MISSING
                } else {
                    Flags::empty()
                }
            },
            settle,
            bound_deg: bound,
            gyro_full_scale: None,
        });
    }
}

#[test]
fn missing_accelerometer_single_and_burst() {
    for rows in [(4000, 4001), (4000, 4200)] {
        check(&Fault {
            name: "accel NaN",
            rows,
            apply: |s| {
                s.ax = f64::NAN;
                s.ay = f64::NAN;
            },
            sensors: ACCEL_ONLY,
            expect: missing_flag,
            settle: 3.0,
            bound_deg: 0.01,
            gyro_full_scale: None,
        });
    }
}

#[test]
fn everything_missing_burst() {
    check(&Fault {
        name: "all sensors NaN, 20 ms",
        rows: (4000, 4020),
        apply: |s| *s = Sample::after(s.dt),
        sensors: Inputs::ALL,
        expect: missing_flag,
        settle: 3.0,
        bound_deg: 0.01,
        gyro_full_scale: None,
    });
}

#[test]
fn encoder_reporting_zero_to_two_pi() {
    // An encoder that reports [0, 2 pi): every crossing of zero jumps by a full turn.
    let r = check(&Fault {
        name: "encoder in [0, 2pi)",
        rows: (0, (SECS * RATE) as usize),
        apply: |s| s.phi = s.phi.rem_euclid(std::f64::consts::TAU),
        sensors: PHI_ONLY,
        expect: |n| {
            if n.starts_with("kf_") {
                Flags::empty()
            } else {
                Flags::ENCODER_WRAPPED
            }
        },
        settle: 0.0,
        bound_deg: 1e-6,
        gyro_full_scale: None,
    });
    assert!(r.iter().all(|(_, d, _)| *d < 1e-6));
}

#[test]
fn encoder_glitch_of_one_turn() {
    // A single reading off by a full turn (a counter glitch) is unwrapped, not a spike.
    check(&Fault {
        name: "encoder +2pi glitch",
        rows: (5000, 5001),
        apply: |s| s.phi += std::f64::consts::TAU,
        sensors: PHI_ONLY,
        expect: |n| {
            if n.starts_with("kf_") {
                Flags::empty()
            } else {
                Flags::ENCODER_WRAPPED
            }
        },
        settle: 0.0,
        bound_deg: 1e-6,
        gyro_full_scale: None,
    });
}

#[test]
fn asin_saturation_from_an_absurd_phi_second_derivative() {
    // The encoder reads 2.5 rad off for 100 ms: phi'' far beyond what the pendulum can do.
    check(&Fault {
        name: "phi +2.5 rad for 100 ms (asin saturates)",
        rows: (4000, 4100),
        apply: |s| s.phi += 2.5,
        sensors: PHI_ONLY,
        expect: |n| {
            if n == "pendulum" {
                Flags::empty()
            } else if n.starts_with("kf_") {
                Flags::MEASUREMENT_SKIPPED
            } else {
                Flags::ASIN_CLAMPED
            }
        },
        settle: 3.0,
        bound_deg: 0.01,
        gyro_full_scale: None,
    });
}

fn reads_gyro(n: &str) -> bool {
    n.starts_with("alg2") || n == "alg3" || n.starts_with("kf_")
}

#[test]
fn gyro_clipped_at_full_scale() {
    // A gyro whose full scale (0.3 rad/s, 17 deg/s) is below the ride's rates. Not told
    // the full scale, nothing can be flagged; told it, every estimator that reads the gyro
    // flags the clipped samples `saturated`.
    const FS: f64 = 0.3;
    let clip: fn(&mut Sample<f64>) = |s| s.gyro = s.gyro.clamp(-FS, FS);
    check(&Fault {
        name: "gyro clipped at 0.3 rad/s for 2 s, full scale unknown",
        rows: (3000, 5000),
        apply: clip,
        sensors: GYRO_ONLY,
        expect: |_| Flags::empty(),
        settle: 3.0,
        bound_deg: 0.01,
        gyro_full_scale: None,
    });
    check(&Fault {
        name: "gyro clipped at 0.3 rad/s for 2 s, full scale told",
        rows: (3000, 5000),
        apply: clip,
        sensors: GYRO_ONLY,
        expect: |n| {
            if reads_gyro(n) {
                Flags::SATURATED
            } else {
                Flags::empty()
            }
        },
        settle: 3.0,
        bound_deg: 0.01,
        gyro_full_scale: Some(FS),
    });
    // Flagged exactly where the gyro reads full scale, and the estimates during the
    // clipping: held rate against the clipped plateau.
    let (clean, truth) = ride();
    let mut faulty = clean.clone();
    for s in &mut faulty[3000..5000] {
        clip(s);
    }
    let (names, told) = run(&faulty, Some(FS));
    let (_, blind) = run(&faulty, None);
    let clipped: Vec<bool> = faulty.iter().map(|s| s.gyro.abs() >= FS).collect();
    let n_clipped = clipped.iter().filter(|c| **c).count();
    assert!(
        n_clipped > 100,
        "the ride must reach full scale ({n_clipped})"
    );
    let rms = |out: &[Vec<Estimate<f64>>], j: usize| {
        let ss: f64 = (3000..5000)
            .map(|k| (out[k][j].theta - truth[k]).powi(2))
            .sum();
        (ss / 2000.0).sqrt().to_degrees()
    };
    for (j, n) in names.iter().enumerate() {
        if !reads_gyro(n) {
            continue;
        }
        for (k, c) in clipped.iter().enumerate() {
            assert_eq!(
                told[k][j].flags.contains(Flags::SATURATED),
                *c,
                "{n} row {k}"
            );
        }
        let (a, b) = (rms(&told, j), rms(&blind, j));
        println!("{n:<12} RMS error while clipped: told {a:.4} deg, not told {b:.4} deg");
        // Measured: within 0.002 deg of each other (docs/reliability.md): the flag costs
        // no accuracy.
        assert!(a <= b + 0.01, "{n}: {a} vs {b}");
    }
}
