//! `pendtilt fit` on 3-D logs: simulate -> fit -> estimate end to end, `-o -`, the physical
//! form with the start rig's tables kept, an input never overwritten, and the refusals
//! (an implausible rig, a still log) that write nothing.
use std::path::{Path, PathBuf};

mod common;
use common::{pendtilt, s, stderr, write};

fn ok(args: &[&str]) -> (String, String) {
    let out = pendtilt(args);
    assert!(out.status.success(), "pendtilt {args:?}: {}", stderr(&out));
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr(&out),
    )
}

fn fails(args: &[&str]) -> String {
    let out = pendtilt(args);
    assert!(!out.status.success(), "pendtilt {args:?} succeeded");
    stderr(&out)
}

/// A 20 s scooter3d log in `dir` with `extra` simulate options.
fn simulate(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let log = dir.join(format!("{name}.csv"));
    let mut args = vec![
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "20",
        "-q",
        "-o",
        s(&log),
    ];
    args.extend_from_slice(extra);
    ok(&args);
    log
}

/// The fitted rig is written, reported per parameter and axis, and `estimate` reads it;
/// `-o -` gives the TOML alone on standard output; the physical form keeps the start
/// rig's `[mounting]`; an input is never the output.
#[test]
fn fit_writes_a_rig_that_estimate_reads() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path(), "scooter3d", &[]);
    let rig = dir.path().join("fitted.toml");
    let (out, err) = ok(&["fit", s(&log), "-o", s(&rig)]);
    for want in [
        "a_x [s]",
        "b_x + b_ring [s^2]",
        "outer (x): natural frequency",
        "inner (y)",
        "RMS residual",
        "iterations",
    ] {
        assert!(out.contains(want), "{want}: {out}");
    }
    assert!(err.contains("held at the start rig's values: b_z"), "{err}");
    // No --params: the written rig has no [mounting], and the log has a speed column.
    let warned = "no --params was given, so the fit took the accelerometer as at P1";
    assert_eq!(err.matches(warned).count(), 1, "{err}");
    assert!(
        err.contains("the point whose speed the log's `speed` column gives"),
        "{err}"
    );
    let text = std::fs::read_to_string(&rig).unwrap();
    assert!(
        text.contains("\na_x = ") && text.contains("\nb_ring = "),
        "{text}"
    );
    let est = dir.path().join("est.csv");
    ok(&["estimate", s(&log), "--params", s(&rig), "-o", s(&est)]);
    assert!(std::fs::read_to_string(&est).unwrap().starts_with("t,"));

    let (toml, err) = ok(&["fit", s(&log), "--target", "gyro", "-q", "-o", "-"]);
    assert!(
        err.contains(warned),
        "a warning is said even with -q: {err}"
    );
    assert!(
        toml.starts_with("# fitted by `pendtilt fit`") && toml.contains("[pendulum3d]"),
        "{toml}"
    );
    assert!(
        !toml.contains("natural frequency") && err.contains("natural frequency"),
        "{err}"
    );

    let start = dir.path().join("scooter3d.rig.toml");
    let phys = dir.path().join("phys.toml");
    ok(&[
        "fit",
        s(&log),
        "--params",
        s(&start),
        "--mass",
        "0.06",
        "-q",
        "-o",
        s(&phys),
    ]);
    let text = std::fs::read_to_string(&phys).unwrap();
    let (_, err) = ok(&["fit", s(&log), "--params", s(&start), "-o", s(&rig)]);
    assert!(!err.contains("[mounting]"), "the start rig has one: {err}");
    assert!(
        text.contains("mass = 0.06") && text.contains("speed_at = [0.0, 0.0, -0.25]"),
        "{text}"
    );
    ok(&["estimate", s(&log), "--params", s(&phys), "-o", s(&est)]);

    let before = std::fs::read(&log).unwrap();
    let err = fails(&["fit", s(&log), "-o", s(&log)]);
    assert!(err.contains("-o"), "{err}");
    assert_eq!(std::fs::read(&log).unwrap(), before);
    let err = fails(&["fit", s(&log), "--method", "newton", "-o", s(&rig)]);
    assert!(
        err.contains("--method newton: for planar logs only"),
        "{err}"
    );
}

/// A ring eight times the pendulum's inertia: the fit says why it is implausible, with
/// the frequencies, exits non-zero and leaves an earlier file as it was.
#[test]
fn an_implausible_fit_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let ring = write(
        dir.path(),
        "ring.toml",
        "[rig.pendulum3d]\nring_inertia = 0.00104\n",
    );
    let log = simulate(dir.path(), "ring", &["--config", s(&ring)]);
    let rig = write(dir.path(), "old.toml", "old\n");
    let err = fails(&["fit", s(&log), "-q", "-o", s(&rig)]);
    assert!(
        err.contains("implausible") && err.contains("further apart than a Cardan pendulum allows"),
        "{err}"
    );
    assert!(err.contains("Hz (outer)"), "{err}");
    assert_eq!(std::fs::read_to_string(&rig).unwrap(), "old\n");
}

/// A log at rest: not identifiable, said with the sensitivity, nothing written.
#[test]
fn a_still_log_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az,roll,pitch\n");
    for k in 0..5000 {
        let w = 1e-6 * (k % 7) as f64;
        csv.push_str(&format!(
            "{},{w},0,0,{w},0,0,0,9.80665,0,0\n",
            k as f64 * 1e-3
        ));
    }
    let log = write(dir.path(), "still.csv", &csv);
    let rig = dir.path().join("rig.toml");
    let err = fails(&["fit", s(&log), "-q", "-o", s(&rig)]);
    assert!(
        err.contains("not identifiable") && err.contains("needs more motion"),
        "{err}"
    );
    assert!(!rig.exists());
}
