//! `report` for a ride: the phases found from the log against MODEL.md
//! 7.8's `ride3d` timeline (speed steps and turns), none on vehicles that do not drive,
//! and the ride section of `report`: both runs of ekf3d (with and without the speed) per
//! phase, the compensated one far better in the turns and the braking, the files written.
use std::path::Path;

use pendtilt::experiment::spatial::{simulate3d, Record3d};
use pendtilt::experiment::NoProgress;
use pendtilt::report::spatial::phases::{detect, Phase, PhaseKind};
use pendtilt::sim::spatial::Scenario3d;

mod common;
use common::{pendtilt, s, stderr};

fn record(name: &str, seed: u64, duration: Option<f64>) -> Record3d {
    let mut sc = Scenario3d::named(name, seed).unwrap();
    if let Some(d) = duration {
        sc.duration = d;
    }
    simulate3d(name, &sc, seed, &NoProgress).unwrap()
}

fn phases_of(r: &Record3d) -> Vec<Phase> {
    let speed: Vec<f64> = r.samples.iter().map(|s| s.speed).collect();
    let gz: Vec<f64> = r.samples.iter().map(|s| s.gyro[2]).collect();
    detect(&r.t, &speed, &gz)
}

fn of_kind(p: &[Phase], kind: PhaseKind) -> Vec<Phase> {
    p.iter().filter(|p| p.kind == kind).copied().collect()
}

/// Each `(t0, sign)` of the timeline falls in exactly one phase of `got`, centred on it
/// within `tol` s, with the sign of its peak; and no phase is left unmatched.
fn matches(kind: &str, got: &[Phase], timeline: &[(f64, f64)], tol: f64) {
    assert_eq!(got.len(), timeline.len(), "{kind}: {got:?}");
    for (p, &(t0, sign)) in got.iter().zip(timeline) {
        let centre = 0.5 * (p.from_s + p.to_s);
        assert!(
            p.from_s < t0 && t0 < p.to_s && (centre - t0).abs() < tol,
            "{kind} at {t0} s: found {p:?}"
        );
        assert!(p.peak_mps2 * sign > 0.5, "{kind} at {t0} s: peak {p:?}");
    }
}

#[test]
fn the_phases_of_ride3d_follow_its_timeline() {
    let r = record("ride3d", 1, None);
    let p = phases_of(&r);
    // MODEL.md 7.8: heading sigmoids (+ left) at 22/28 (+-60), 50 (+30), 70/76 (+-90),
    // 94/100 (+-45) s; the centripetal acceleration v w_z takes the turn's sign.
    matches(
        "turning",
        &of_kind(&p, PhaseKind::Turning),
        &[
            (22.0, 1.0),
            (28.0, -1.0),
            (50.0, 1.0),
            (70.0, 1.0),
            (76.0, -1.0),
            (94.0, 1.0),
            (100.0, -1.0),
        ],
        1.0,
    );
    // speed 15 -> 5 at 62 s (4.2 m/s^2), 12 -> 0 at 108 s
    let braking = of_kind(&p, PhaseKind::Braking);
    matches("braking", &braking, &[(62.0, -1.0), (108.0, -1.0)], 1.0);
    assert!(
        (braking[0].peak_mps2 + 4.2).abs() < 0.3,
        "the braking at 62 s is 4.2 m/s^2: {:?}",
        braking[0]
    );
    // 0 -> 6 at 8 s, -> 10 at 15 s, -> 15 at 40 s, 5 -> 12 at 84 s
    matches(
        "accelerating",
        &of_kind(&p, PhaseKind::Accelerating),
        &[(8.0, 1.0), (15.0, 1.0), (40.0, 1.0), (84.0, 1.0)],
        1.0,
    );
}

#[test]
fn vehicles_that_do_not_drive_have_no_phase() {
    // still3d: steps of roll and pitch, no speed; scooter3d: a standing scooter shaken by
    // its engine and swinging up to 10 deg, with a noisy speed sensor
    for (name, duration) in [("still3d", None), ("scooter3d", Some(40.0))] {
        let p = phases_of(&record(name, 3, duration));
        assert!(p.is_empty(), "{name}: {p:?}");
    }
}

fn ok(args: &[&str]) {
    let out = pendtilt(args);
    assert!(out.status.success(), "pendtilt {args:?}: {}", stderr(&out));
}

