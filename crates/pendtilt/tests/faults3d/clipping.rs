//! Clipping: correct logs never look clipped, a gyro clipping below the rig's full scale
//! is found and said.
use crate::common::faults3d::{estimate, simulate, Csv, GYRO_CLIP, T_FAULT};
use crate::common::{pendtilt, s, stderr};
use std::path::{Path, PathBuf};

/// The clip finder (`io::plateau`) never fires on a correct log: the four 3-D scenarios
/// as simulated (noisy, and with ideal sensors: readings that repeat whenever the body is
/// still), and a still3d log written as a quantised IMU would (gyro steps of 0.061 deg/s,
/// accelerometer steps of 0.0024 m/s^2: readings repeat at rest). No warning, no row
/// flagged `saturated`.
#[test]
fn correct_logs_never_look_clipped() {
    let dir = tempfile::tempdir().unwrap();
    let mut cases = Vec::new();
    for scenario in ["still3d", "scooter3d", "ship3d", "ride3d"] {
        for ideal in [false, true] {
            let log = dir.path().join(format!("{scenario}{ideal}.csv"));
            let mut args = vec![
                "simulate",
                "--scenario",
                scenario,
                "--duration",
                "20",
                "--seed",
                "4",
                "-q",
                "-o",
                s(&log),
            ];
            if ideal {
                args.push("--ideal-sensors");
            }
            let o = pendtilt(&args);
            assert!(o.status.success(), "{}", stderr(&o));
            cases.push(log);
        }
    }
    cases.push(quantised_still(dir.path()));
    for log in &cases {
        never_clipped(dir.path(), log);
    }
}

/// still3d quantised: every gyro and accelerometer cell of `still3dfalse.csv` rounded to
/// its step, with its rig and scenario beside it; the log's path.
fn quantised_still(dir: &Path) -> PathBuf {
    let still = dir.join("still3dfalse.csv");
    let mut c = Csv::read(&still);
    let lsb_gyro = 0.061f64.to_radians();
    let q = |v: f64, lsb: f64| ((v / lsb).round() * lsb).to_string();
    c.edit(
        &["gyro_x", "gyro_y", "gyro_z"],
        f64::NEG_INFINITY,
        f64::INFINITY,
        |v| q(v, lsb_gyro),
    );
    c.edit(&["ax", "ay", "az"], f64::NEG_INFINITY, f64::INFINITY, |v| {
        q(v, 0.0024)
    });
    let quantised = dir.join("still3d_quantised.csv");
    c.write(&quantised);
    // Copy the rig and scenario beside it under its name.
    for ext in ["rig.toml", "scenario.toml"] {
        std::fs::copy(
            dir.join(format!("still3dfalse.{ext}")),
            dir.join(format!("still3d_quantised.{ext}")),
        )
        .unwrap();
    }
    let repeats = (1..c.rows.len())
        .filter(|&i| c.rows[i][c.col("gyro_x")] == c.rows[i - 1][c.col("gyro_x")])
        .count();
    assert!(
        repeats * 2 > c.rows.len(),
        "quantised, at rest: {repeats} repeats"
    );
    quantised
}

/// `pendtilt estimate --flags` on `log` with its rig and scenario: no unknown full scale
/// said, no row flagged saturated.
fn never_clipped(dir: &Path, log: &Path) {
    let stem = log.file_stem().unwrap().to_str().unwrap();
    let out = dir.join(format!("{stem}.est.csv"));
    let o = pendtilt(&[
        "estimate",
        s(log),
        "--params",
        s(&dir.join(format!("{stem}.rig.toml"))),
        "--scenario",
        s(&dir.join(format!("{stem}.scenario.toml"))),
        "--flags",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{stem}: {}", stderr(&o));
    assert!(
        !stderr(&o).contains("unknown full scale"),
        "{stem}: {}",
        stderr(&o)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        !text.contains("saturated"),
        "{stem}: a row flagged saturated"
    );
}

/// A rig that overstates the gyro's range: the gyro clipped at 0.1 rad/s for 2 s (the
/// `gyro_clipped` fault) read with `[gyro] full_scale = 8.7` in the rig. The clip is below
/// the rig's full scale, so the finder still looks (it looked only without a full scale,
/// and said nothing): warned as a range smaller than the rig says, and every estimate is
/// the same as without a full scale in the rig.
#[test]
fn a_gyro_clip_below_the_rigs_full_scale_is_found_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path());
    let mut c = Csv::read(&log);
    c.clip(
        &["gyro_x", "gyro_y", "gyro_z"],
        T_FAULT,
        T_FAULT + 2.0,
        GYRO_CLIP,
    );
    let bad = dir.path().join("clipped.csv");
    c.write(&bad);
    let unknown = estimate(dir.path(), &bad, "unknown", "");
    let told = estimate(dir.path(), &bad, "told", "[gyro]\nfull_scale = 8.7\n");
    assert!(
        told.stderr.contains(
            "(`gyro_y`): -0.1 rad/s on 5 rows in a row up to here, which a sensor with noise \
             never writes: a clip below the rig's [gyro] full_scale 8.7 rad/s: the sensor's \
             range is smaller than the rig says"
        ),
        "{}",
        told.stderr
    );
    assert!(
        !told.stderr.contains("unknown full scale"),
        "{}",
        told.stderr
    );
    assert_eq!(unknown.est, told.est, "the same estimates and flags");
}
