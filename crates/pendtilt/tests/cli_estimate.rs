//! `pendtilt estimate` end to end: a small simulated log, the same log with other column
//! names and in degrees, a log missing the gyro, and bad input.
use std::path::{Path, PathBuf};

mod common;
use common::bin;
use pendtilt::sim::{simulate, Scenario};

/// Writes a 3 s scooter log as `t,phi,gyro,ax,ay,theta` (or renamed / in degrees).
fn write_log(path: &Path, names: [&str; 6], degrees: bool, drop_gyro: bool) {
    let mut sc = Scenario::named("scooter").unwrap();
    sc.duration = 3.0;
    let rows = simulate(&sc, 7).unwrap();
    let k = if degrees {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let mut text = String::new();
    let cols: Vec<&str> = names
        .iter()
        .enumerate()
        .filter(|(i, _)| !(drop_gyro && *i == 2))
        .map(|(_, n)| *n)
        .collect();
    text.push_str(&cols.join(","));
    text.push('\n');
    for r in &rows {
        let mut v = vec![r.t, r.phi * k, r.gyro * k, r.ax, r.ay, r.theta * k];
        if drop_gyro {
            v.remove(2);
        }
        let s: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        text.push_str(&s.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn out_path(dir: &Path, name: &str) -> PathBuf {
    dir.join(name)
}

#[test]
fn runs_every_estimator_one_row_per_input_row_and_prints_the_error_table() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let out = out_path(d.path(), "est.csv");
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (header, rows) = read_csv(&out);
    assert_eq!(rows.len(), 3000);
    for name in [
        "t", "accel", "pendulum", "alg1", "alg2", "alg3", "kf_accel", "kf_alg2", "kf_fused",
        "theta",
    ] {
        assert!(
            header.iter().any(|h| h == name),
            "missing column {name}: {header:?}"
        );
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("RMS [deg]") && stdout.contains("alg2"),
        "{stdout}"
    );
    // The raw pendulum beats the raw accelerometer under the scooter's vibration.
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let th = col("theta");
    let rms = |c: usize| {
        (rows
            .iter()
            .skip(500)
            .map(|r| (r[c] - r[th]).powi(2))
            .sum::<f64>()
            / (rows.len() - 500) as f64)
            .sqrt()
    };
    assert!(rms(col("pendulum")) < rms(col("accel")));
    // No --params: the default rig is said to be used.
    assert!(String::from_utf8_lossy(&o.stderr).contains("default rig"));
}

#[test]
fn mapped_names_and_degrees_give_the_same_estimates() {
    let d = tmp();
    let a = out_path(d.path(), "a.csv");
    let b = out_path(d.path(), "b.csv");
    write_log(&a, ["t", "phi", "gyro", "ax", "ay", "theta"], false, false);
    write_log(
        &b,
        ["time", "enc", "gz", "accx", "accy", "pot"],
        true,
        false,
    );
    let (oa, ob) = (out_path(d.path(), "oa.csv"), out_path(d.path(), "ob.csv"));
    let s = bin()
        .args([
            "estimate",
            a.to_str().unwrap(),
            "-o",
            oa.to_str().unwrap(),
            "-q",
        ])
        .status()
        .unwrap();
    assert!(s.success());
    let o = bin()
        .args([
            "estimate",
            b.to_str().unwrap(),
            "-o",
            ob.to_str().unwrap(),
            "--map",
            "t=time,phi=enc,gyro=gz,ax=accx,ay=accy,theta=pot",
            "--deg",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("phi <- enc (deg)"),
        "mapping is reported: {err}"
    );
    let (ha, ra) = read_csv(&oa);
    let (hb, rb) = read_csv(&ob);
    assert_eq!(ha, hb);
    assert_eq!(ra.len(), rb.len());
    let mut worst: f64 = 0.0;
    for (x, y) in ra.iter().zip(&rb) {
        for (u, v) in x.iter().zip(y) {
            worst = worst.max((u - v).abs());
        }
    }
    // Degrees written with 17 digits and converted back: rounding only.
    assert!(worst < 1e-9, "worst {worst}");
}

#[test]
fn output_in_degrees_and_flag_columns() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let (r, g) = (out_path(d.path(), "r.csv"), out_path(d.path(), "g.csv"));
    for (o, extra) in [(&r, vec![]), (&g, vec!["--out-deg", "--flags"])] {
        let mut args = vec![
            "estimate",
            log.to_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
            "-q",
            "--only",
            "pendulum,alg1",
        ];
        args.extend(extra);
        assert!(bin().args(&args).status().unwrap().success());
    }
    let text = std::fs::read_to_string(&g).unwrap();
    let header = text.lines().next().unwrap();
    assert_eq!(header, "t,pendulum,alg1,theta,pendulum_flags,alg1_flags");
    // The first sample starts the differentiator: flagged.
    assert!(text.lines().nth(1).unwrap().ends_with(",initialising"));
    let (_, rr) = read_csv(&r);
    let row = text.lines().nth(100).unwrap();
    let deg: f64 = row.split(',').nth(2).unwrap().parse().unwrap();
    assert!((deg - rr[99][2].to_degrees()).abs() < 1e-9);
}

#[test]
fn estimators_without_their_inputs_are_skipped_with_a_notice() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(&log, ["t", "phi", "gyro", "ax", "ay", "theta"], false, true);
    let out = out_path(d.path(), "est.csv");
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("skipped alg2: the log has no gyro"), "{err}");
    let (header, rows) = read_csv(&out);
    assert!(header.iter().any(|h| h == "alg1") && !header.iter().any(|h| h == "alg2"));
    assert_eq!(rows.len(), 3000);
}

#[test]
fn bad_input_is_a_clear_error_never_a_panic() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    std::fs::write(&log, "t,phi\n0,0.1\n0.001,abc\n").unwrap();
    let out = out_path(d.path(), "est.csv");
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("log.csv:3") && err.contains("phi") && err.contains("abc"),
        "{err}"
    );

    let rig = out_path(d.path(), "rig.toml");
    std::fs::write(&rig, "[pendulum]\nmass = -1.0\n").unwrap();
    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "--params",
            rig.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("rig.toml") && err.contains("pendulum.mass"),
        "{err}"
    );

    let o = bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--only",
            "alg9",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown estimator `alg9`"));
}

