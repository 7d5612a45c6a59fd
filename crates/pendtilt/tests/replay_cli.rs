//! `pendtilt replay`: a recorded IMU through the virtual pendulum, as a user runs it.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pendtilt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn excerpt(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/broad")
        .join(format!("{name}.mat"))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A BROAD trial replays into a 7.6 log with the truth, one row per recorded row, and a
/// rig file beside it whose gravity is the recording's; `estimate` reads both.
#[test]
fn a_broad_trial_replays_into_a_log_that_estimate_reads() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("t10.csv");
    let o = pendtilt(&[
        "replay",
        s(&excerpt("10_undisturbed_slow_translation_A")),
        "-o",
        s(&log),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("replayed 11427 rows (40.0 s at 285.7 Hz)"),
        "{e}"
    );
    assert!(e.contains("initial rest: 8.00 s"), "{e}");
    let text = std::fs::read_to_string(&log).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az,roll,pitch"
    );
    assert_eq!(lines.count(), 11427);
    let rig = std::fs::read_to_string(dir.path().join("t10.rig.toml")).unwrap();
    assert!(
        rig.contains("[pendulum3d]") && rig.contains("gravity = 9.8"),
        "{rig}"
    );
    let est = dir.path().join("est.csv");
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "--params",
        s(&dir.path().join("t10.rig.toml")),
        "--only",
        "ekf3d,vqf",
        "-o",
        s(&est),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = std::fs::read_to_string(&est).unwrap().lines().count();
    assert_eq!(rows, 11428);
}

/// A user's IMU CSV at 200 Hz with its own names and units (time in ms, gyro in deg/s,
/// accelerometer in g): still for 1 s, then rolling 0.2 rad over 0.25 s and holding it.
fn imu_csv_text() -> String {
    let mut text = String::from("time_ms,gx,gy,gz,ax,ay,az\n");
    for k in 0..400 {
        let t = k as f64 * 5.0;
        let roll = if k < 200 {
            0.0
        } else {
            0.2 * ((k - 200) as f64 / 50.0).min(1.0)
        };
        text += &format!(
            "{t},{},0,0,0,{},{}\n",
            if (200..250).contains(&k) {
                0.2 / 0.25 * 57.29577951308232
            } else {
                0.0
            },
            9.81 * roll.sin() / 9.80665,
            9.81 * roll.cos() / 9.80665
        );
    }
    text
}

/// A user's IMU CSV with other names and units, mapped and converted on the command line.
#[test]
fn an_imu_csv_with_its_own_names_and_units() {
    let dir = tempfile::tempdir().unwrap();
    let imu = dir.path().join("imu.csv");
    std::fs::write(&imu, imu_csv_text()).unwrap();
    let out = dir.path().join("log.csv");
    let o = pendtilt(&[
        "replay",
        s(&imu),
        "--map",
        "t=time_ms,gyro_x=gx,gyro_y=gy,gyro_z=gz",
        "--time-unit",
        "ms",
        "--deg",
        "gyro",
        "--accel-unit",
        "g",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("the recording has no truth"), "{e}");
    // The body rolled 0.2 rad: the pendulum, settled, reads it.
    let last = std::fs::read_to_string(&out).unwrap();
    let row: Vec<f64> = last
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert!((row[1] - 0.2).abs() < 0.01, "{row:?}");
}

/// The same log without --accel-unit g: gravity's size at rest says so.
#[test]
fn an_imu_csv_in_g_without_accel_unit_g_is_doubted() {
    let dir = tempfile::tempdir().unwrap();
    let imu = dir.path().join("imu.csv");
    std::fs::write(&imu, imu_csv_text()).unwrap();
    let out = dir.path().join("log.csv");
    let o = pendtilt(&[
        "replay",
        s(&imu),
        "--map",
        "t=time_ms,gyro_x=gx,gyro_y=gy,gyro_z=gz",
        "--time-unit",
        "ms",
        "--deg",
        "gyro",
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("give --accel-unit g"), "{}", stderr(&o));
}

/// A corrupt cell names the file, the line and the column; the output may not be the
/// input.
#[test]
fn an_imu_csv_with_a_corrupt_cell_and_the_output_on_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let imu = dir.path().join("imu.csv");
    let out = dir.path().join("log.csv");
    std::fs::write(&imu, imu_csv_text().replacen("\n15,0,", "\n15,0x,", 1)).unwrap();
    let o = pendtilt(&[
        "replay",
        s(&imu),
        "--map",
        "t=time_ms,gyro_x=gx,gyro_y=gy,gyro_z=gz",
        "-o",
        s(&out),
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("imu.csv:5: column 2 (`gx`): not a number: `0x`"),
        "{}",
        stderr(&o)
    );
    let o = pendtilt(&["replay", s(&imu), "-o", s(&imu)]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("imu.csv"), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&imu)
        .unwrap()
        .starts_with("time_ms"));
}

/// `--vibration scooter3d`: the accelerometer reads the vibration at the log's times,
/// clipped at 2 g, and the summary says how many rows were clipped; an unknown scenario is
/// refused with the names.
#[test]
fn vibration_is_added_aliased_and_clipped() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.csv");
    let vib = dir.path().join("vib.csv");
    let trial = excerpt("27_disturbed_phone_vibration_B");
    let o = pendtilt(&["replay", s(&trial), "-o", s(&plain), "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = pendtilt(&[
        "replay",
        s(&trial),
        "--vibration",
        "scooter3d",
        "-o",
        s(&vib),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("vibration of scooter3d added"), "{e}");
    assert!(e.contains("read as 0.7 Hz"), "{e}");
    let read = |p: &Path| -> Vec<Vec<f64>> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .map(|x| x.parse().unwrap_or(f64::NAN))
                    .collect()
            })
            .collect()
    };
    let (a, b) = (read(&plain), read(&vib));
    assert_eq!(a.len(), b.len());
    let fs = 2.0 * 9.80665;
    let mut moved = 0;
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x[3..6], y[3..6], "the gyro as recorded");
        for i in 6..9 {
            assert!(y[i].abs() <= fs + 1e-9, "{y:?}");
        }
        moved += usize::from((x[6] - y[6]).abs() > 0.5);
    }
    assert!(moved > a.len() / 2, "{moved}");
    let o = pendtilt(&["replay", s(&trial), "--vibration", "bus", "-o", s(&vib)]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("scooter3d"), "{}", stderr(&o));
}
