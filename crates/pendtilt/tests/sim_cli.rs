//! `pendtilt simulate` end to end: log, rig TOML and scenario TOML on disk, reproducible,
//! and clear errors.

use pendtilt::config::RigConfig;
use pendtilt::core::PhysicalParams;

mod common;
use common::{pendtilt, s};

fn ok(args: &[&str]) {
    let out = pendtilt(args);
    assert!(
        out.status.success(),
        "pendtilt {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn writes_log_rig_and_scenario_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("run.csv");
    ok(&[
        "simulate",
        "--scenario",
        "sigmoid",
        "--duration",
        "1.5",
        "--seed",
        "3",
        "--pivot-offset",
        "0.1",
        "--quiet",
        "-o",
        s(&log),
    ]);
    let text = std::fs::read_to_string(&log).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,phi,gyro,ax,ay,theta"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 1500);
    assert!(rows.iter().all(|r| r.len() == 6));
    assert_eq!(rows[1][0], 0.001);

    // The rig TOML reads back, unedited, through the rig-file loader.
    let rig = RigConfig::load(dir.path().join("run.rig.toml")).unwrap();
    let p = rig.physical().expect("physical [pendulum]");
    assert_eq!(
        p,
        PhysicalParams {
            pivot_offset: 0.1,
            ..PhysicalParams::default()
        }
    );

    // The resolved scenario reruns to the same bytes (its seed included).
    let scen = dir.path().join("run.scenario.toml");
    let again = dir.path().join("again.csv");
    ok(&["simulate", "--config", s(&scen), "--quiet", "-o", s(&again)]);
    assert_eq!(std::fs::read(&log).unwrap(), std::fs::read(&again).unwrap());
}

#[test]
fn same_seed_same_bytes_and_flags_take_effect() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        dir.path().join("a.csv"),
        dir.path().join("b.csv"),
        dir.path().join("c.csv"),
    );
    let base = [
        "simulate",
        "--scenario",
        "scooter",
        "--duration",
        "1",
        "--quiet",
    ];
    ok(&[&base[..], &["--seed", "5", "-o", s(&a)][..]].concat());
    ok(&[&base[..], &["--seed", "5", "-o", s(&b)][..]].concat());
    ok(&[&base[..], &["--seed", "6", "-o", s(&c)][..]].concat());
    let (ta, tb, tc) = (
        std::fs::read(&a).unwrap(),
        std::fs::read(&b).unwrap(),
        std::fs::read(&c).unwrap(),
    );
    assert_eq!(ta, tb);
    assert_ne!(ta, tc);

    // --no-noise --no-vibration with a still body: a clean, level log.
    let d = dir.path().join("d.csv");
    ok(&[
        "simulate",
        "--scenario",
        "still",
        "--duration",
        "0.2",
        "--ideal-sensors",
        "--set",
        "motion.angle=0.1",
        "--quiet",
        "-o",
        s(&d),
    ]);
    let text = std::fs::read_to_string(&d).unwrap();
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v[1], 0.1, "{line}");
        assert_eq!(v[5], 0.1, "{line}");
        assert_eq!(v[2], 0.0, "{line}");
    }
}

