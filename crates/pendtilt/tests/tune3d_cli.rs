//! `pendtilt tune` on a 3-D log end to end: the rig file it writes is the input's with a
//! filled `[ekf3d]` table, `pendtilt estimate` reads it as it is and it beats the
//! defaults against the simulator's truth on a rig the defaults were not chosen on; `-o
//! -` writes only TOML to standard output; tuning a tuned file replaces its table; a truth
//! target is refused.
use std::path::{Path, PathBuf};

mod common;
use common::{pendtilt, s, stderr};
use pendtilt::bank::spatial::rig::{Pendulum3dConfig, Rig3dConfig};
use pendtilt::sim::spatial::output::write_log;
use pendtilt::sim::spatial::Rig3d;
use pendtilt::tune::spatial::zoo::ride;

/// Zoo ride 0 (scooter3d on an unseen rig: 1.2 Hz, zeta 0.15, 5 mm pivot offset,
/// consumer sensors), 30 s, as a 3-D log with its rig file.
fn fixture(dir: &Path) -> (PathBuf, PathBuf) {
    let r = ride(0, 30.0);
    let log = dir.join("ride.csv");
    let f = std::fs::File::create(&log).unwrap();
    write_log(
        r.scenario.run(0).unwrap(),
        std::io::BufWriter::new(f),
        |_| {},
    )
    .unwrap();
    let rig = dir.join("rig.toml");
    let text = Rig3d {
        pendulum3d: r.scenario.rig.pendulum3d,
        mounting: r.scenario.rig.mounting,
    }
    .to_toml_string()
    .unwrap();
    std::fs::write(&rig, text).unwrap();
    (log, rig)
}

/// ekf3d's RMS inclination error [deg] as `estimate` prints it.
fn ekf3d_rms(log: &Path, rig: &Path, out: &Path) -> f64 {
    let o = pendtilt(&[
        "estimate",
        s(log),
        "--params",
        s(rig),
        "--only",
        "ekf3d",
        "-o",
        s(out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).to_string() + &stderr(&o);
    let line = text
        .lines()
        .find(|l| l.starts_with("ekf3d "))
        .unwrap_or_else(|| panic!("{text}"));
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

#[test]
fn the_tuned_file_round_trips_through_estimate_and_beats_the_defaults() {
    let dir = tempfile::tempdir().unwrap();
    let (log, rig) = fixture(dir.path());
    let tuned = dir.path().join("tuned.toml");
    let o = pendtilt(&["tune", s(&log), "-p", s(&rig), "-o", s(&tuned)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    // What it found, each with its evidence, and the doubts.
    assert!(out.contains("ekf3d.gyro_density = "), "{out}");
    assert!(out.contains("median of the spectrum"), "{out}");
    assert!(
        out.contains("ekf3d.gyro_bias_walk") && out.contains("KEPT"),
        "{out}"
    );
    let text = std::fs::read_to_string(&tuned).unwrap();
    assert!(text.contains("# doubts"), "{text}");
    let a = Rig3dConfig::load(&rig).unwrap();
    let b = Rig3dConfig::load(&tuned).unwrap();
    assert_eq!(a.pendulum3d, b.pendulum3d);
    assert_eq!(a.mounting, b.mounting);
    assert!(b.ekf3d.gives_sensor_noise(), "{:?}", b.ekf3d);
    assert!(matches!(b.pendulum3d, Pendulum3dConfig::Physical(_)));
    // estimate takes it as it is, and says nothing of default noise figures.
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "--params",
        s(&tuned),
        "-o",
        s(&dir.path().join("e.csv")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !stderr(&o).contains("default sensor noise"),
        "{}",
        stderr(&o)
    );
    let d = ekf3d_rms(&log, &rig, &dir.path().join("d.csv"));
    let t = ekf3d_rms(&log, &tuned, &dir.path().join("t.csv"));
    println!("ekf3d: defaults {d} deg, tuned {t} deg");
    assert!(t < 0.7 * d, "{t} vs {d}");
    // Tuning the tuned file again replaces its table: one [ekf3d], its keys once.
    let again = dir.path().join("again.toml");
    let o = pendtilt(&["tune", s(&log), "-p", s(&tuned), "-o", s(&again), "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&again).unwrap();
    assert_eq!(text.matches("[ekf3d]").count(), 1, "{text}");
    assert_eq!(text.matches("\ngyro_density = ").count(), 1, "{text}");
    assert_eq!(Rig3dConfig::load(&again).unwrap().pendulum3d, a.pendulum3d);
}

#[test]
fn dash_writes_only_toml_to_standard_output() {
    let dir = tempfile::tempdir().unwrap();
    let (log, rig) = fixture(dir.path());
    let o = pendtilt(&["tune", s(&log), "-p", s(&rig), "-o", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout.clone()).unwrap();
    // The whole of standard output is the rig file; what was found went to stderr.
    out.parse::<toml::Table>().unwrap();
    let r = Rig3dConfig::from_toml_str(&out, "stdout").unwrap();
    assert!(r.ekf3d.vibration_density.is_some());
    assert!(
        stderr(&o).contains("ekf3d.vibration_density = "),
        "{}",
        stderr(&o)
    );
    // Without --params: the default rig's pendulum with the tuned table.
    let o = pendtilt(&["tune", s(&log), "-o", "-", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert_eq!(
        Rig3dConfig::from_toml_str(&out, "stdout")
            .unwrap()
            .pendulum3d,
        Rig3dConfig::default().pendulum3d
    );
}

#[test]
fn a_truth_target_is_refused_and_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let (log, rig) = fixture(dir.path());
    let out = dir.path().join("t.toml");
    let o = pendtilt(&[
        "tune",
        s(&log),
        "-p",
        s(&rig),
        "-o",
        s(&out),
        "--target",
        "truth",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("without its truth"), "{}", stderr(&o));
    assert!(!out.exists());
}

/// An accelerometer read in the wrong unit (`--accel-unit g` on a log in m/s^2): the 3-D
/// tune and fit say so on standard error with the fix, and the tuned file carries it.
#[test]
fn a_wrong_accelerometer_unit_is_said_by_tune_and_fit() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("sc.csv");
    let out = pendtilt(&[
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "12",
        "-q",
        "-o",
        s(&log),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let rig = dir.path().join("sc.rig.toml");
    let tuned = dir.path().join("t.toml");
    let out = pendtilt(&[
        "tune",
        s(&log),
        "--params",
        s(&rig),
        "--accel-unit",
        "g",
        "-q",
        "-o",
        s(&tuned),
    ]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: ") && err.contains("leave out --accel-unit g"),
        "{err}"
    );
    let text = std::fs::read_to_string(&tuned).unwrap();
    assert!(text.contains("# NOT TO BE TRUSTED: tuned on a log whose units look wrong"));
    let out = pendtilt(&[
        "fit",
        s(&log),
        "--params",
        s(&rig),
        "--accel-unit",
        "g",
        "-q",
        "-o",
        "-",
    ]);
    assert!(
        stderr(&out).contains("leave out --accel-unit g"),
        "{}",
        stderr(&out)
    );
    // Read as it is, neither says anything of the unit.
    let out = pendtilt(&["tune", s(&log), "--params", s(&rig), "-q", "-o", s(&tuned)]);
    assert!(!stderr(&out).contains("--accel-unit"), "{}", stderr(&out));
}
