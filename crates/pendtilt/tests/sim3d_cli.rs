//! `pendtilt simulate --scenario still3d|scooter3d|ship3d|ride3d` end to end: the log, the rig
//! and the scenario file on disk; the log reads back through the 3-D reader to the very values
//! the library simulates; the scenario file reruns to the same bytes; clear errors.

use pendtilt::io::{read_log3d, Log3dReader};
use pendtilt::sim::spatial::{LogRow3d, Rig3d, Scenario3d};

mod common;
use common::{pendtilt, s, stderr};

fn ok(args: &[&str]) {
    let out = pendtilt(args);
    assert!(
        out.status.success(),
        "pendtilt {args:?} failed: {}",
        stderr(&out)
    );
}

#[test]
fn every_scenario_round_trips_through_the_log_reader() {
    let dir = tempfile::tempdir().unwrap();
    for (name, seed) in [
        ("still3d", 1u64),
        ("scooter3d", 2),
        ("ship3d", 3),
        ("ride3d", 4),
    ] {
        let log = dir.path().join(format!("{name}.csv"));
        let sd = seed.to_string();
        ok(&[
            "simulate",
            "--scenario",
            name,
            "--duration",
            "0.3",
            "--seed",
            &sd,
            "-q",
            "-o",
            s(&log),
        ]);
        let text = std::fs::read_to_string(&log).unwrap();
        assert_eq!(
            text.lines().next(),
            Some(LogRow3d::COLUMNS.join(",").as_str())
        );
        let mut want = Scenario3d::named(name, seed).unwrap();
        want.duration = 0.3;
        let rows: Vec<LogRow3d> = want.run(seed).unwrap().map(|(_, r)| r).collect();
        let read = read_log3d(&log).unwrap();
        assert_eq!(read.len(), 300);
        assert_eq!(rows.len(), 300);
        for (r, w) in read.iter().zip(&rows) {
            assert_eq!(
                (r.t, r.phi, r.gyro, r.accel),
                (w.t, w.phi, w.gyro, w.accel),
                "{name} line {}",
                r.line
            );
            assert_eq!(
                (r.speed, r.roll, r.pitch),
                (Some(w.speed), Some(w.roll), Some(w.pitch))
            );
            assert!(!r.issues.missing && !r.issues.time_not_increasing);
        }
        // The rig file reads back to the scenario's rig; the scenario file to the scenario.
        let rig = std::fs::read_to_string(dir.path().join(format!("{name}.rig.toml"))).unwrap();
        assert_eq!(Rig3d::from_toml(&rig, "rig").unwrap(), want.rig);
        assert!(rig.contains("[pendulum3d]") && rig.contains("[mounting]"));
        let scen_path = dir.path().join(format!("{name}.scenario.toml"));
        let scen = std::fs::read_to_string(&scen_path).unwrap();
        let (back, file_seed) = Scenario3d::from_toml(&scen, "scenario").unwrap();
        assert_eq!((back, file_seed), (want, Some(seed)));
        // Rerun from the scenario file: the same bytes.
        let again = dir.path().join(format!("{name}_again.csv"));
        ok(&["simulate", "--config", s(&scen_path), "-q", "-o", s(&again)]);
        assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes());
    }
}

#[test]
fn switches_noise_and_vibration_off() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("r.csv");
    ok(&[
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "0.2",
        "--ideal-sensors",
        "--no-vibration",
        "--rate",
        "500",
        "-q",
        "-o",
        s(&log),
    ]);
    let mut want = Scenario3d::named("scooter3d", 1).unwrap();
    want.duration = 0.2;
    want.rate = 500.0;
    want.sensors = want.sensors.ideal();
    want.motion = want.motion.without_vibration();
    let read = read_log3d(&log).unwrap();
    assert_eq!(read.len(), 100);
    for ((x, w), r) in want.run(1).unwrap().zip(&read) {
        assert_eq!(r.phi, x.encoders(), "ideal encoders read the truth");
        assert_eq!(r.gyro, x.body.w);
        assert_eq!(r.accel, w.accel);
    }
    let scen = std::fs::read_to_string(dir.path().join("r.scenario.toml")).unwrap();
    let (back, _) = Scenario3d::from_toml(&scen, "scenario").unwrap();
    assert!(!back.motion.has_vibration() && !scen.contains("kind = \"engine\""));
    assert_eq!(back.sensors, want.sensors);
}

