//! A small simulated log end to end: every estimator, other column names and degrees,
//! output options, a log missing the gyro, a rig file, the scoring window, bad input.
use crate::common::bin;
use crate::common::cli_estimate::write_log;
use std::path::{Path, PathBuf};

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn out_path(dir: &Path, name: &str) -> PathBuf {
    dir.join(name)
}

#[test]
fn runs_every_estimator_one_row_per_input_row_and_prints_the_error_table() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let out = out_path(d.path(), "est.csv");
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (header, rows) = read_csv(&out);
    assert_eq!(rows.len(), 3000);
    for name in [
        "t", "accel", "pendulum", "alg1", "alg2", "alg3", "kf_accel", "kf_alg2", "kf_fused",
        "theta",
    ] {
        assert!(
            header.iter().any(|h| h == name),
            "missing column {name}: {header:?}"
        );
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("RMS [deg]") && stdout.contains("alg2"),
        "{stdout}"
    );
    // The raw pendulum beats the raw accelerometer under the scooter's vibration.
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let th = col("theta");
    let rms = |c: usize| {
        (rows
            .iter()
            .skip(500)
            .map(|r| (r[c] - r[th]).powi(2))
            .sum::<f64>()
            / (rows.len() - 500) as f64)
            .sqrt()
    };
    assert!(rms(col("pendulum")) < rms(col("accel")));
    // No --params: the default rig is said to be used.
    assert!(String::from_utf8_lossy(&o.stderr).contains("default rig"));
}

#[test]
fn mapped_names_and_degrees_give_the_same_estimates() {
    let d = tmp();
    let a = out_path(d.path(), "a.csv");
    let b = out_path(d.path(), "b.csv");
    write_log(&a, ["t", "phi", "gyro", "ax", "ay", "theta"], false, false);
    write_log(
        &b,
        ["time", "enc", "gz", "accx", "accy", "pot"],
        true,
        false,
    );
    let (oa, ob) = (out_path(d.path(), "oa.csv"), out_path(d.path(), "ob.csv"));
    let s = bin()
        .args([
            "estimate",
            a.to_str().unwrap(),
            "-o",
            oa.to_str().unwrap(),
            "-q",
        ])
        .status()
        .unwrap();
    assert!(s.success());
    let o = bin()
        .args([
            "estimate",
            b.to_str().unwrap(),
            "-o",
            ob.to_str().unwrap(),
            "--map",
            "t=time,phi=enc,gyro=gz,ax=accx,ay=accy,theta=pot",
            "--deg",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("phi <- enc (deg)"),
        "mapping is reported: {err}"
    );
    let (ha, ra) = read_csv(&oa);
    let (hb, rb) = read_csv(&ob);
    assert_eq!(ha, hb);
    assert_eq!(ra.len(), rb.len());
    let mut worst: f64 = 0.0;
    for (x, y) in ra.iter().zip(&rb) {
        for (u, v) in x.iter().zip(y) {
            worst = worst.max((u - v).abs());
        }
    }
    // Degrees written with 17 digits and converted back: rounding only.
    assert!(worst < 1e-9, "worst {worst}");
}

#[test]
fn output_in_degrees_and_flag_columns() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let (r, g) = (out_path(d.path(), "r.csv"), out_path(d.path(), "g.csv"));
    for (o, extra) in [(&r, vec![]), (&g, vec!["--out-deg", "--flags"])] {
        let mut args = vec![
            "estimate",
            log.to_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
            "-q",
            "--only",
            "pendulum,alg1",
        ];
        args.extend(extra);
        assert!(bin().args(&args).status().unwrap().success());
    }
    let text = std::fs::read_to_string(&g).unwrap();
    let header = text.lines().next().unwrap();
    assert_eq!(header, "t,pendulum,alg1,theta,pendulum_flags,alg1_flags");
    // The first sample starts the differentiator: flagged.
    assert!(text.lines().nth(1).unwrap().ends_with(",initialising"));
    let (_, rr) = read_csv(&r);
    let row = text.lines().nth(100).unwrap();
    let deg: f64 = row.split(',').nth(2).unwrap().parse().unwrap();
    assert!((deg - rr[99][2].to_degrees()).abs() < 1e-9);
}