#[test]
fn bad_input_fails_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("x.csv");
    let cases: [(&[&str], &str); 4] = [
        (&["--scenario", "tractor"], "scooter"),
        (
            &["--scenario", "sine", "--set", "pendulum.mass=-1"],
            "pendulum.mass",
        ),
        (
            &["--scenario", "sine", "--set", "pendulum.colour=3"],
            "colour",
        ),
        (
            &["--scenario", "scooter", "--frequency", "3"],
            "--frequency",
        ),
    ];
    for (args, needle) in cases {
        let out = pendtilt(&[&["simulate"][..], args, &["-o", s(&log)][..]].concat());
        assert!(!out.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let cfg = dir.path().join("bad.toml");
    std::fs::write(&cfg, "scenario = \"sine\"\n[motion]\nfrequency = -2.0\n").unwrap();
    let out = pendtilt(&["simulate", "--config", s(&cfg), "-o", s(&log)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("bad.toml") && err.contains("motion.frequency"),
        "{err}"
    );
    // A value of the wrong type, or a misspelt key, is named and placed (earlier: it
    // said `bad.toml: invalid type: string "abc", expected f64`, no key, no line).
    for (text, want) in [
        (
            "scenario = \"sine\"\n\n[pendulum]\nmass = \"abc\"\n",
            "bad.toml: `pendulum.mass` (line 4, column 1): invalid type: string \"abc\", expected f64",
        ),
        (
            "scenario = \"sine\"\nduration = 2\n[pendulum]\n  lenght = 0.1\n",
            "bad.toml: `pendulum.lenght` (line 4, column 3): unknown field `lenght`",
        ),
    ] {
        std::fs::write(&cfg, text).unwrap();
        let out = pendtilt(&["simulate", "--config", s(&cfg), "-o", s(&log)]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(err.contains(want), "{err}");
    }
    assert!(!log.exists());
    // A huge value is quoted as written, not as 300 digits.
    for (set, want) in [
        ("pendulum.mass=1e300", "mass * length^2 = 2.5e297 kg m^2"),
        (
            "pendulum.damping=-1e300",
            "pendulum.damping: must be >= 0, got -1e300",
        ),
    ] {
        let out = pendtilt(&[
            "simulate",
            "--scenario",
            "sine",
            "--set",
            set,
            "-o",
            s(&log),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(want) && err.len() < 400,
            "{err}"
        );
    }
}

#[test]
fn a_duration_of_no_row_is_refused_and_writes_nothing() {
    // `--duration 0` wrote a header-only log (exit 0) that no command reads.
    let dir = tempfile::tempdir().unwrap();
    for scenario in ["scooter", "scooter3d"] {
        let log = dir.path().join(format!("{scenario}.csv"));
        let o = common::pendtilt(&[
            "simulate",
            "--scenario",
            scenario,
            "--duration",
            "0",
            "-o",
            log.to_str().unwrap(),
        ]);
        let e = common::stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(
            e.contains(
                "a duration of 0 s at 1000 Hz gives no row, and a log needs at least one: give \
                 --duration 0.001 or more"
            ),
            "{e}"
        );
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_step_too_long_for_the_pendulum_is_refused_and_writes_nothing() {
    // `--rate 1` integrated the 2.19 Hz pendulum at 0.5 s steps: phi -25040 rad (planar),
    // NaN (3-D), exit 0 and no word.
    let dir = tempfile::tempdir().unwrap();
    for scenario in ["sine", "scooter3d"] {
        let log = dir.path().join(format!("{scenario}.csv"));
        let o = common::pendtilt(&[
            "simulate",
            "--scenario",
            scenario,
            "--rate",
            "1",
            "-o",
            log.to_str().unwrap(),
        ]);
        let e = common::stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(
            e.contains(
                "substeps: an integration step of 5.000e-1 s (1 / (rate 1 Hz x substeps 2)) is \
                 too long for the pendulum, whose fastest mode is 13.733 rad/s (2.186 Hz)"
            ) && e.contains("raise substeps to 28 (--substeps 28) or the rate"),
            "{e}"
        );
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    // What it names runs.
    let log = dir.path().join("ok.csv");
    let o = common::pendtilt(&[
        "simulate",
        "--scenario",
        "sine",
        "--rate",
        "1",
        "--substeps",
        "28",
        "-o",
        log.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
}

#[test]
fn settings_driving_the_pendulum_beyond_physics_write_nothing() {
    // A broadband vibration of 1e300 m/s^2 wrote phi 5.8e294 rad (planar) and NaN (3-D),
    // exit 0.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("v.csv");
    let o = common::pendtilt(&[
        "simulate",
        "--scenario",
        "scooter",
        "--duration",
        "0.1",
        "--set",
        "vibration.broadband.rms=[1e300,1e300]",
        "-o",
        log.to_str().unwrap(),
    ]);
    let e = common::stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("at t = 0.001 s the simulated pendulum angle phi is 5.790357006361599e294 rad")
            && e.contains("the settings drive the pendulum beyond any physical motion"),
        "{e}"
    );
    let s3 = dir.path().join("s3.csv");
    let o = common::pendtilt(&[
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "0.01",
        "-q",
        "-o",
        s3.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let text = std::fs::read_to_string(dir.path().join("s3.scenario.toml")).unwrap();
    let i = text.find("[[motion.broadband]]").unwrap();
    let j = i + text[i..].find("amp = ").unwrap();
    let k = j + text[j..].find('\n').unwrap();
    let huge = dir.path().join("huge.scenario.toml");
    std::fs::write(&huge, format!("{}amp = 1e300{}", &text[..j], &text[k..])).unwrap();
    let h3 = dir.path().join("h3.csv");
    let o = common::pendtilt(&[
        "simulate",
        "--config",
        huge.to_str().unwrap(),
        "-o",
        h3.to_str().unwrap(),
    ]);
    let e = common::stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("the simulated encoder angle phi_x is NaN rad"),
        "{e}"
    );
    assert!(!log.exists() && !h3.exists());
}

/// Runs `pendtilt simulate --duration 0.01 extra.. -o dir/out`, which must succeed; its
/// standard error, where the warnings are.
fn simulate_warnings(dir: &std::path::Path, extra: &[&str], out: &str) -> String {
    let log = dir.join(out);
    let mut args = vec!["simulate", "--duration", "0.01"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", s(&log)]);
    let o = pendtilt(&args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn a_length_in_millimetres_on_the_command_line_is_doubted_like_in_a_rig_file() {
    // `--pivot-offset 50` meant 50 mm: every command reading a rig file warned about it,
    // simulate (which writes that rig file) did not. One check (config::doubt_length)
    // now words it for where the value was given.
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    let run = |extra: &[&str], out: &str| simulate_warnings(dir.path(), extra, out);
    let beyond = "a pivot offset l12 of 50 m is beyond 2 m, larger than any vehicle";
    let e = run(&["--scenario", "still", "--pivot-offset", "50"], "a.csv");
    assert!(
        e.contains(&format!("warning: --pivot-offset 50: {beyond}")),
        "{e}"
    );
    assert!(
        e.contains("give --pivot-offset 0.05 (the options are in metres)"),
        "{e}"
    );
    let e = run(
        &["--scenario", "still", "--set", "pendulum.pivot_offset=-120"],
        "b.csv",
    );
    assert!(
        e.contains(
            "warning: --set pendulum.pivot_offset=-120: a pivot offset l12 of -120 m is beyond 2 m"
        ),
        "{e}"
    );
    assert!(e.contains("give --set pendulum.pivot_offset=-0.12"), "{e}");
    // The rig it wrote, given back as --rig, and its scenario file as --config.
    let rig = p("a.rig.toml");
    let e = run(&["--scenario", "step", "--rig", s(&rig)], "c.csv");
    assert!(
        e.contains(&format!(
            "warning: {}: pendulum.pivot_offset: {beyond}",
            s(&rig)
        )),
        "{e}"
    );
    assert!(
        e.contains("write pendulum.pivot_offset = 0.05 (the rig file is in metres)"),
        "{e}"
    );
    let scen = p("c.scenario.toml");
    let e = run(&["--config", s(&scen)], "d.csv");
    assert!(
        e.contains(&format!(
            "warning: {}: pendulum.pivot_offset: {beyond}",
            s(&scen)
        )),
        "{e}"
    );
    assert!(e.contains("(the scenario file is in metres)"), "{e}");
}

#[test]
fn a_3d_length_in_millimetres_in_a_scenario_or_rig_file_is_doubted() {
    // A 3-D scenario file with r12 = 50 m on z; the 3-D rig file it wrote, to estimate.
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    let run = |extra: &[&str], out: &str| simulate_warnings(dir.path(), extra, out);
    run(&["--scenario", "still3d"], "s3.csv");
    for f in ["s3.scenario.toml", "s3.rig.toml"] {
        let t = std::fs::read_to_string(p(f)).unwrap();
        let t = t.replace(
            "pivot_offset = [0.0, 0.0, 0.0]",
            "pivot_offset = [0.0, 0.0, 50.0]",
        );
        std::fs::write(p(f), t).unwrap();
    }
    let e = run(&["--config", s(&p("s3.scenario.toml"))], "s4.csv");
    assert!(e.contains("rig.pendulum3d.pivot_offset: a pivot offset r12 = [0.0, 0.0, 50.0] m (50.000 m long) is beyond 2 m"), "{e}");
    assert!(
        e.contains("write rig.pendulum3d.pivot_offset = [0.0, 0.0, 0.05]"),
        "{e}"
    );
    let o = pendtilt(&[
        "estimate",
        s(&p("s3.csv")),
        "-p",
        s(&p("s3.rig.toml")),
        "-o",
        s(&p("e3.csv")),
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && e.contains("pendulum3d.pivot_offset: a pivot offset r12"),
        "{e}"
    );
}

#[test]
fn plausible_lengths_or_quiet_give_no_warning() {
    // Plausible lengths (1.5 m, the defaults), or --quiet: not a word.
    let dir = tempfile::tempdir().unwrap();
    let run = |extra: &[&str], out: &str| simulate_warnings(dir.path(), extra, out);
    let e = run(
        &[
            "--scenario",
            "still",
            "--pivot-offset",
            "1.5",
            "--length",
            "0.2",
            "--inertia",
            "0.01",
        ],
        "e.csv",
    );
    assert!(!e.contains("warning"), "{e}");
    let e = run(
        &["--scenario", "still", "--pivot-offset", "50", "--quiet"],
        "f.csv",
    );
    assert!(e.is_empty(), "{e}");
}

#[test]
fn a_missing_config_file_is_named_once() {
    // Was: `nope.toml: No such file or directory (os error 2): No such file or directory
    // (os error 2)` (the io error was both in the message and its source).
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("nope.toml");
    let log = dir.path().join("x.csv");
    let o = common::pendtilt(&[
        "simulate",
        "--config",
        cfg.to_str().unwrap(),
        "-o",
        log.to_str().unwrap(),
    ]);
    let e = common::stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("nope.toml: No such file or directory"), "{e}");
    assert_eq!(e.matches("No such file").count(), 1, "{e}");
}

/// The sensors' full scales and gravity in a scenario file or `--set` get the rig file's
/// unit checks (earlier: `full_scale = 500`, meant as deg/s, simulated a gyro that never clips, and
/// `[sensors.accel] full_scale = 16`, meant as g, one that clips at 1.6 g, without a
/// word). No built-in scenario is doubted.
#[test]
fn full_scales_in_another_unit_in_a_scenario_are_doubted() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("x.csv");
    let cfg = dir.path().join("fs.toml");
    std::fs::write(
        &cfg,
        "scenario = \"scooter\"\n[sensors.accel]\nfull_scale = 16\n[pendulum]\ngravity = 1.0\n",
    )
    .unwrap();
    let run = |args: &[&str]| {
        let out = pendtilt(
            &[
                &["simulate"][..],
                args,
                &["--duration", "0.5", "-o", s(&log)][..],
            ]
            .concat(),
        );
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let e = run(&["--config", s(&cfg)]);
    assert!(
        e.contains("fs.toml: sensors.accel.full_scale: 16 m/s^2 is below 19.6 m/s^2 (2 g)")
            && e.contains(
                "write sensors.accel.full_scale = 156.906 (the scenario file is in m/s^2)"
            )
            && e.contains("fs.toml: pendulum.gravity: 1 m/s^2 is not the Earth's gravity")
            && e.contains("written in g? write pendulum.gravity = 9.80665"),
        "{e}"
    );
    let e = run(&["--scenario", "sine", "--set", "sensors.gyro.full_scale=500"]);
    assert!(
        e.contains("--set sensors.gyro.full_scale=500: sensors.gyro.full_scale: 500 rad/s is above 69.8 rad/s")
            && e.contains("write sensors.gyro.full_scale = 8.72665"),
        "{e}"
    );
    for name in ["still", "sigmoid", "step", "sine", "chirp", "scooter"] {
        let e = run(&["--scenario", name]);
        assert!(!e.contains("warning"), "{name}: {e}");
    }
}

/// `pendtilt simulate --scenario NAME --duration SECONDS -o OUT EXTRA..`.
fn simulate(name: &str, seconds: &str, out: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "simulate",
        "--scenario",
        name,
        "--duration",
        seconds,
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    pendtilt(&args)
}

/// A log written to a device or standard output has no "beside": the rig and scenario
/// files are written only where --rig-out says, and the summary says so (earlier:
/// `-o /dev/null` wrote `/dev/null.rig.toml` and `/dev/null.scenario.toml` into /dev).
#[test]
fn a_log_to_a_device_writes_no_file_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["sine", "scooter3d"] {
        let out = simulate(name, "0.2", "/dev/null", &[]);
        assert!(out.status.success());
        let e = String::from_utf8_lossy(&out.stderr);
        assert!(
            e.contains("rig: none (no file beside standard output or a device: give --rig-out FILE); scenario: none"),
            "{e}"
        );
        assert!(!std::path::Path::new("/dev/null.rig.toml").exists());
        assert!(!std::path::Path::new("/dev/null.scenario.toml").exists());
    }
    // A device that fails is not said to keep an earlier file; `report` names a device as
    // one, not as a file.
    let out = simulate("sine", "0.2", "/dev/full", &[]);
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains(
            "/dev/full was written to directly (a device or pipe): what reached it is incomplete"
        ) && !e.contains("earlier file"),
        "{e}"
    );
    let log = dir.path().join("l.csv");
    assert!(simulate("sine", "1", s(&log), &["-q"]).status.success());
    let out = pendtilt(&["report", s(&log), "-o", "/dev/null"]);
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("-o /dev/null: is a device or pipe, not a directory"),
        "{e}"
    );
    // /dev/stdout redirected to a file is a regular file, still no place for side files.
    let file = std::fs::File::create(dir.path().join("redirected.csv")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args([
            "simulate",
            "--scenario",
            "sine",
            "--duration",
            "0.2",
            "-o",
            "/dev/stdout",
        ])
        .stdout(file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!std::path::Path::new("/dev/stdout.rig.toml").exists());
    assert!(std::fs::read_to_string(dir.path().join("redirected.csv"))
        .unwrap()
        .starts_with("t,phi,gyro"));
    let rig = dir.path().join("r.toml");
    let out = simulate("sine", "0.2", "/dev/null", &["--rig-out", s(&rig)]);
    assert!(out.status.success());
    assert!(std::fs::read_to_string(&rig)
        .unwrap()
        .contains("[pendulum]"));
}
