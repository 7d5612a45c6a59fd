//! `pendtilt report` on 3-D logs: the report has every estimator of the
//! 3-D registry, its RMS and max agree with what `estimate` prints on the same log, the
//! figures and pages are written, and bad input stops with the file and place.
use std::path::{Path, PathBuf};

use pendtilt::bank::spatial::REGISTRY3D;
use pendtilt::report::html::referenced_paths;

mod common;
use common::{pendtilt, s, stderr, write};

fn ok(args: &[&str]) -> String {
    let out = pendtilt(args);
    assert!(out.status.success(), "pendtilt {args:?}: {}", stderr(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A 12 s scooter3d log (seed 4) in `dir`: the log and its scenario file.
fn scooter_log(dir: &Path) -> (PathBuf, PathBuf) {
    let log = dir.join("sc.csv");
    ok(&[
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "12",
        "--seed",
        "4",
        "-q",
        "-o",
        s(&log),
    ]);
    (log, dir.join("sc.scenario.toml"))
}

/// `estimate`'s printed table: (name, RMS, max) in degrees.
fn printed_scores(stdout: &str) -> Vec<(String, f64, f64)> {
    stdout
        .lines()
        .skip(2)
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (
                f[0].to_string(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
            )
        })
        .collect()
}

/// The report's table has every 3-D estimator, scored from 5 s, with the RMS and max that
/// `estimate` `printed` on the same log.
fn assert_table_is_estimates(json: &serde_json::Value, printed: &[(String, f64, f64)]) {
    let rows = json["inclination"].as_array().unwrap();
    let names: Vec<&str> = rows.iter().map(|r| r["name"].as_str().unwrap()).collect();
    let registry: Vec<&str> = REGISTRY3D.iter().map(|e| e.name).collect();
    assert_eq!(names, registry);
    assert_eq!(json["scored"], 7000, "12 s at 1 kHz, scored from 5 s");
    assert_eq!(printed.len(), rows.len());
    for ((name, rms, max), r) in printed.iter().zip(rows) {
        assert_eq!(name, r["name"].as_str().unwrap());
        // estimate prints five decimals
        let (jr, jm) = (
            r["rms_deg"].as_f64().unwrap(),
            r["max_deg"].as_f64().unwrap(),
        );
        assert!(
            (rms - jr).abs() <= 6e-6,
            "{name}: RMS {rms} printed, {jr} reported"
        );
        assert!(
            (max - jm).abs() <= 6e-6,
            "{name}: max {max} printed, {jm} reported"
        );
    }
}

/// Three figures in `out`, PNG and SVG, non-empty, one panel per estimator, with their
/// axes labelled.
fn assert_figures(json: &serde_json::Value, out: &Path) {
    let figs = json["figures"].as_array().unwrap();
    assert_eq!(figs.len(), 3);
    for (f, stem) in figs.iter().zip(["roll", "pitch", "inclination"]) {
        assert_eq!(f["png"], format!("{stem}.png"));
        assert_eq!(f["axes"].as_array().unwrap().len(), REGISTRY3D.len());
        for ext in ["png", "svg"] {
            let p = out.join(format!("{stem}.{ext}"));
            let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
            assert!(len > 10_000, "{}: {len} bytes", p.display());
        }
    }
    let svg = std::fs::read_to_string(out.join("pitch.svg")).unwrap();
    assert!(svg.contains("pitch [deg]") && svg.contains("time [s]"));
    let svg = std::fs::read_to_string(out.join("inclination.svg")).unwrap();
    assert!(svg.contains("inclination error [deg]"));
}

/// The page in `out` shows every estimator and references only files that exist; the
/// markdown has the table and the figure; a clean log's page claims no warning.
fn assert_pages(out: &Path) {
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for n in REGISTRY3D.iter().map(|e| e.name) {
        assert!(html.contains(&format!("{n}</td>")), "{n} not in the page");
    }
    for r in referenced_paths(&html) {
        assert!(out.join(&r).is_file(), "{r}");
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("| ekf3d |") && md.contains("![") && md.contains("inclination.png"));
    // A clean log: the page claims no warning.
    assert!(!html.contains("Reading the log gave"));
}

/// `log` with one impossible gyro_x cell (1e6 rad/s on file line 3001), as `dir/bad.csv`.
fn with_a_bad_gyro_cell(log: &Path, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(log).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = header.iter().position(|h| *h == "gyro_x").unwrap();
    let mut cells: Vec<String> = lines[3000].split(',').map(str::to_string).collect();
    cells[col] = "1e6".into();
    lines[3000] = cells.join(",");
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, lines.join("\n") + "\n").unwrap();
    bad
}

#[test]
fn report_agrees_with_estimate_and_writes_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let (log, scen) = scooter_log(dir.path());
    let est = dir.path().join("est.csv");
    let printed = printed_scores(&ok(&[
        "estimate",
        s(&log),
        "--scenario",
        s(&scen),
        "-o",
        s(&est),
    ]));
    let out = dir.path().join("rep");
    let stdout = ok(&[
        "report",
        s(&log),
        "--scenario",
        s(&scen),
        "-o",
        s(&out),
        "-q",
    ]);
    assert!(
        stdout.contains("Inclination error, t >= t0 + 5 s"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_table_is_estimates(&json, &printed);
    assert_figures(&json, &out);
    assert_pages(&out);

    // One impossible gyro cell: the page says so at its top, as standard error does.
    let bad = with_a_bad_gyro_cell(&log, dir.path());
    let out = dir.path().join("bad_report");
    ok(&[
        "report",
        s(&bad),
        "--scenario",
        s(&scen),
        "-o",
        s(&out),
        "-q",
    ]);
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        html.contains("Reading the log gave 1 warning") && html.contains("bad.csv:3001"),
        "{html}"
    );
}

/// A still log where every estimator but the raw pendulum is exact: the report's RMS for
/// `accel3d` (ideal accelerometer at rest) is zero, and `pendulum3d`'s is the hand-computed
/// angle between the encoder's up and the true up.
#[test]
fn a_hand_made_log_scores_as_computed_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let (roll, pitch) = (0.1f64, -0.05f64);
    let g = 9.80665;
    // up in body axes for ZYX roll, pitch (MODEL.md 7.1): f = g (-sin p, sin r cos p, cos r cos p)
    let a = [
        -g * pitch.sin(),
        g * roll.sin() * pitch.cos(),
        g * roll.cos() * pitch.cos(),
    ];
    let mut csv = String::from("t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az,roll,pitch\n");
    for k in 0..2000 {
        // the encoders read 0.01 rad more roll than the truth
        csv.push_str(&format!(
            "{},{},{},0,0,0,{},{},{},{roll},{pitch}\n",
            k as f64 * 1e-3,
            roll + 0.01,
            pitch,
            a[0],
            a[1],
            a[2]
        ));
    }
    let log = write(dir.path(), "still.csv", &csv);
    let out = dir.path().join("rep");
    ok(&["report", s(&log), "--score-from", "1", "-o", s(&out), "-q"]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let row = |n: &str| {
        json["inclination"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == n)
            .unwrap()
            .clone()
    };
    assert_eq!(json["scored"], 1000);
    assert!(row("accel3d")["rms_deg"].as_f64().unwrap() < 1e-9);
    // pendulum3d: roll off by 0.01 rad at pitch -0.05: the up vectors differ by
    // acos(u1 . u2) with u = (-sin p, sin r cos p, cos r cos p)
    let up = |r: f64, p: f64| [-p.sin(), r.sin() * p.cos(), r.cos() * p.cos()];
    let (u1, u2) = (up(roll + 0.01, pitch), up(roll, pitch));
    let want = (u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2])
        .min(1.0)
        .acos()
        .to_degrees();
    let got = row("pendulum3d")["rms_deg"].as_f64().unwrap();
    assert!((got - want).abs() < 1e-6, "{got} vs {want}");
    assert!((want - 0.01f64.to_degrees() * pitch.cos()).abs() < 1e-4);
}

