//! `pendtilt report` as a command on a small simulated log, and its errors.
use std::path::{Path, PathBuf};

use pendtilt::report::html::referenced_paths;
mod common;
use common::bin;
use pendtilt::sim::planar::{rig_toml, simulate, Scenario};

/// A 4 s scooter log with (or without) the theta column, and its rig file.
fn write_log(dir: &Path, with_theta: bool) -> (PathBuf, PathBuf) {
    let mut sc = Scenario::named("scooter").unwrap();
    sc.duration = 4.0;
    let rows = simulate(&sc, 9).unwrap();
    let mut csv = String::from(if with_theta {
        "t,phi,gyro,ax,ay,theta\n"
    } else {
        "t,phi,gyro,ax,ay\n"
    });
    for r in &rows {
        csv.push_str(&format!("{},{},{},{},{}", r.t, r.phi, r.gyro, r.ax, r.ay));
        if with_theta {
            csv.push_str(&format!(",{}", r.theta));
        }
        csv.push('\n');
    }
    let log = dir.join(if with_theta {
        "ride.csv"
    } else {
        "no_theta.csv"
    });
    std::fs::write(&log, csv).unwrap();
    let rig = dir.join("rig.toml");
    std::fs::write(&rig, rig_toml(&sc.physical()).unwrap()).unwrap();
    (log, rig)
}

#[test]
fn report_writes_pages_figures_and_prints_the_table() {
    let dir = tempfile::tempdir().unwrap();
    let (log, rig) = write_log(dir.path(), true);
    let out = dir.path().join("rep");
    let o = bin()
        .args([
            "report",
            log.to_str().unwrap(),
            "--params",
            rig.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        stdout.contains("Metrics (FIR 20 Hz)") && stdout.contains("| alg2 "),
        "{stdout}"
    );
    for f in [
        "index.html",
        "report.md",
        "report.json",
        "est_alg1.png",
        "est_alg1.svg",
        "kalman_accel_vs_pendulum.png",
        "fig3_kalman_variance.png",
    ] {
        let p = out.join(f);
        assert!(
            std::fs::metadata(&p)
                .map(|m| m.len() > 100)
                .unwrap_or(false),
            "{f}"
        );
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let refs = referenced_paths(&html);
    assert!(refs.len() > 10);
    for r in refs {
        assert!(out.join(&r).is_file(), "missing {r}");
    }
    // the printed numbers are the JSON's
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let views = json["views"].as_array().unwrap();
    assert_eq!(views.len(), 2);
    let names: Vec<&str> = views[1]["metrics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    for n in [
        "accel", "pendulum", "alg1", "alg2", "alg3", "kf_accel", "kf_alg2", "alg2_dc",
    ] {
        assert!(names.contains(&n), "{n} missing from {names:?}");
    }
    assert!(json["claims"].as_array().unwrap().len() >= 5);
}

#[test]
fn a_log_without_theta_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (log, rig) = write_log(dir.path(), false);
    let o = bin()
        .args([
            "report",
            log.to_str().unwrap(),
            "--params",
            rig.to_str().unwrap(),
            "--out",
            dir.path().join("x").to_str().unwrap(),
            "-q",
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("no_theta.csv") && err.contains("theta"),
        "{err}"
    );
    assert!(!dir.path().join("x/index.html").exists());
}

#[test]
fn a_bad_rig_file_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (log, _) = write_log(dir.path(), true);
    let rig = dir.path().join("broken_rig.toml");
    std::fs::write(&rig, "[pendulum]\nmass = -1.0\n").unwrap();
    let o = bin()
        .args([
            "report",
            log.to_str().unwrap(),
            "--params",
            rig.to_str().unwrap(),
            "--out",
            dir.path().join("x").to_str().unwrap(),
            "-q",
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("broken_rig.toml"), "{err}");
    let missing = dir.path().join("absent.csv");
    let o = bin()
        .args([
            "report",
            missing.to_str().unwrap(),
            "--out",
            dir.path().join("y").to_str().unwrap(),
            "-q",
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("absent.csv"));
}

/// The RMS [deg] and sample count of `name` in a report.json's unfiltered view.
fn report_rms(dir: &Path, name: &str) -> (f64, u64) {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let m = json["views"][0]["metrics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == name)
        .unwrap_or_else(|| panic!("no {name} in {json}"));
    (
        m["rms_deg"].as_f64().unwrap(),
        m["samples"].as_u64().unwrap(),
    )
}

#[test]
fn report_scores_the_rows_estimate_scores() {
    let dir = tempfile::tempdir().unwrap();
    let mut sc = Scenario::named("scooter").unwrap();
    sc.duration = 12.0;
    let log = dir.path().join("ride.csv");
    let rows = simulate(&sc, 4).unwrap();
    let mut csv = String::from("t,phi,gyro,ax,ay,theta\n");
    for r in &rows {
        csv.push_str(&format!(
            "{},{},{},{},{},{}\n",
            r.t, r.phi, r.gyro, r.ax, r.ay, r.theta
        ));
    }
    std::fs::write(&log, csv).unwrap();
    let report = |out: &str, extra: &[&str]| {
        let o = bin()
            .args(["report", log.to_str().unwrap(), "-q", "-o"])
            .arg(dir.path().join(out))
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        dir.path().join(out)
    };
    // By default both leave out the first 5 s and agree on the figure.
    let (rms, n) = report_rms(&report("default", &[]), "ekf");
    assert_eq!(n, 7000);
    let o = bin()
        .args(["estimate", log.to_str().unwrap(), "--only", "ekf", "-o"])
        .arg(dir.path().join("e.csv"))
        .output()
        .unwrap();
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("t >= t0 + 5 s (7000 rows scored)"),
        "{table}"
    );
    let line = table.lines().find(|l| l.starts_with("ekf ")).unwrap();
    let est: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!((est - rms).abs() < 6e-5, "estimate {est} vs report {rms}");
    let page = std::fs::read_to_string(dir.path().join("default/index.html")).unwrap();
    assert!(page.contains("scored from 5 s after the first row"), "page");
    // The start-up costs the ekf: scored from 0 it is worse, over every row.
    let (whole, n) = report_rms(&report("whole", &["--score-from", "0"]), "ekf");
    assert_eq!(n, 12000);
    assert!(whole > rms, "{whole} vs {rms}");
    // A start beyond the log is refused, naming it.
    let o = bin()
        .args([
            "report",
            log.to_str().unwrap(),
            "-q",
            "--score-from",
            "30",
            "-o",
        ])
        .arg(dir.path().join("none"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success()
            && err.contains("ride.csv")
            && err.contains("the last row is at t0 + 11.999 s"),
        "{err}"
    );
    assert!(!dir.path().join("none").exists());
}
