//! No command destroys its inputs: every subcommand refuses an output
//! that is one of its inputs (same name, symlink, hard link), a run that fails half way
//! leaves an earlier output byte for byte, and a header-only log leaves no file behind.
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{pendtilt, s, stderr};
use pendtilt::config::RigConfig;
use pendtilt::sim::planar::{simulate, Scenario};

/// A directory with a 3 s sigmoid log (`t,phi,gyro,ax,ay,theta`) and a rig file.
struct Fixture {
    dir: tempfile::TempDir,
    log: PathBuf,
    rig: PathBuf,
}

impl Fixture {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("log.csv");
        std::fs::write(&log, log_text(None)).unwrap();
        let rig = dir.path().join("rig.toml");
        std::fs::write(&rig, RigConfig::default().to_toml_string()).unwrap();
        Self { dir, log, rig }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// The names in the directory (a stray temporary file would show here).
    fn names(&self) -> BTreeSet<String> {
        names_in(self.dir.path())
    }

    fn symlink(&self, to: &Path, name: &str) -> PathBuf {
        let p = self.path(name);
        std::os::unix::fs::symlink(to, &p).unwrap();
        p
    }

    fn hard_link(&self, to: &Path, name: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::hard_link(to, &p).unwrap();
        p
    }
}

fn names_in(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// The log text; `bad_line` (1-based file line) gets `abc` in the gyro column.
fn log_text(bad_line: Option<usize>) -> String {
    let mut sc = Scenario::named("sigmoid").unwrap();
    sc.duration = 3.0;
    let rows = simulate(&sc, 3).unwrap();
    let mut text = String::from("t,phi,gyro,ax,ay,theta\n");
    for (i, r) in rows.iter().enumerate() {
        let gyro = if bad_line == Some(i + 2) {
            "abc".to_string()
        } else {
            format!("{:?}", r.gyro)
        };
        text.push_str(&format!(
            "{:?},{:?},{gyro},{:?},{:?},{:?}\n",
            r.t, r.phi, r.ax, r.ay, r.theta
        ));
    }
    text
}

/// The command line of `command` reading the fixture's log (and rig) and writing `out`.
fn args<'a>(f: &'a Fixture, command: &'a str, log: &'a Path, out: &'a str) -> Vec<&'a str> {
    let mut a = vec![command, s(log)];
    if command != "filter" {
        a.extend(["-p", s(&f.rig)]);
    }
    a.extend(["-o", out]);
    if command != "filter" {
        a.push("-q");
    }
    a
}

fn assert_failed(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "exit code; stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// Runs `command` with `-o` onto `out` and checks it is refused naming both files, with
/// the log and the rig byte-identical and nothing new in the directory.
fn assert_refused(f: &Fixture, command: &str, out: &Path, input_opt: &str) {
    let (log0, rig0, names0) = (
        std::fs::read(&f.log).unwrap(),
        std::fs::read(&f.rig).unwrap(),
        f.names(),
    );
    let o = pendtilt(&args(f, command, &f.log, s(out)));
    let err = assert_failed(&o);
    assert!(
        err.contains(&format!("-o {}", out.display()))
            && err.contains("is the same file as")
            && err.contains(input_opt),
        "{command} -o {}: {err}",
        out.display()
    );
    assert_eq!(
        std::fs::read(&f.log).unwrap(),
        log0,
        "{command}: log changed"
    );
    assert_eq!(
        std::fs::read(&f.rig).unwrap(),
        rig0,
        "{command}: rig changed"
    );
    assert_eq!(f.names(), names0, "{command}: a file appeared or vanished");
}

#[test]
fn estimate_fit_filter_refuse_to_write_onto_an_input_or_a_link_to_it() {
    let f = Fixture::new();
    let log_sym = f.symlink(&f.log, "log-link.csv");
    let log_hard = f.hard_link(&f.log, "log-hard.csv");
    let rig_sym = f.symlink(&f.rig, "rig-link.toml");
    let rig_hard = f.hard_link(&f.rig, "rig-hard.toml");
    let dotted = f.dir.path().join(".").join("log.csv");
    for command in ["estimate", "fit", "filter"] {
        let input = if command == "filter" { "INPUT" } else { "LOG" };
        for out in [&f.log, &log_sym, &log_hard, &dotted] {
            assert_refused(&f, command, out, input);
        }
        if command != "filter" {
            for out in [&f.rig, &rig_sym, &rig_hard] {
                assert_refused(&f, command, out, "--params");
            }
        }
    }
}

#[test]
fn report_refuses_a_file_as_its_directory_and_a_directory_holding_an_input() {
    let f = Fixture::new();
    for out in [&f.log, &f.rig] {
        let before = std::fs::read(out).unwrap();
        let o = pendtilt(&args(&f, "report", &f.log, s(out)));
        let err = assert_failed(&o);
        assert!(err.contains("is a file, not a directory"), "{err}");
        assert_eq!(std::fs::read(out).unwrap(), before);
    }
    // The log hard-linked as `rep/report.md` (a file the report writes): refused after
    // the report was made in the staging directory, nothing moved in.
    let rep = f.path("rep");
    std::fs::create_dir(&rep).unwrap();
    let inside = rep.join("report.md");
    std::fs::hard_link(&f.log, &inside).unwrap();
    let log0 = std::fs::read(&f.log).unwrap();
    let names0 = f.names();
    let o = pendtilt(&args(&f, "report", &inside, s(&rep)));
    let err = assert_failed(&o);
    assert!(err.contains("report.md is the same file as LOG"), "{err}");
    assert_eq!(std::fs::read(&f.log).unwrap(), log0);
    assert_eq!(names_in(&rep), BTreeSet::from(["report.md".to_string()]));
    assert_eq!(f.names(), names0, "the staging directory is gone");
}

#[test]
fn simulate_refuses_to_write_onto_its_config_or_rig_or_one_output_twice() {
    let f = Fixture::new();
    let run = |extra: &[&str]| {
        let mut a = vec!["simulate", "--scenario", "still", "--duration", "0.2", "-q"];
        a.extend(extra);
        pendtilt(&a)
    };
    // A first run makes run.csv, run.rig.toml and run.scenario.toml.
    let first = f.path("run.csv");
    let o = run(&["-o", s(&first)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let scen = f.path("run.scenario.toml");
    let rig = f.path("run.rig.toml");
    let rig_link = f.symlink(&rig, "rig-link.toml");
    let other = f.path("other.csv");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        // The log onto the scenario file read by --config.
        (vec!["--config", s(&scen), "-o", s(&scen)], "--config"),
        // The scenario file written beside -o run.csv is the --config file itself.
        (vec!["--config", s(&scen), "-o", s(&first)], "--config"),
        (
            vec!["--rig", s(&rig), "-o", s(&other), "--rig-out", s(&rig)],
            "--rig",
        ),
        (vec!["--rig", s(&rig), "-o", s(&rig_link)], "--rig"),
        (vec!["--rig", s(&rig_link), "-o", s(&rig)], "--rig"),
        (vec!["-o", s(&other), "--rig-out", s(&other)], "-o"),
    ];
    for (extra, named) in cases {
        let before: Vec<Vec<u8>> = [&first, &scen, &rig]
            .iter()
            .map(|p| std::fs::read(p).unwrap())
            .collect();
        let names0 = f.names();
        let err = assert_failed(&run(&extra));
        assert!(
            err.contains("is the same file as") && err.contains(named),
            "{extra:?}: {err}"
        );
        for (p, b) in [&first, &scen, &rig].iter().zip(&before) {
            assert_eq!(
                &std::fs::read(p).unwrap(),
                b,
                "{extra:?} changed {}",
                p.display()
            );
        }
        assert_eq!(f.names(), names0, "{extra:?}");
    }
}

/// A bad cell at line 2,503: the run fails naming the line and says the earlier output is
/// unchanged, and it is, byte for byte; no temporary file is left.
#[test]
fn a_run_failing_half_way_leaves_the_earlier_output_as_it_was() {
    let f = Fixture::new();
    let bad = f.path("bad.csv");
    std::fs::write(&bad, log_text(Some(2503))).unwrap();
    for (command, out) in [
        ("estimate", "est.csv"),
        ("fit", "fit.toml"),
        ("filter", "filtered.csv"),
        ("report", "rep"),
    ] {
        let out = f.path(out);
        let o = pendtilt(&args(&f, command, &f.log, s(&out)));
        assert!(o.status.success(), "{command}: {}", stderr(&o));
        let earlier = if command == "report" {
            std::fs::read(out.join("report.json")).unwrap()
        } else {
            std::fs::read(&out).unwrap()
        };
        let names0 = f.names();
        let err = assert_failed(&pendtilt(&args(&f, command, &bad, s(&out))));
        assert!(err.contains("bad.csv:2503"), "{command}: {err}");
        let said = if command == "report" {
            format!(
                "nothing was written into {}; the files already there are unchanged",
                out.display()
            )
        } else {
            format!(
                "{} was not written; the earlier file is unchanged",
                out.display()
            )
        };
        assert!(err.contains(&said), "{command}: {err}");
        let now = if command == "report" {
            std::fs::read(out.join("report.json")).unwrap()
        } else {
            std::fs::read(&out).unwrap()
        };
        assert!(now == earlier, "{command}: the earlier output changed");
        assert_eq!(f.names(), names0, "{command}: a stray file");
    }
}

#[test]
fn a_header_only_log_leaves_no_file_behind() {
    let f = Fixture::new();
    let empty = f.path("empty.csv");
    std::fs::write(&empty, "t,phi,gyro,ax,ay,theta\n").unwrap();
    for (command, out) in [
        ("estimate", "est.csv"),
        ("fit", "fit.toml"),
        ("filter", "filtered.csv"),
        ("report", "rep"),
    ] {
        let names0 = f.names();
        let out = f.path(out);
        let err = assert_failed(&pendtilt(&args(&f, command, &empty, s(&out))));
        assert!(err.contains("empty.csv"), "{command}: {err}");
        assert!(
            err.contains(&format!("{} was not written", out.display())),
            "{command}: {err}"
        );
        assert_eq!(f.names(), names0, "{command} left a file behind");
    }
}

#[test]
fn output_on_stdout_still_works_and_an_existing_output_is_replaced_whole() {
    let f = Fixture::new();
    let o = pendtilt(&args(&f, "estimate", &f.log, "-"));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with("t,"), "{}", &text[..40.min(text.len())]);
    let input_lines = std::fs::read_to_string(&f.log).unwrap().lines().count();
    assert_eq!(
        text.lines().count(),
        input_lines,
        "header + one row per input row"
    );
    // Writing onto an older, longer file leaves exactly the new content.
    let out = f.path("est.csv");
    std::fs::write(&out, "x\n".repeat(100_000)).unwrap();
    let o = pendtilt(&args(&f, "estimate", &f.log, s(&out)));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    // Through a symlink to a file that is no input: the file is replaced, the link kept.
    let link = f.symlink(&out, "est-link.csv");
    let o = pendtilt(&args(&f, "filter", &f.log, s(&link)));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .starts_with("t,phi,gyro,ax,ay,theta\n"));
}

#[test]
fn unusable_output_paths_are_refused_before_any_work_and_dev_null_stays_a_device() {
    let f = Fixture::new();
    let sub = f.path("sub");
    std::fs::create_dir(&sub).unwrap();
    let names0 = f.names();
    let err = assert_failed(&pendtilt(&args(&f, "estimate", &f.log, s(&sub))));
    assert!(err.contains("is a directory; give a file name"), "{err}");
    let missing = f.path("nodir/est.csv");
    let err = assert_failed(&pendtilt(&args(&f, "fit", &f.log, s(&missing))));
    assert!(err.contains("nodir does not exist"), "{err}");
    let err = assert_failed(&pendtilt(&["reproduce", "-q", "--out", s(&f.log)]));
    assert!(err.contains("is a file, not a directory"), "{err}");
    assert_eq!(f.names(), names0);
    // /dev/null is written in place, not renamed over.
    let o = pendtilt(&args(&f, "estimate", &f.log, "/dev/null"));
    assert!(o.status.success(), "{}", stderr(&o));
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
}

/// Waits up to 10 s for a name in `dir` that `pred` accepts.
fn wait_for_name(dir: &Path, pred: impl Fn(&str) -> bool) -> Option<String> {
    let start = std::time::Instant::now();
    while start.elapsed() < std::time::Duration::from_secs(10) {
        if let Some(n) = names_in(dir).into_iter().find(|n| pred(n)) {
            return Some(n);
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    None
}

#[test]
fn an_interrupted_run_leaves_no_partial_output_behind() {
    use std::io::Write;
    // The log is a named pipe that stays open: the command reads its first rows, has its
    // partial output open and waits for more, deterministically, when the signal comes.
    // Before: Ctrl-C or SIGTERM left `.NAME.XXXXXX.partial` (a hidden file, or a staging
    // directory) as large as the run had got: 2.7 GB after 20 s of a long `simulate`.
    let text = log_text(None);
    let head: String = text.lines().take(500).map(|l| format!("{l}\n")).collect();
    for (command, out_name, sig) in [
        ("estimate", "est.csv", libc::SIGINT),
        ("report", "rep", libc::SIGTERM),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("log.fifo");
        let c = std::ffi::CString::new(s(&fifo)).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let out = dir.path().join(out_name);
        let child = common::bin()
            .args([command, s(&fifo), "-q", "-o", s(&out)])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Opening the pipe for writing waits for the command to open it for reading.
        let mut writer = std::fs::OpenOptions::new().write(true).open(&fifo).unwrap();
        writer.write_all(head.as_bytes()).unwrap();
        writer.flush().unwrap();
        let partial = wait_for_name(dir.path(), |n| n.ends_with(".partial"));
        assert!(partial.is_some(), "{command}: no partial output to remove");
        std::thread::sleep(std::time::Duration::from_millis(200));
        // SAFETY: signalling the child this test started.
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
        let o = child.wait_with_output().unwrap();
        drop(writer);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(128 + sig), "{command}: {e}");
        assert!(e.contains(&format!("interrupted (signal {sig})")), "{e}");
        assert!(e.contains("the partial output was removed"), "{e}");
        assert_eq!(
            names_in(dir.path()),
            BTreeSet::from(["log.fifo".to_string()]),
            "{command}: {e}"
        );
    }
    // A long simulation hung up while it writes: its log, rig and scenario files.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("long.csv");
    let child = common::bin()
        .args([
            "simulate",
            "--scenario",
            "scooter",
            "--duration=1e6",
            "-q",
            "-o",
            s(&out),
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let partial = wait_for_name(dir.path(), |n| n.starts_with(".long.csv."));
    assert!(partial.is_some(), "simulate: no partial output to remove");
    // SAFETY: signalling the child this test started.
    assert_eq!(
        unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGHUP) },
        0
    );
    let o = child.wait_with_output().unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(128 + libc::SIGHUP), "simulate: {e}");
    assert!(names_in(dir.path()).is_empty(), "simulate: {e}");
}

#[test]
fn report_moves_nothing_in_when_a_directory_blocks_one_of_its_files() {
    // A directory `rep/roll.svg` failed the move half way (files before it moved in) with
    // the io error printed twice; now refused before the first move.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("r3.csv");
    let o = pendtilt(&[
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "1",
        "-q",
        "-o",
        s(&log),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rep = dir.path().join("rep");
    std::fs::create_dir_all(rep.join("roll.svg")).unwrap();
    std::fs::write(rep.join("notes.txt"), "mine").unwrap();
    let o = pendtilt(&["report", s(&log), "--score-from", "0.5", "-o", s(&rep)]);
    let e = assert_failed(&o);
    assert!(
        e.contains("roll.svg is a directory, where this command writes a file of that name")
            && e.contains("nothing was written into"),
        "{e}"
    );
    assert_eq!(
        names_in(&rep),
        ["notes.txt", "roll.svg"].map(String::from).into()
    );
    assert_eq!(names_in(dir.path()).len(), 4, "{:?}", names_in(dir.path()));
}