#[test]
fn bad_input_names_the_file_and_place_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let head = "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az,roll,pitch\n";
    let row = |t: f64| format!("{t},0,0,0,0,0,0,0,9.8,0,0\n");
    let mut csv = String::from(head);
    for k in 0..100 {
        csv.push_str(&row(k as f64 * 1e-3));
    }
    csv.push_str("0.1,0,0,abc,0,0,0,0,9.8,0,0\n");
    let log = write(dir.path(), "bad.csv", &csv);
    let out = dir.path().join("rep");
    let o = pendtilt(&["report", s(&log), "-o", s(&out), "-q"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("bad.csv:102: column 4 (`gyro_x`)") && e.contains("abc"),
        "{e}"
    );
    assert!(!out.exists(), "a failed report left {}", out.display());

    // no truth: refused, naming the columns
    let mut csv = String::from("t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az\n");
    for k in 0..100 {
        csv.push_str(&format!("{},0,0,0,0,0,0,0,9.8\n", k as f64 * 1e-3));
    }
    let log = write(dir.path(), "notruth.csv", &csv);
    let e = stderr(&pendtilt(&["report", s(&log), "-o", s(&out), "-q"]));
    assert!(
        e.contains("notruth.csv") && e.contains("`roll` and `pitch`"),
        "{e}"
    );
    assert!(!out.exists());

    // the 3-D options on a planar log
    let planar = write(
        dir.path(),
        "p.csv",
        "t,phi,gyro,ax,ay,theta\n0,0,0,0,9.8,0\n",
    );
    let e = stderr(&pendtilt(&[
        "report",
        s(&planar),
        "--scenario",
        s(&planar),
        "-o",
        s(&out),
    ]));
    assert!(e.contains("--scenario: for 3-D logs only"), "{e}");
}
