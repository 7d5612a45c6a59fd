//! Planar against 3-D: logs, rigs, scenarios and options of the other kind are named,
//! never read as the wrong kind; the rig's forms and the output's safety.
use crate::common::estimate3d::{level_log, ok, simulate};
use crate::common::{bin, pendtilt, s, stderr, write};
use pendtilt::bank::spatial::REGISTRY3D;

#[test]
fn only_with_an_unknown_name_lists_the_3d_estimators_and_planar_options_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let log = write(dir.path(), "log.csv", &level_log(20, 1.0, None));
    let out = dir.path().join("est.csv");
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "--only",
        "ekf3d,alg2",
        "-q",
        "-o",
        s(&out),
    ]);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(e.contains("unknown 3-D estimator alg2"), "{e}");
    for entry in REGISTRY3D {
        assert!(e.contains(entry.name), "{e}");
    }
    let planar = write(
        dir.path(),
        "p.csv",
        "t,phi,gyro,ax,ay\n0,0,0,0,9.8\n0.001,0,0,0,9.8\n",
    );
    let o = pendtilt(&["estimate", s(&planar), "--quaternion", "-q", "-o", s(&out)]);
    assert!(
        stderr(&o).contains("--quaternion: for 3-D logs only"),
        "{}",
        stderr(&o)
    );
    let o = pendtilt(&["estimate", s(&log), "--map", "phi=x", "-q", "-o", s(&out)]);
    assert!(
        stderr(&o).contains("--map phi=...: a column of a planar log"),
        "{}",
        stderr(&o)
    );
}

/// A rig file in the normalised form is read; a wrong one is named with its line and
/// column; the log is never the output.
#[test]
fn rig_forms_and_output_safety() {
    let dir = tempfile::tempdir().unwrap();
    let log = write(dir.path(), "log.csv", &level_log(20, 1.0, None));
    let out = dir.path().join("est.csv");
    let rig = write(
        dir.path(),
        "n.toml",
        "[pendulum3d]\na_x = 0.0436\na_y = 0.0436\nb_x = 0.053\nb_y = 0.053\nb_z = 4e-4\n\
         b_ring = 0.0\nc = [0.0, 0.0, 0.0]\ngravity = 9.80665\n",
    );
    ok(&[
        "estimate",
        s(&log),
        "--params",
        s(&rig),
        "-q",
        "-o",
        s(&out),
    ]);
    let bad = write(
        dir.path(),
        "b.toml",
        "[pendulum3d]\nmass = 0.05\nlength = \"long\"\n",
    );
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "--params",
        s(&bad),
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(stderr(&o).contains("b.toml:3:10:"), "{}", stderr(&o));
    let before = std::fs::read(&log).unwrap();
    let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&log)]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&log).unwrap(), before);
}

/// Runs `pendtilt args..` with `input` on standard input (read through a pipe).
fn piped(args: &[&str], input: &str) -> std::process::Output {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = bin()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let text = input.to_string();
    // A writer thread: the child may stop reading (an error) before the pipe is drained.
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(text.as_bytes());
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    out
}

#[test]
fn a_3d_log_given_to_a_planar_reader_is_named_never_read_as_planar() {
    let dir = tempfile::tempdir().unwrap();
    let text = level_log(200, 1.0, None);
    // `stream` tells a 3-D log by its header and runs the 3-D estimators (it once ran
    // the planar `accel` on the 3-D ax, ay).
    let o = piped(&["stream", "-q"], &text);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.starts_with("t,pendulum3d_roll,pendulum3d_pitch,"),
        "{out}"
    );
    assert_eq!(out.lines().count(), 201, "one row per line");
    // `fit` said "no usable `theta` column"; it fits a 3-D log as one, and this one has
    // no true roll and pitch for the default target.
    let log = write(dir.path(), "log.csv", &text);
    let fitted = dir.path().join("fit.toml");
    let o = pendtilt(&["fit", s(&log), "-q", "-o", s(&fitted)]);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("has no finite `roll` and `pitch`") && e.contains("--target gyro"),
        "{e}"
    );
    assert!(!e.contains("no usable"), "{e}");
    assert!(!fitted.exists());
    // A 3-D log without gyro_z was read as planar: `accel` alone, exit 0.
    let no_gz = text
        .replace(",gyro_z,", ",")
        .replace(",0,0,0,0,0,0,", ",0,0,0,0,0,");
    let log = write(dir.path(), "no_gz.csv", &no_gz);
    let out = dir.path().join("est.csv");
    let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&out)]);
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains(
            "no_gz.csv:1: the header has the 3-D columns phi_x, phi_y, gyro_x, gyro_y but no \
             `gyro_z`"
        ),
        "{e}"
    );
    assert!(!out.exists());
    // One axis read as a planar log on purpose still works (with the roll plane's
    // accelerometer axes).
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "-q",
        "--map",
        "phi=phi_x,gyro=gyro_x,ax=ay,ay=az",
        "--only",
        "alg2",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A 3-D log through a pipe to estimate: copied, told by its header, estimated in 3-D.
    let o = piped(&["estimate", "/dev/stdin", "-q", "-o", s(&out)], &text);
    assert!(o.status.success(), "{}", stderr(&o));
    let est = std::fs::read_to_string(&out).unwrap();
    assert!(est.starts_with("t,pendulum3d_roll,"), "{est}");
}