#[test]
fn wrong_names_and_planar_flags_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("x.csv");
    let out = pendtilt(&["simulate", "--scenario", "rides3d", "-o", s(&log)]);
    assert!(!out.status.success());
    let e = stderr(&out);
    for n in [
        "still3d",
        "scooter3d",
        "ship3d",
        "ride3d",
        "scooter",
        "sigmoid",
    ] {
        assert!(e.contains(n), "{e}");
    }
    assert!(e.contains("unknown scenario 'rides3d'"), "{e}");
    let out = pendtilt(&[
        "simulate",
        "--scenario",
        "ship3d",
        "--mass",
        "0.1",
        "-o",
        s(&log),
    ]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("--mass: for the planar scenarios only"),
        "{}",
        stderr(&out)
    );
    assert!(!log.exists(), "nothing written on an error");
    // The scenario file is an input: -o may not overwrite it.
    let first = dir.path().join("a.csv");
    ok(&[
        "simulate",
        "--scenario",
        "still3d",
        "--duration",
        "0.01",
        "-q",
        "-o",
        s(&first),
    ]);
    let scen = dir.path().join("a.scenario.toml");
    let before = std::fs::read(&scen).unwrap();
    let out = pendtilt(&["simulate", "--config", s(&scen), "-q", "-o", s(&first)]);
    assert!(
        !out.status.success(),
        "rerun into the same name overwrites its own input"
    );
    assert_eq!(std::fs::read(&scen).unwrap(), before);
}

#[test]
fn reader_errors_name_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("r.csv");
    ok(&[
        "simulate",
        "--scenario",
        "still3d",
        "--duration",
        "0.005",
        "-q",
        "-o",
        s(&log),
    ]);
    let mut text = std::fs::read_to_string(&log).unwrap();
    text = text.replacen("0.003,", "0.003,oops", 1);
    std::fs::write(&log, &text).unwrap();
    let e = read_log3d(&log).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!(
            "{}:5: column 2 (`phi_x`): not a number: `oops",
            log.display()
        )),
        "{e}"
    );
    let planar = dir.path().join("p.csv");
    std::fs::write(&planar, "t,phi,gyro,ax,ay\n0,0,0,0,9.8\n").unwrap();
    let e = Log3dReader::open(&planar).unwrap_err().to_string();
    assert!(e.contains(":1: not a 3-D log: no `phi_x`"), "{e}");
}

/// Writes the scenario files of the two tests below into `dir`: `part.toml` (one key, no
/// base), `ship.toml` (the same key on `ship3d` seed 4) and `typo.toml` (a misspelt key).
fn scenario_files(dir: &std::path::Path) {
    std::fs::write(
        dir.join("part.toml"),
        "[rig.pendulum3d]\ninertia_xx = 0.0026\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("ship.toml"),
        "scenario = \"ship3d\"\nseed = 4\n[rig.pendulum3d]\ninertia_xx = 0.0026\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("typo.toml"),
        "[rig.pendulum3d]\ninertia_x = 0.0026\n",
    )
    .unwrap();
}