#[test]
fn estimators_without_their_inputs_are_skipped_with_a_notice() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(&log, ["t", "phi", "gyro", "ax", "ay", "theta"], false, true);
    let out = out_path(d.path(), "est.csv");
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("skipped alg2: the log has no gyro"), "{err}");
    let (header, rows) = read_csv(&out);
    assert!(header.iter().any(|h| h == "alg1") && !header.iter().any(|h| h == "alg2"));
    assert_eq!(rows.len(), 3000);
}

#[test]
fn bad_input_is_a_clear_error_never_a_panic() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    std::fs::write(&log, "t,phi\n0,0.1\n0.001,abc\n").unwrap();
    let out = out_path(d.path(), "est.csv");
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("log.csv:3") && err.contains("phi") && err.contains("abc"),
        "{err}"
    );

    let rig = out_path(d.path(), "rig.toml");
    std::fs::write(&rig, "[pendulum]\nmass = -1.0\n").unwrap();
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "--params",
            rig.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("rig.toml") && err.contains("pendulum.mass"),
        "{err}"
    );

    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--only",
            "alg9",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown estimator `alg9`"));
}

#[test]
fn a_rig_file_changes_the_estimates() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let rig = out_path(d.path(), "rig.toml");
    std::fs::write(&rig, "[differentiator]\ncutoff_hz = 15.0\n").unwrap();
    let (a, b) = (out_path(d.path(), "a.csv"), out_path(d.path(), "b.csv"));
    assert!(bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            a.to_str().unwrap(),
            "-q",
            "--only",
            "alg1"
        ])
        .status()
        .unwrap()
        .success());
    assert!(bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            b.to_str().unwrap(),
            "-q",
            "--only",
            "alg1",
            "--params",
            rig.to_str().unwrap()
        ])
        .status()
        .unwrap()
        .success());
    let (_, ra) = read_csv(&a);
    let (_, rb) = read_csv(&b);
    let diff: f64 = ra
        .iter()
        .zip(&rb)
        .map(|(x, y)| (x[1] - y[1]).abs())
        .fold(0.0, f64::max);
    assert!(
        diff > 1e-3,
        "a 15 Hz differentiator must change alg1: {diff}"
    );
}

/// The planar error table leaves the start-up out: from 5 s after the first row by
/// default (a 3 s log has no row scored, and says how to score it), from `--score-from`
/// when given, and its RMS is the file's RMS over those rows.
#[test]
fn the_error_table_scores_from_score_from() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let out = out_path(d.path(), "est.csv");
    let run = |extra: &[&str]| {
        let o = bin()
            .args([
                "estimate",
                log.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    // A 3 s log is scored whole by default (it is shorter than 10 s), and says so.
    let default = run(&[]);
    assert!(
        default.contains("t >= t0 + 0 s (3000 rows scored: the whole log, which lasts 3.0 s"),
        "{default}"
    );
    let beyond = run(&["--score-from", "5"]);
    assert!(
        beyond.contains("t >= t0 + 5 s (0 rows scored)")
            && beyond.contains("score earlier with --score-from SECONDS"),
        "{beyond}"
    );
    let table = run(&["--score-from", "1"]);
    assert!(
        table.contains("t >= t0 + 1 s (2000 rows scored)"),
        "{table}"
    );
    // ekf's RMS in the table is the file's over t >= 1 s (t0 = 0).
    let (header, rows) = read_csv(&out);
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let (t, e, th) = (col("t"), col("ekf"), col("theta"));
    let late: Vec<&Vec<f64>> = rows.iter().filter(|r| r[t] >= 1.0).collect();
    let rms = (late.iter().map(|r| (r[e] - r[th]).powi(2)).sum::<f64>() / late.len() as f64)
        .sqrt()
        .to_degrees();
    let line = table.lines().find(|l| l.starts_with("ekf ")).unwrap();
    let printed: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!((printed - rms).abs() < 1e-4, "{line} vs {rms}");
    let all = run(&["--score-from", "0"]);
    assert!(all.contains("(3000 rows scored)"), "{all}");
}
