//! `pendtilt batch`: many logs across the cores, each log's estimates byte for byte those of
//! `estimate`, a bad log reported and skipped, and a summary table per log.
use std::path::Path;

mod common;
use common::{pendtilt, s, stderr};

fn simulate(dir: &Path, scenario: &str, seed: &str, name: &str) {
    let out = dir.join(name);
    let o = pendtilt(&[
        "simulate",
        "--scenario",
        scenario,
        "--duration",
        "8",
        "--seed",
        seed,
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Three simulated logs (two planar, one 3-D) under `d/logs/a` and `d/logs/b`, and a bad
/// one (a cell that is not a number) beside them.
fn logs_and_a_bad_one(d: &Path) {
    std::fs::create_dir_all(d.join("logs/a")).unwrap();
    std::fs::create_dir_all(d.join("logs/b")).unwrap();
    simulate(d, "scooter", "1", "logs/a/ride.csv");
    simulate(d, "scooter", "2", "logs/b/ride.csv");
    simulate(d, "scooter3d", "1", "logs/b/sc3.csv");
    std::fs::write(
        d.join("logs/b/bad.csv"),
        "t,phi,gyro\n0,0.1,0\n0.001,abc,0\n",
    )
    .unwrap();
}

/// Each good log's estimates in `out` are, byte for byte, what `estimate` writes with the
/// rig (and a 3-D log's scenario) that simulate wrote beside it; the bad log has none.
fn assert_estimates_as_estimate_writes_them(d: &Path, out: &Path) {
    for (log, est) in [
        ("logs/a/ride.csv", "a/ride.est.csv"),
        ("logs/b/ride.csv", "b/ride.est.csv"),
        ("logs/b/sc3.csv", "b/sc3.est.csv"),
    ] {
        let single = d.join("single.csv");
        let own = |suffix: &str| d.join(log.replace(".csv", suffix));
        let path = d.join(log);
        let mut args = vec!["estimate", s(&path), "-q", "-o", s(&single)];
        let (rig, scenario) = (own(".rig.toml"), own(".scenario.toml"));
        args.extend(["--params", s(&rig)]);
        if log.contains("sc3") {
            args.extend(["--scenario", s(&scenario)]);
        }
        let o = pendtilt(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            std::fs::read(out.join(est)).unwrap(),
            std::fs::read(&single).unwrap(),
            "{log}"
        );
    }
    assert!(!out.join("b/bad.est.csv").exists());
}

/// The summary in `out`: one row per log, the bad one failed, the RMS of the table
/// `estimate` prints, and its markdown twin.
fn assert_summary(d: &Path, out: &Path) {
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let header = rows.headers().unwrap().clone();
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let records: Vec<csv::StringRecord> = rows.records().map(|r| r.unwrap()).collect();
    assert_eq!(records.len(), 4);
    let bad = records.iter().find(|r| r[0].ends_with("bad.csv")).unwrap();
    assert_eq!(&bad[col("status")], "failed");
    assert!(bad[col("error")].contains("not a number"));
    let ride = records
        .iter()
        .find(|r| r[0].ends_with("a/ride.csv"))
        .unwrap();
    assert_eq!((&ride[col("status")], &ride[col("rows")]), ("ok", "8000"));
    assert!(ride[col("rig")].ends_with("a/ride.rig.toml"), "{ride:?}");
    assert_eq!(&bad[col("rig")], "default");
    let o = pendtilt(&[
        "estimate",
        s(&d.join("logs/a/ride.csv")),
        "-o",
        s(&d.join("x.csv")),
    ]);
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    let line = table.lines().find(|l| l.starts_with("ekf ")).unwrap();
    let printed: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    let summary: f64 = ride[col("ekf_rms_deg")].parse().unwrap();
    assert!((printed - summary).abs() < 1e-4, "{line} vs {summary}");
    let sc3 = records.iter().find(|r| r[0].ends_with("sc3.csv")).unwrap();
    assert!(sc3[col("ekf3d_rms_deg")].parse::<f64>().unwrap() < 0.5);
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("| ekf RMS [deg] |") && md.contains("Failed (skipped)"),
        "{md}"
    );
}

#[test]
fn every_log_gets_estimates_byte_for_byte_and_a_bad_one_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    logs_and_a_bad_one(d);
    let out = d.join("out");
    let pattern = format!("{}/logs/**/*.csv", d.display());
    let o = pendtilt(&["batch", &pattern, "-j", "2", "-o", s(&out)]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("1 of 4 logs failed"), "{e}");
    assert!(
        e.contains("bad.csv:3: column 2 (`phi`): not a number: `abc`"),
        "{e}"
    );
    assert_estimates_as_estimate_writes_them(d, &out);
    assert_summary(d, &out);

    // A second run leaves the first one's estimates alone (they are under -o), and
    // one job gives the same files as two.
    let out1 = d.join("logs/out1");
    let o = pendtilt(&["batch", &pattern, "-j", "1", "-q", "-o", s(&out1)]);
    assert_eq!(o.status.code(), Some(1));
    let again = pendtilt(&["batch", &pattern, "-q", "-o", s(&out1)]);
    assert_eq!(again.status.code(), Some(1));
    assert_eq!(
        std::fs::read(out1.join("a/ride.est.csv")).unwrap(),
        std::fs::read(out.join("a/ride.est.csv")).unwrap()
    );
    assert!(
        !out1.join("out1").exists(),
        "the outputs were taken for logs"
    );
}

#[test]
fn batch_refuses_what_it_cannot_do() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let e = stderr(&pendtilt(&["batch", "x.csv", "-o", "-"]));
    assert!(e.contains("-o -: batch writes a folder"), "{e}");
    let pattern = format!("{}/*.csv", d.display());
    let e = stderr(&pendtilt(&["batch", &pattern, "-o", s(&d.join("o"))]));
    assert!(e.contains("no file matches the pattern"), "{e}");
    let e = stderr(&pendtilt(&[
        "batch",
        s(&d.join("none.csv")),
        "-o",
        s(&d.join("o")),
    ]));
    assert!(e.contains("none.csv: no such file"), "{e}");
}