fn phase<'a>(ride: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    ride["scores"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["phase"] == name)
        .unwrap_or_else(|| panic!("no {name} in {ride}"))
}

fn run<'a>(p: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    p["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["name"] == name)
        .unwrap_or_else(|| panic!("no run {name} in {p}"))
}

fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// A ride3d log (seed 2) in `dir` and its report, which must write its pages and the ride
/// figure; the log and the report's folder.
fn ride_and_its_report(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let log = dir.join("ride.csv");
    ok(&[
        "simulate",
        "--scenario",
        "ride3d",
        "--seed",
        "2",
        "-q",
        "-o",
        s(&log),
    ]);
    let out = dir.join("rep");
    ok(&[
        "report",
        s(&log),
        "--scenario",
        s(&dir.join("ride.scenario.toml")),
        "-q",
        "-o",
        s(&out),
    ]);
    for f in [
        "index.html",
        "report.md",
        "report.json",
        "ride.png",
        "ride.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    (log, out)
}

/// 0.3-0.45 g turns and 0.43 g braking tilt the specific force by 13-24 deg: without the
/// speed the filter follows part of it; with it, it does not (RMS over the phase at least
/// 5 times smaller; the largest error at least halved: today's ekf3d still has a few
/// degrees' spikes on some seeds, the 1 deg target is not met yet).
fn assert_the_speed_helps_in_turns_and_braking(ride: &serde_json::Value) {
    for name in ["turning", "braking"] {
        let p = phase(ride, name);
        let (c, u) = (run(p, "ekf3d"), run(p, "ekf3d without speed"));
        for (key, factor) in [("inclination_rms_deg", 5.0), ("inclination_max_deg", 2.0)] {
            assert!(
                factor * num(c, key) < num(u, key),
                "{name} {key}: with the speed {} vs without {}",
                num(c, key),
                num(u, key)
            );
        }
        assert!(num(p, "seconds") > 5.0, "{name}: {p}");
    }
    let braking = phase(ride, "braking");
    assert!(
        5.0 * num(run(braking, "ekf3d"), "pitch_max_deg")
            < num(run(braking, "ekf3d without speed"), "pitch_max_deg")
    );
}

/// Every figure on one time axis, the log's first to last row, so that their ticks line
/// up (the pitch figure once started a row later, ticked at other times); the number of
/// panels.
fn panels_on_the_logs_time_axis(json: &serde_json::Value, log: &Path) -> usize {
    let csv = std::fs::read_to_string(log).unwrap();
    let t_of = |line: &str| line.split(',').next().unwrap().parse::<f64>().unwrap();
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with(['#', 't'])).collect();
    let span = (t_of(rows[0]), t_of(rows[rows.len() - 1]));
    let mut panels = 0;
    for f in json["figures"].as_array().unwrap() {
        for a in f["axes"].as_array().unwrap() {
            let x = (
                a["x_range"][0].as_f64().unwrap(),
                a["x_range"][1].as_f64().unwrap(),
            );
            assert_eq!(x, span, "{}: {}", f["png"], a["title"]);
            panels += 1;
        }
    }
    panels
}

#[test]
fn report_on_a_ride_sets_ekf3d_beside_itself_without_the_speed() {
    let dir = tempfile::tempdir().unwrap();
    let (log, out) = ride_and_its_report(dir.path());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let ride = &json["ride"];
    assert_eq!(ride["compensated"], "ekf3d");
    assert_eq!(ride["uncompensated"], "ekf3d without speed");
    assert_eq!(json["figures"][0]["png"], "ride.png");
    // the overall row is the report's own table's ekf3d row
    let all = phase(ride, "all");
    let table = json["inclination"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["name"] == "ekf3d")
        .unwrap();
    let comp = run(all, "ekf3d");
    assert!((num(comp, "inclination_rms_deg") - num(table, "rms_deg")).abs() < 1e-9);
    assert!((num(comp, "inclination_max_deg") - num(table, "max_deg")).abs() < 1e-9);
    assert_the_speed_helps_in_turns_and_braking(ride);
    // the page lists the ride table and its figure
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("Per phase of the ride") && html.contains("ride.png"));
    let panels = panels_on_the_logs_time_axis(&json, &log);
    // one interactive plot per panel
    assert_eq!(html.matches("<div class=\"iplot\"").count(), panels);
    assert!(Path::new(&out.join("ride.svg")).metadata().unwrap().len() > 10_000);
}
