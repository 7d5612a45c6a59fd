//! `pendtilt fit` end to end: a simulated log in, a rig file out that loads as it is.
use clap::Parser;
use pendtilt::cli::{run, Cli};
use pendtilt::config::RigConfig;
use pendtilt::sim::{simulate, Scenario};
use pendtilt_core::PendulumParams;
use std::io::Write;

fn write_log(dir: &std::path::Path) -> std::path::PathBuf {
    let mut s = Scenario::named("sigmoid").unwrap();
    s.sensors = s.sensors.ideal();
    let rows = simulate(&s, 1).unwrap();
    let path = dir.join("log.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    writeln!(f, "t,phi,gyro,ax,ay,theta").unwrap();
    for r in &rows {
        writeln!(
            f,
            "{},{},{},{},{},{}",
            r.t, r.phi, r.gyro, r.ax, r.ay, r.theta
        )
        .unwrap();
    }
    path
}

fn fit(args: &[&str]) -> anyhow::Result<()> {
    let mut all = vec!["pendtilt", "fit"];
    all.extend_from_slice(args);
    run(Cli::try_parse_from(all)?)
}

#[test]
fn fit_writes_a_rig_file_that_loads_with_the_fitted_values() {
    let dir = tempfile::tempdir().unwrap();
    let log = write_log(dir.path());
    let t = PendulumParams::<f64>::default();
    for method in ["newton", "lm"] {
        let out = dir.path().join(format!("rig_{method}.toml"));
        fit(&[
            log.to_str().unwrap(),
            "--target",
            "truth",
            "--method",
            method,
            "--a",
            &(1.5 * t.a).to_string(),
            "--b",
            &(0.5 * t.b).to_string(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .unwrap();
        let rig = RigConfig::load(&out).unwrap();
        let p = rig.params();
        assert!((p.a / t.a - 1.0).abs() < 0.01, "{method}: {p:?}");
        assert!((p.b / t.b - 1.0).abs() < 0.01, "{method}: {p:?}");
        // The cutoff the fit used is fixed in the file.
        assert!(rig.differentiator.cutoff_hz.is_some());
    }
    let out = dir.path().join("rig_alg3.toml");
    fit(&[
        log.to_str().unwrap(),
        "--method",
        "lm",
        "--algorithm",
        "alg3",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ])
    .unwrap();
    let rig = RigConfig::load(&out).unwrap();
    let g = rig.alg3.gains(&rig.params());
    assert!((g.k / t.a - 1.0).abs() < 0.01, "{g:?}");
    assert!((g.m / -t.b - 1.0).abs() < 0.01, "{g:?}");
}

#[test]
fn fit_refuses_a_negative_start_and_a_log_without_truth() {
    let dir = tempfile::tempdir().unwrap();
    let log = write_log(dir.path());
    let out = dir.path().join("rig.toml");
    let e = fit(&[
        log.to_str().unwrap(),
        "--a",
        "-0.01",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ])
    .unwrap_err();
    // `{:#}`: the whole chain, as the command prints it.
    let e = format!("{e:#}");
    assert!(e.contains("invalid start value a"), "{e}");
    assert!(e.contains("rig.toml was not written"), "{e}");
    assert!(!out.exists());
    let bare = dir.path().join("bare.csv");
    std::fs::write(&bare, "t,phi,gyro\n0,0,0\n0.001,0,0\n").unwrap();
    let e = fit(&[bare.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]).unwrap_err();
    assert!(format!("{e:#}").contains("`theta`"), "{e:#}");
}

/// `--cost output` on a realistic log (8 s chirp, default noisy sensors, the full
/// `scooter` vibration with broadband floor vibration): within 5 % of a and b.
#[test]
fn fit_cost_output_recovers_a_and_b_on_a_vibrating_log() {
    use pendtilt::sim::motion::{Chirp, Motion};
    let dir = tempfile::tempdir().unwrap();
    let motion = Motion::Chirp(Chirp {
        f0: 0.2,
        f1: 3.0,
        sweep_time: 8.0,
        ..Chirp::default()
    });
    let mut s = Scenario::with_motion(motion, 8.0);
    s.vibration = Scenario::named("scooter").unwrap().vibration;
    let rows = simulate(&s, 7).unwrap();
    let log = dir.path().join("vib.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&log).unwrap());
    writeln!(f, "t,phi,gyro,ax,ay,theta").unwrap();
    for r in &rows {
        writeln!(
            f,
            "{},{},{},{},{},{}",
            r.t, r.phi, r.gyro, r.ax, r.ay, r.theta
        )
        .unwrap();
    }
    drop(f);
    let t = PendulumParams::<f64>::default();
    let out = dir.path().join("rig.toml");
    fit(&[
        log.to_str().unwrap(),
        "--cost",
        "output",
        "--method",
        "lm",
        "--a",
        &(1.5 * t.a).to_string(),
        "--b",
        &(0.5 * t.b).to_string(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ])
    .unwrap();
    let p = RigConfig::load(&out).unwrap().params();
    assert!((p.a / t.a - 1.0).abs() < 0.05, "{p:?}");
    assert!((p.b / t.b - 1.0).abs() < 0.05, "{p:?}");
    // The same driven by the accelerometer columns.
    let out2 = dir.path().join("rig_accel.toml");
    fit(&[
        log.to_str().unwrap(),
        "--cost",
        "output",
        "--accel-drive",
        "--method",
        "lm",
        "-o",
        out2.to_str().unwrap(),
        "-q",
    ])
    .unwrap();
    let p2 = RigConfig::load(&out2).unwrap().params();
    assert!((p2.a / t.a - 1.0).abs() < 0.05, "{p2:?}");
    assert!((p2.b / t.b - 1.0).abs() < 0.05, "{p2:?}");
    // The output cost refuses the gyro target.
    let e = fit(&[
        log.to_str().unwrap(),
        "--cost",
        "output",
        "--target",
        "gyro",
        "-o",
        dir.path().join("no.toml").to_str().unwrap(),
        "-q",
    ])
    .unwrap_err();
    assert!(format!("{e:#}").contains("output-error cost"), "{e:#}");
}