/// A 3-D scenario file of some keys is applied on top of the named scenario, key by key,
/// as a planar one is (earlier: with `--scenario scooter3d` it was refused as "is a
/// scenario" with an empty name; with its own `scenario = "ship3d"` as "missing field
/// `duration`", no file named). A whole file still reruns to the same bytes.
#[test]
fn a_3d_scenario_file_of_some_keys_overrides_the_named_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    scenario_files(dir.path());
    let base = Scenario3d::named("scooter3d", 1).unwrap();
    ok(&[
        "simulate",
        "--scenario",
        "scooter3d",
        "--config",
        s(&p("part.toml")),
        "--duration",
        "0.5",
        "-q",
        "-o",
        s(&p("a.csv")),
    ]);
    let text = std::fs::read_to_string(p("a.scenario.toml")).unwrap();
    let (got, _) = Scenario3d::from_toml(&text, "a.scenario.toml").unwrap();
    let mut want = base.clone();
    want.duration = 0.5;
    want.rig.pendulum3d.inertia_xx = 0.0026;
    assert_eq!(got, want);
    // Its own `scenario` key and seed name the base.
    ok(&[
        "simulate",
        "--config",
        s(&p("ship.toml")),
        "--duration",
        "0.5",
        "-q",
        "-o",
        s(&p("b.csv")),
    ]);
    let text = std::fs::read_to_string(p("b.scenario.toml")).unwrap();
    assert!(text.contains("scenario = \"ship3d\"\nseed = 4\n"), "{text}");
    let (got, _) = Scenario3d::from_toml(&text, "b.scenario.toml").unwrap();
    let mut want = Scenario3d::named("ship3d", 4).unwrap();
    want.duration = 0.5;
    want.rig.pendulum3d.inertia_xx = 0.0026;
    assert_eq!(got, want);
    // A whole file reruns to the same bytes.
    ok(&[
        "simulate",
        "--config",
        s(&p("b.scenario.toml")),
        "-q",
        "-o",
        s(&p("c.csv")),
    ]);
    assert_eq!(
        std::fs::read(p("b.csv")).unwrap(),
        std::fs::read(p("c.csv")).unwrap()
    );
}

/// A 3-D scenario file naming another scenario than --scenario, or none at all, or with a
/// misspelt key, is a clear error, and nothing is written.
#[test]
fn a_3d_scenario_file_naming_another_scenario_or_none_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    scenario_files(dir.path());
    // (the --config file, --scenario if any, what the error says)
    let refused: [(&str, Option<&str>, &[&str]); 3] = [
        (
            "ship.toml",
            Some("scooter3d"),
            &[
                "--scenario scooter3d: the --config file ",
                "ship.toml is a ship3d scenario (its `scenario` key): give one of them",
            ],
        ),
        ("part.toml", None, &["no base scenario", "a 3-D one: still3d, scooter3d"]),
        (
            "typo.toml",
            Some("scooter3d"),
            &["typo.toml: `rig.pendulum3d.inertia_x` (line 2, column 1): unknown field `inertia_x`"],
        ),
    ];
    for (config, scenario, says) in refused {
        let (file, out) = (p(config), p("d.csv"));
        let mut args = vec!["simulate", "--config", s(&file), "-o", s(&out)];
        if let Some(name) = scenario {
            args.extend(["--scenario", name]);
        }
        let o = pendtilt(&args);
        assert!(!o.status.success());
        let e = stderr(&o);
        assert!(says.iter().all(|w| e.contains(w)), "{config}: {e}");
    }
    assert!(!p("d.csv").exists());
}

/// The scenario file's header tells the truth about its units: the [motion] amplitudes in
/// degrees, the sensors' angles in radians (it said "angles in degrees, SI otherwise",
/// and `encoder_noise` is in rad).
#[test]
fn the_scenario_files_header_names_its_units_truly() {
    let o = pendtilt(&["simulate", "--scenario", "still3d", "--print-scenario"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let header: String = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        header.contains("[motion] roll, pitch and yaw terms in degrees")
            && header.contains("[sensors] angles in rad"),
        "{header}"
    );
    let v: toml::Value = toml::from_str(&text).unwrap();
    let o = pendtilt(&["simulate", "--scenario", "scooter3d", "--print-scenario"]);
    let sc: toml::Value = toml::from_str(&String::from_utf8(o.stdout).unwrap()).unwrap();
    let written = sc["sensors"]["encoder_noise"].as_float().unwrap();
    let s = Scenario3d::named("scooter3d", 1).unwrap();
    assert_eq!(written, s.sensors.encoder_noise);
    assert!((written - 0.01f64.to_radians()).abs() < 1e-15, "{written}");
    // still3d's roll: a 10 deg sigmoid, written as 10.
    let roll_amp = v["motion"]["roll"][0]["shape"]["amp"].as_float().unwrap();
    assert_eq!(roll_amp, 10.0);
}
