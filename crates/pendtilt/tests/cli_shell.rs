//! The conventions of a Unix tool: shell completions and man pages generated from the
//! command line's own definition, `--version` with the commit, and a pipe whose reader
//! stops early ending the run quietly.
use std::io::{BufRead, BufReader};
use std::process::Stdio;

mod common;
use common::{bin, pendtilt, s, stderr};

const SUBCOMMANDS: [&str; 13] = [
    "rig",
    "batch",
    "estimate",
    "filter",
    "simulate",
    "fit",
    "report",
    "replay",
    "reproduce",
    "stream",
    "tune",
    "completions",
    "man",
];

fn stdout_of(args: &[&str]) -> String {
    let o = pendtilt(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn completions_know_every_subcommand_and_option() {
    let bash = stdout_of(&["completions", "bash"]);
    assert!(bash.contains("_pendtilt()"), "{bash}");
    for c in SUBCOMMANDS {
        assert!(bash.contains(c), "bash completion lacks {c}");
    }
    // An option of one subcommand, and the values of an enumerated one.
    assert!(bash.contains("--vibration") && bash.contains("--time-unit"));
    let zsh = stdout_of(&["completions", "zsh"]);
    assert!(
        zsh.starts_with("#compdef pendtilt"),
        "{}",
        &zsh[..40.min(zsh.len())]
    );
    let fish = stdout_of(&["completions", "fish"]);
    assert!(fish.contains("complete -c pendtilt"), "{fish}");
    let o = pendtilt(&["completions", "tcsh"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("possible values"), "{}", stderr(&o));
}

#[test]
fn the_man_pages_describe_every_subcommand() {
    let page = stdout_of(&["man"]);
    assert!(
        page.contains(".TH pendtilt 1"),
        "{}",
        &page[..200.min(page.len())]
    );
    for c in SUBCOMMANDS {
        assert!(page.contains(c), "pendtilt(1) lacks {c}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("man");
    let o = pendtilt(&["man", "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    for c in ["estimate", "replay", "tune"] {
        let p = std::fs::read_to_string(out.join(format!("pendtilt-{c}.1"))).unwrap();
        assert!(p.contains(&format!("pendtilt\\-{c}")), "{p}");
    }
    let estimate = std::fs::read_to_string(out.join("pendtilt-estimate.1")).unwrap();
    assert!(estimate.contains("\\-\\-params"), "{estimate}");
    // -o - is no directory: refused, none named `-` made.
    let o = bin()
        .current_dir(dir.path())
        .args(["man", "-o", "-"])
        .output()
        .unwrap();
    assert!(
        !o.status.success() && stderr(&o).contains("-o -"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("-").exists());
}

#[test]
fn the_version_names_the_commit() {
    let v = stdout_of(&["--version"]);
    let want = format!("pendtilt {} (", env!("CARGO_PKG_VERSION"));
    assert!(v.starts_with(&want), "{v}");
    let commit = v
        .trim_end()
        .trim_end_matches(')')
        .rsplit('(')
        .next()
        .unwrap();
    assert!(
        commit == "unknown" || commit.trim_end_matches("-dirty").len() >= 7,
        "{v}"
    );
}

/// `pendtilt simulate ... -o - | head -1`: the reader goes after one line; the run ends
/// with success and says nothing (it used to end "error: ... Broken pipe", exit 1).
#[test]
fn a_reader_that_stops_early_ends_the_run_quietly() {
    for args in [
        &[
            "simulate",
            "--scenario",
            "scooter",
            "--duration",
            "30",
            "-q",
            "-o",
            "-",
        ][..],
        &[
            "simulate",
            "--scenario",
            "scooter3d",
            "--duration",
            "30",
            "-q",
            "-o",
            "-",
        ][..],
    ] {
        let mut child = bin()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        assert!(first.starts_with("t,"), "{first}");
        // The reader is dropped here: the pipe closes with rows still to come.
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("error"), "{args:?}: {}", stderr(&o));
    }
}

/// Runs `script` in sh with `$P` the binary, in `dir`; returns (stdout, stderr).
fn sh(dir: &std::path::Path, script: &str) -> (String, String) {
    let o = std::process::Command::new("sh")
        .args(["-c", &format!("set -e\n{script}")])
        .env("P", env!("CARGO_BIN_EXE_pendtilt"))
        .current_dir(dir)
        .output()
        .unwrap();
    let (out, err) = (
        String::from_utf8(o.stdout).unwrap(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    );
    assert!(o.status.success(), "{script}: {err}");
    (out, err)
}

/// With `-o -` standard output carries the data alone: the summaries (the error table,
/// the fit's verdict, tune's findings) go to standard error, so that the next command of
/// a pipe reads a clean CSV or TOML (the error table used to follow the CSV, and `fit` and
/// `tune` put their summaries before the TOML).
#[test]
fn with_o_dash_standard_output_is_the_data_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // simulate | estimate | a second estimate's input check: every line a CSV row.
    let (csv, err) = sh(
        d,
        "$P simulate --scenario scooter --duration 3 -q -o - | $P estimate /dev/stdin -o -",
    );
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3001, "{}", lines.last().unwrap());
    let width = lines[0].split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == width));
    assert!(
        err.contains("RMS [deg]"),
        "the error table goes to stderr: {err}"
    );
    std::fs::write(d.join("est.csv"), &csv).unwrap();
    let (fir, _) = sh(d, "$P filter est.csv --order 50 --cutoff 20 -o -");
    assert_eq!(fir.lines().count(), 3001);
    // fit -o - | estimate --params /dev/stdin: the TOML alone on the pipe.
    sh(
        d,
        "$P simulate --scenario scooter --duration 20 -q -o ride.csv",
    );
    let (toml, err) = sh(d, "$P fit ride.csv -o -");
    assert!(toml.starts_with('#') || toml.starts_with('['), "{toml}");
    assert!(!toml.contains("Converged"), "{toml}");
    assert!(err.contains("natural frequency"), "{err}");
    let (est, _) = sh(
        d,
        "$P fit ride.csv -o - -q | $P estimate ride.csv --params /dev/stdin -o - -q",
    );
    assert_eq!(est.lines().count(), 20001);
    let (tuned, err) = sh(d, "$P tune ride.csv -o -");
    assert!(
        tuned
            .lines()
            .all(|l| l.is_empty() || l.starts_with('#') || l.starts_with('[') || l.contains('=')),
        "{tuned}"
    );
    assert!(!err.is_empty());
    toml_parses(&tuned);
    // 3-D: the score table on stderr too.
    sh(
        d,
        "$P simulate --scenario still3d --duration 3 -q -o s3.csv",
    );
    let (csv3, err3) = sh(d, "$P estimate s3.csv --params s3.rig.toml -o -");
    assert!(csv3.lines().all(|l| !l.contains("RMS")), "{csv3}");
    assert!(err3.contains("RMS"), "{err3}");
}

fn toml_parses(text: &str) {
    let v: Result<toml::Value, _> = toml::from_str(text);
    assert!(v.is_ok(), "{text}");
}

/// A log large enough to take a while gets a progress line on a terminal only: with
/// standard error a pipe (as here, and in CI or a script) nothing of it is written.
#[test]
fn no_progress_line_reaches_a_pipe() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sh(
        d,
        "$P simulate --scenario scooter --duration 120 -q -o big.csv",
    );
    assert!(std::fs::metadata(d.join("big.csv")).unwrap().len() > 10_000_000);
    let (_, err) = sh(d, "$P estimate big.csv --only pendulum -o est.csv");
    assert!(!err.contains("estimating"), "{err}");
    assert!(err.contains("120000 rows"), "{err}");
}

/// `-` reads standard input: `simulate | estimate - | filter -` in one pipe (filter reads
/// its input twice, so a pipe is copied first), a 3-D log too (told from its header,
/// which a pipe shows only once), and an error names `<stdin>` with its line.
#[test]
fn a_dash_reads_standard_input_planar_and_3d() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (csv, err) = sh(
        d,
        "$P simulate --scenario scooter --duration 3 -q -o - | $P estimate - -o - | \
         $P filter - --order 50 --cutoff 20 -o -",
    );
    assert_eq!(csv.lines().count(), 3001, "{err}");
    assert!(csv.starts_with("t,accel,pendulum,"), "{}", &csv[..80]);
    assert!(
        err.contains("<stdin>: columns: t, phi, gyro, ax, ay, theta"),
        "{err}"
    );
    // 3-D through standard input and through a pipe named as a file: the same estimates
    // as from the file.
    sh(
        d,
        "$P simulate --scenario still3d --duration 3 -q -o s3.csv",
    );
    let (file, _) = sh(d, "$P estimate s3.csv --params s3.rig.toml -q -o -");
    let (piped, _) = sh(d, "cat s3.csv | $P estimate - --params s3.rig.toml -q -o -");
    assert_eq!(file, piped);
    assert!(file.starts_with("t,pendulum3d_roll,"), "{}", &file[..60]);
    let (fifo, _) = sh(
        d,
        "mkfifo f.csv; cat s3.csv > f.csv & $P estimate f.csv --params s3.rig.toml -q -o -",
    );
    assert_eq!(file, fifo);
    // A bad cell on standard input: named `<stdin>`, its line and column.
    let o = std::process::Command::new("sh")
        .args([
            "-c",
            "printf 't,phi,gyro\\n0,0.1,0\\n0.001,abc,0\\n' | $P estimate - -o -",
        ])
        .env("P", env!("CARGO_BIN_EXE_pendtilt"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("<stdin>:3: column 2 (`phi`): not a number: `abc`"),
        "{e}"
    );
}

/// `--summary FILE` takes the summary (the error table, what was written, a fit's report)
/// off the terminal into FILE; warnings and notes stay on standard error; FILE may not be
/// one of the command's files.
#[test]
fn the_summary_goes_to_the_summary_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sh(
        d,
        "$P simulate --scenario scooter --duration 12 -o ride.csv --summary sim.txt",
    );
    let sim = std::fs::read_to_string(d.join("sim.txt")).unwrap();
    assert!(sim.starts_with("wrote 12000 rows"), "{sim}");
    let (out, err) = sh(d, "$P estimate ride.csv -o est.csv --summary est.txt");
    assert!(out.is_empty(), "stdout: {out}");
    assert!(err.contains("note: no --params"), "notes stay: {err}");
    assert!(!err.contains("RMS") && !err.contains("rows ->"), "{err}");
    let table = std::fs::read_to_string(d.join("est.txt")).unwrap();
    assert!(table.starts_with("12000 rows -> est.csv"), "{table}");
    assert!(table.contains("t >= t0 + 5 s (7000 rows scored)") && table.contains("RMS [deg]"));
    // With -o - the data alone on standard output, the report in the file.
    let (toml, err) = sh(d, "$P fit ride.csv -o - --summary fit.txt");
    toml_parses(&toml);
    assert!(!err.contains("natural frequency"), "{err}");
    let fit = std::fs::read_to_string(d.join("fit.txt")).unwrap();
    assert!(fit.contains("natural frequency"), "{fit}");
    // Never onto an input (nor a link to it), nor onto standard output.
    let before = std::fs::read(d.join("ride.csv")).unwrap();
    std::os::unix::fs::symlink(d.join("ride.csv"), d.join("link.csv")).unwrap();
    for target in ["ride.csv", "link.csv", "-"] {
        let o = bin()
            .current_dir(d)
            .args(["estimate", "ride.csv", "-o", "e2.csv", "--summary", target])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{target}: {err}");
        assert!(err.contains("--summary"), "{err}");
        assert!(!d.join("e2.csv").exists());
    }
    assert_eq!(std::fs::read(d.join("ride.csv")).unwrap(), before);
}