#[test]
fn a_planar_log_through_a_pipe_reads_as_the_file_does() {
    // `estimate <(cat log.csv)` or `cat log.csv | pendtilt estimate /dev/stdin`: the 3-D
    // check used to read the pipe's first 8 kB, and the reader then took a line from the
    // middle for the header ("no `t` column ... the first line looks like data").
    let dir = tempfile::tempdir().unwrap();
    let mut sc = pendtilt::sim::planar::Scenario::named("sine").unwrap();
    sc.duration = 2.0;
    let rows = pendtilt::sim::planar::simulate(&sc, 1).unwrap();
    let mut text = String::from("t,phi,gyro,ax,ay,theta\n");
    for r in &rows {
        let x = r.sample();
        text.push_str(&format!(
            "{},{},{},{},{},{}\n",
            r.t, x.phi, x.gyro, x.ax, x.ay, r.theta
        ));
    }
    assert!(text.len() > 1 << 17, "more than the reader's buffer");
    let log = write(dir.path(), "log.csv", &text);
    let (from_file, from_pipe) = (dir.path().join("f.csv"), dir.path().join("p.csv"));
    let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&from_file)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = piped(
        &["estimate", "/dev/stdin", "-q", "-o", s(&from_pipe)],
        &text,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&from_file).unwrap(),
        std::fs::read(&from_pipe).unwrap()
    );
}

#[test]
fn a_rig_or_scenario_of_the_other_kind_is_named_as_such() {
    // Was: `unknown field `accel`, expected one of `pendulum3d`, ...` (a planar rig for a
    // 3-D log), a TOML parse error at `amplitude` (a planar scenario), and
    // `pendulum3d: unknown key` (a 3-D rig for a planar log).
    let dir = tempfile::tempdir().unwrap();
    let log3 = simulate(dir.path(), "scooter3d", &["--duration", "1"]);
    let log = simulate(dir.path(), "scooter", &["--duration", "1"]);
    let f = |n: &str| dir.path().join(n);
    let out = f("e.csv");
    let run = |args: &[&str]| {
        let o = pendtilt(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert!(!out.exists());
        stderr(&o)
    };
    let e = run(&[
        "estimate",
        s(&log3),
        "-p",
        s(&f("scooter.rig.toml")),
        "-o",
        s(&out),
    ]);
    assert!(
        e.contains(
            "scooter.rig.toml:2:1: [pendulum]: a planar rig file (MODEL.md 5), and this log is \
             3-D: give a 3-D rig file ([pendulum3d], MODEL.md 7.6)"
        ),
        "{e}"
    );
    let sc = f("scooter.scenario.toml");
    let e = run(&["estimate", s(&log3), "--scenario", s(&sc), "-o", s(&out)]);
    assert!(
        e.contains(
            "scooter.scenario.toml: a planar scenario file (scenario = \"scooter\", [pendulum]), \
             read as a 3-D one"
        ),
        "{e}"
    );
    let e = run(&[
        "estimate",
        s(&log),
        "-p",
        s(&f("scooter3d.rig.toml")),
        "-o",
        s(&out),
    ]);
    assert!(
        e.contains(
            "[pendulum3d] is a table of a 3-D rig file (MODEL.md 7.6), and a planar rig is read \
             here: give a planar rig file ([pendulum], MODEL.md 5)"
        ),
        "{e}"
    );
}

#[test]
fn one_axis_of_a_3d_log_read_as_planar_needs_the_roll_planes_accelerometer_axes() {
    // The hint said `--map phi=...,gyro=...`; followed, the planar ax, ay were the 3-D ax,
    // ay (the roll axis's plane is the 3-D y, z): `accel` -173 deg, Madgwick -140 deg on
    // a ride whose roll was -0.6 deg, exit 0; fit ended IMPLAUSIBLE (f_n 0.026 Hz).
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path(), "scooter3d", &["--duration", "20"]);
    let rig = dir.path().join("f.toml");
    let o = pendtilt(&[
        "fit",
        s(&log),
        "--map",
        "phi=phi_x,gyro=gyro_x,theta=roll",
        "-o",
        s(&rig),
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("--map reads one axis of a 3-D log (MODEL.md 7.6) as planar (phi <- phi_x)")
            && e.contains(
                "give --map phi=phi_x,gyro=gyro_x,ax=ay,ay=az,theta=roll (MODEL.md 7.4: planar \
                 x, y = 3-D y, z)"
            ),
        "{e}"
    );
    assert!(!rig.exists());
    // The map it gives: the default rig's pendulum, a = 4.364e-2, within 5 %.
    let o = pendtilt(&[
        "fit",
        s(&log),
        "--map",
        "phi=phi_x,gyro=gyro_x,ax=ay,ay=az,theta=roll",
        "-o",
        s(&rig),
    ]);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    let text = std::fs::read_to_string(&rig).unwrap();
    let a: f64 = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("a = "))
        .and_then(|v| v.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((a / 4.364385e-2 - 1.0).abs() < 0.05, "a = {a}\n{text}");
}
