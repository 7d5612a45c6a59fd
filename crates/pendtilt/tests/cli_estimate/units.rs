//! Units the rig or the log gets wrong, doubted by every command that reads them: a pivot
//! offset in millimetres, a gyro in deg/s, decimal commas, degrees read as radians, a
//! time unit judged by the physics.
use crate::common::bin;
use crate::common::cli_estimate::write_log;
use pendtilt::sim::planar::{simulate, Scenario};
use std::path::Path;

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
    let quoted = spreadsheet_export(&text);
    assert!(quoted.contains("e-") || quoted.contains("E-") || quoted.contains("\"0\""));
    let comma = dir.path().join("comma.csv");
    std::fs::write(&comma, &quoted).unwrap();
    let run = |command: &str, input: &Path, out: &str| run_to(dir.path(), command, input, out);
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
    the_fix_reads_as_the_plain_log(dir.path(), &comma, &log);
    // A cell that is no number at all gets no such hint.
    std::fs::write(&comma, text.replacen("\n0.0,", "\nabc,", 1)).unwrap();
    let e = String::from_utf8_lossy(&run("estimate", &comma, "e.csv").stderr).into_owned();
    assert!(
        e.contains("not a number: `abc`") && !e.contains("decimal comma"),
        "{e}"
    );
}

/// `text` as a spreadsheet exports it: every cell quoted, numbers with a decimal comma.
fn spreadsheet_export(text: &str) -> String {
    text.lines()
        .map(|l| {
            let cells: Vec<String> = l
                .split(',')
                .map(|c| format!("\"{}\"", c.replace('.', ",")))
                .collect();
            cells.join(",") + "\n"
        })
        .collect()
}

/// Runs `pendtilt command input -o dir/out`.
fn run_to(dir: &Path, command: &str, input: &Path, out: &str) -> std::process::Output {
    bin()
        .arg(command)
        .arg(input)
        .arg("-o")
        .arg(dir.join(out))
        .output()
        .unwrap()
}

/// The command the hint gives, on the comma log: the estimates of the comma log are the
/// plain log's, byte for byte (the quoted header, and quoted cells without a comma, read
/// as they are).
fn the_fix_reads_as_the_plain_log(dir: &Path, comma: &Path, log: &Path) {
    let fix = pendtilt::io::DECIMAL_COMMA_FIX;
    let run = |command: &str, input: &Path, out: &str| run_to(dir, command, input, out);
    let converted = dir.join("log_points.csv");
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
        let b = run(command, log, &format!("b.{out}"));
        for o in [&a, &b] {
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        let (a, b) = (
            std::fs::read(dir.join(format!("a.{out}"))).unwrap(),
            std::fs::read(dir.join(format!("b.{out}"))).unwrap(),
        );
        assert!(a.len() > 1000 && a == b, "{command}");
    }
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
            let o = crate::common::run_on(command, &log, extra, crate::common::s(&out));
            let e = crate::common::stderr(&o);
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