#[test]
fn a_rig_file_changes_the_estimates() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let rig = out_path(d.path(), "rig.toml");
    std::fs::write(&rig, "[differentiator]\ncutoff_hz = 15.0\n").unwrap();
    let (a, b) = (out_path(d.path(), "a.csv"), out_path(d.path(), "b.csv"));
    assert!(bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            a.to_str().unwrap(),
            "-q",
            "--only",
            "alg1"
        ])
        .status()
        .unwrap()
        .success());
    assert!(bin()
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            b.to_str().unwrap(),
            "-q",
            "--only",
            "alg1",
            "--params",
            rig.to_str().unwrap()
        ])
        .status()
        .unwrap()
        .success());
    let (_, ra) = read_csv(&a);
    let (_, rb) = read_csv(&b);
    let diff: f64 = ra
        .iter()
        .zip(&rb)
        .map(|(x, y)| (x[1] - y[1]).abs())
        .fold(0.0, f64::max);
    assert!(
        diff > 1e-3,
        "a 15 Hz differentiator must change alg1: {diff}"
    );
}

/// Every command that reads the rig (`estimate`, `fit`, `report`, `tune`), given a rig
/// holding `doubtful`, says each of `want` (`{rig}` stands for the rig's path) on standard
/// error; with `plausible` instead, `estimate` gives no warning.
fn doubted_by_every_command(doubtful: &str, want: &[&str], plausible: &str) {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let rig = dir.path().join("doubt.toml");
    std::fs::write(&rig, doubtful).unwrap();
    let out = dir.path().join("out");
    let run = |command: &str, extra: &[&str]| {
        let o = bin()
            .arg(command)
            .arg(&log)
            .arg("-p")
            .arg(&rig)
            .args(extra)
            .arg("-o")
            .arg(out.with_extension(command))
            .output()
            .unwrap();
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    for (command, extra) in [
        ("estimate", &["--only", "alg2_offset"][..]),
        ("fit", &[][..]),
        ("report", &[][..]),
        ("tune", &["--time-limit", "1"][..]),
    ] {
        let e = run(command, extra);
        for w in want {
            let w = w.replace("{rig}", rig.to_str().unwrap());
            assert!(e.contains(&w), "{command}: {w}: {e}");
        }
    }
    std::fs::write(&rig, plausible).unwrap();
    let e = run("estimate", &[]);
    assert!(!e.contains("warning"), "{e}");
}

#[test]
fn a_pivot_offset_in_millimetres_is_doubted_by_every_command_that_reads_the_rig() {
    // `pivot_offset = 50` meant 50 mm: read as 50 m it took alg2_offset 87 deg RMS off
    // (EKF 2.3, UKF 5.4 deg against 0.5) on a scooter ride, without a word.
    doubted_by_every_command(
        "[pendulum]\npivot_offset = 50\n",
        &[
            "warning: {rig}: pendulum.pivot_offset: a pivot offset l12 of 50 m is beyond 2 m",
            "if it was written in millimetres, write pendulum.pivot_offset = 0.05",
        ],
        "[pendulum]\npivot_offset = 0.05\n",
    );
}

#[test]
fn a_gyro_full_scale_in_deg_per_s_is_doubted_by_every_command_that_reads_the_rig() {
    // `[gyro] full_scale = 500` meant 500 deg/s: read as rad/s it switched off the clip
    // finder's "below the full scale" check and the plausibility bound, without a word;
    // `[accel] full_scale = 16` meant 16 g.
    doubted_by_every_command(
        "[gyro]\nfull_scale = 500\n[accel]\nfull_scale = 16\n",
        &[
            "warning: {rig}: gyro.full_scale: 500 rad/s is above 69.8 rad/s",
            "if it was written in deg/s, write gyro.full_scale = 8.72665",
            "warning: {rig}: accel.full_scale: 16 m/s^2 is below 19.6 m/s^2",
            "written in g? 16 g is 156.9 m/s^2: write accel.full_scale = 156.906",
        ],
        "[gyro]\nfull_scale = 8.73\n[accel]\nfull_scale = 156.9\n",
    );
}

#[test]
fn quoted_decimal_commas_are_named_with_a_command_that_converts_the_log() {
    // A spreadsheet's export: comma-separated, every cell quoted, numbers with a decimal
    // comma ("0,001","-0,026",...). Was: `not a number: `0,0``, and nothing to act on.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let text = std::fs::read_to_string(&log).unwrap();
    let quoted: String = text
        .lines()
        .map(|l| {
            let cells: Vec<String> = l
                .split(',')
                .map(|c| format!("\"{}\"", c.replace('.', ",")))
                .collect();
            cells.join(",") + "\n"
        })
        .collect();
    assert!(quoted.contains("e-") || quoted.contains("E-") || quoted.contains("\"0\""));
    let comma = dir.path().join("comma.csv");
    std::fs::write(&comma, &quoted).unwrap();
    let run = |command: &str, input: &Path, out: &str| {
        bin()
            .arg(command)
            .arg(input)
            .arg("-o")
            .arg(dir.path().join(out))
            .output()
            .unwrap()
    };
    let fix = pendtilt::io::DECIMAL_COMMA_FIX;
    let o = run("estimate", &comma, "e.csv");
    let e = String::from_utf8_lossy(&o.stderr);
    let at = format!(
        "{}:2: column 1 (`t`): not a number: `0,0`: ",
        comma.display()
    );
    assert!(!o.status.success() && e.contains(&at), "{e}");
    assert!(
        e.contains("a number with a decimal comma (quoted, \"0,0\"), and the log must use decimal points: convert it with `")
            && e.contains(fix),
        "{e}"
    );
    let o = run("filter", &comma, "f.csv");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success()
            && e.contains("'0,0' is not a number: a number with a decimal comma")
            && e.contains(fix),
        "{e}"
    );
    // The command as given, on this log: the estimates of the comma log are the plain
    // log's, byte for byte (the quoted header, and quoted cells without a comma, read as
    // they are).
    let converted = dir.path().join("log_points.csv");
    let cmd = fix
        .replace("log.csv", comma.to_str().unwrap())
        .replace("log_points.csv", converted.to_str().unwrap());
    let sh = std::process::Command::new("sh")
        .args(["-c", &cmd])
        .output()
        .unwrap();
    assert!(
        sh.status.success(),
        "{cmd}: {}",
        String::from_utf8_lossy(&sh.stderr)
    );
    for (command, out) in [("estimate", "csv"), ("filter", "f.csv")] {
        let a = run(command, &converted, &format!("a.{out}"));
        let b = run(command, &log, &format!("b.{out}"));
        for o in [&a, &b] {
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        let (a, b) = (
            std::fs::read(dir.path().join(format!("a.{out}"))).unwrap(),
            std::fs::read(dir.path().join(format!("b.{out}"))).unwrap(),
        );
        assert!(a.len() > 1000 && a == b, "{command}");
    }
    // A cell that is no number at all gets no such hint.
    std::fs::write(&comma, text.replacen("\n0.0,", "\nabc,", 1)).unwrap();
    let e = String::from_utf8_lossy(&run("estimate", &comma, "e.csv").stderr).into_owned();
    assert!(
        e.contains("not a number: `abc`") && !e.contains("decimal comma"),
        "{e}"
    );
}

#[test]
fn a_header_in_degrees_read_as_radians_is_named_and_the_unit_check_agrees() {
    // `phi (deg)` and `gyro[deg/s]` mapped without --deg: the name says it, line 1.
    let dir = tempfile::tempdir().unwrap();
    let deg = dir.path().join("deg.csv");
    let names = ["t", "phi (deg)", "gyro[deg/s]", "ax", "ay", "theta"];
    write_log(&deg, names, true, false);
    let rad = dir.path().join("rad.csv");
    write_log(
        &rad,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let run = |log: &Path, extra: &[&str], out: &str| {
        let o = bin()
            .arg("estimate")
            .arg(log)
            .args(extra)
            .arg("-o")
            .arg(dir.path().join(out))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let map = "phi=phi (deg),gyro=gyro[deg/s]";
    let e = run(&deg, &["--map", map], "a.csv");
    let at = |c: &str| format!("warning: {}:1: column `{c}`", deg.display());
    assert!(
        e.contains(&format!(
            "{} (gyro): its name says deg/s, and it is read in rad/s (no --deg): read it with \
             --deg gyro",
            at("gyro[deg/s]")
        )) && e.contains(&format!(
            "{} (phi): its name says degrees, and it is read in radians (no --deg): read it \
             with --deg phi",
            at("phi (deg)")
        )),
        "{e}"
    );
    // The unit check from the physics gives the same fix.
    assert!(
        e.contains("is gyro in deg/s? read it with --deg gyro"),
        "{e}"
    );
    // With the fix: no unit warning, and the radian log's estimates.
    let e = run(&deg, &["--map", map, "--deg", "phi,gyro,theta"], "b.csv");
    assert!(!e.contains("--deg"), "{e}");
    run(&rad, &[], "c.csv");
    let read = |f: &str| -> Vec<f64> {
        std::fs::read_to_string(dir.path().join(f))
            .unwrap()
            .lines()
            .skip(1)
            .flat_map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let (b, c) = (read("b.csv"), read("c.csv"));
    assert_eq!(b.len(), c.len());
    let worst = b
        .iter()
        .zip(&c)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst}");
}

/// The unit check runs in the log reader, for every command that reads a planar log.
/// Earlier, `fit --target gyro` on a gyro in deg/s "Converged" at its start (cost 17.5
/// rad/s) and wrote the rig without a word, `report` and `tune` said nothing either; only
/// `estimate` checked. Each now gives the same warning with the fix, and the summary counts
/// it; the same log in rad/s says nothing.
#[test]
fn every_command_that_reads_a_log_says_a_gyro_in_deg_per_s() {
    let dir = tempfile::tempdir().unwrap();
    let mut sc = Scenario::named("scooter").unwrap();
    sc.duration = 8.0;
    let rows = simulate(&sc, 3).unwrap();
    for (name, k) in [("deg.csv", 180.0 / std::f64::consts::PI), ("rad.csv", 1.0)] {
        let mut text = String::from("t,phi,gyro,ax,ay,theta\n");
        for r in &rows {
            text.push_str(&format!(
                "{:?},{:?},{:?},{:?},{:?},{:?}\n",
                r.t,
                r.phi,
                r.gyro * k,
                r.ax,
                r.ay,
                r.theta
            ));
        }
        let log = dir.path().join(name);
        std::fs::write(&log, text).unwrap();
        for (command, extra, out) in [
            ("estimate", &[][..], "e.csv"),
            ("fit", &["--target", "gyro"][..], "f.toml"),
            ("tune", &[][..], "t.toml"),
            ("report", &[][..], "rep"),
        ] {
            let out = dir.path().join(out);
            let o = common::run_on(command, &log, extra, common::s(&out));
            let e = common::stderr(&o);
            let said = e.contains(&format!("warning: {}: gyro is ", log.display()))
                && e.contains("is gyro in deg/s? read it with --deg gyro");
            assert_eq!(said, k != 1.0, "{command} on {name}: {e}");
        }
        // On the report's page the unit warning leads the few shown.
        let page = std::fs::read_to_string(dir.path().join("rep/index.html")).unwrap();
        assert_eq!(
            page.contains("which the figures below carry: ")
                && page.contains(&format!(
                    "which the figures below carry: {}: gyro is ",
                    log.display()
                )),
            k != 1.0,
            "{page}"
        );
    }
}

/// A time unit given is checked as one found: a 1 kHz log in seconds read with
/// `--time-unit ms` (planar and 3-D) is refused with the fix (it ran, ekf at 93 deg); the
/// same log with its time in ms runs with the option, and `--time-unit s` always runs.
#[test]
fn a_time_unit_given_is_judged_by_the_physics() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("s.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let out = dir.path().join("e.csv");
    let run = |log: &Path, unit: &str| {
        bin()
            .arg("estimate")
            .arg(log)
            .args(["--time-unit", unit, "-q", "-o"])
            .arg(&out)
            .output()
            .unwrap()
    };
    let o = run(&log, "ms");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains("column 1 (`t`): read with --time-unit ms")
            && e.contains("read as seconds it is 1000 Hz: drop --time-unit ms"),
        "{e}"
    );
    assert!(!out.exists());
    assert!(run(&log, "s").status.success());
    // The same rows with t in ms.
    let text = std::fs::read_to_string(&log).unwrap();
    let mut lines = text.lines();
    let mut ms = format!("{}\n", lines.next().unwrap());
    for l in lines {
        let (t, rest) = l.split_once(',').unwrap();
        ms.push_str(&format!("{},{rest}\n", t.parse::<f64>().unwrap() * 1000.0));
    }
    let log_ms = dir.path().join("ms.csv");
    std::fs::write(&log_ms, ms).unwrap();
    let o = run(&log_ms, "ms");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // 3-D: the same check.
    let log3 = dir.path().join("r3.csv");
    let o = bin()
        .args([
            "simulate",
            "--scenario",
            "still3d",
            "--duration",
            "2",
            "-q",
            "-o",
        ])
        .arg(&log3)
        .output()
        .unwrap();
    assert!(o.status.success());
    let o = run(&log3, "us");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{e}");
    assert!(e.contains("drop --time-unit us"), "{e}");
}

/// The planar error table leaves the start-up out: from 5 s after the first row by
/// default (a 3 s log has no row scored, and says how to score it), from `--score-from`
/// when given, and its RMS is the file's RMS over those rows.
#[test]
fn the_error_table_scores_from_score_from() {
    let d = tmp();
    let log = out_path(d.path(), "log.csv");
    write_log(
        &log,
        ["t", "phi", "gyro", "ax", "ay", "theta"],
        false,
        false,
    );
    let out = out_path(d.path(), "est.csv");
    let run = |extra: &[&str]| {
        let o = bin()
            .args([
                "estimate",
                log.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    // A 3 s log is scored whole by default (it is shorter than 10 s), and says so.
    let default = run(&[]);
    assert!(
        default.contains("t >= t0 + 0 s (3000 rows scored: the whole log, which lasts 3.0 s"),
        "{default}"
    );
    let beyond = run(&["--score-from", "5"]);
    assert!(
        beyond.contains("t >= t0 + 5 s (0 rows scored)")
            && beyond.contains("score earlier with --score-from SECONDS"),
        "{beyond}"
    );
    let table = run(&["--score-from", "1"]);
    assert!(
        table.contains("t >= t0 + 1 s (2000 rows scored)"),
        "{table}"
    );
    // ekf's RMS in the table is the file's over t >= 1 s (t0 = 0).
    let (header, rows) = read_csv(&out);
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let (t, e, th) = (col("t"), col("ekf"), col("theta"));
    let late: Vec<&Vec<f64>> = rows.iter().filter(|r| r[t] >= 1.0).collect();
    let rms = (late.iter().map(|r| (r[e] - r[th]).powi(2)).sum::<f64>() / late.len() as f64)
        .sqrt()
        .to_degrees();
    let line = table.lines().find(|l| l.starts_with("ekf ")).unwrap();
    let printed: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!((printed - rms).abs() < 1e-4, "{line} vs {rms}");
    let all = run(&["--score-from", "0"]);
    assert!(all.contains("(3000 rows scored)"), "{all}");
}
