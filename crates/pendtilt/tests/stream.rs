//! `pendtilt stream`: log lines fed slowly through a pipe; every estimate
//! line must come out before the next input line is sent.
//!
//! No timing is assumed beyond a generous per-line timeout (10 s): the test waits for each
//! output line, so a slow machine only makes it slower, and a tool that buffers its output
//! fails it deterministically (the line never comes while its input is held back).
use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use pendtilt::sim::planar::{simulate, Scenario};

const TIMEOUT: Duration = Duration::from_secs(10);

struct Child {
    child: std::process::Child,
    stdin: Option<std::process::ChildStdin>,
    lines: mpsc::Receiver<String>,
}

impl Child {
    fn spawn(args: &[&str]) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
            .arg("stream")
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let stdin = child.stdin.take();
        Self {
            child,
            stdin,
            lines,
        }
    }

    fn send(&mut self, line: &str) {
        let stdin = self.stdin.as_mut().unwrap();
        stdin.write_all(line.as_bytes()).unwrap();
        stdin.write_all(b"\n").unwrap();
        stdin.flush().unwrap();
    }

    fn next_line(&self, what: &str) -> String {
        match self.lines.recv_timeout(TIMEOUT) {
            Ok(l) => l,
            Err(e) => panic!("no output line for {what} within {TIMEOUT:?}: {e}"),
        }
    }

    /// Closes stdin, waits for the exit; returns (status, stderr, remaining stdout lines).
    fn finish(mut self) -> (std::process::ExitStatus, String, Vec<String>) {
        drop(self.stdin.take());
        let mut stderr = String::new();
        use std::io::Read;
        self.child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut stderr)
            .unwrap();
        let status = self.child.wait().unwrap();
        let rest: Vec<String> = self.lines.try_iter().collect();
        (status, stderr, rest)
    }
}

fn sim_lines(n_secs: f64) -> Vec<String> {
    let mut s = Scenario::named("scooter").unwrap();
    s.duration = n_secs;
    simulate(&s, 3)
        .unwrap()
        .iter()
        .map(|r| format!("{},{},{},{},{},{}", r.t, r.phi, r.gyro, r.ax, r.ay, r.theta))
        .collect()
}

#[test]
fn every_estimate_line_arrives_before_the_next_input_line() {
    let data = sim_lines(0.06);
    let mut c = Child::spawn(&["--flags", "-q"]);
    c.send("t,phi,gyro,ax,ay,theta");
    // The output header comes as soon as the input header is in.
    let header = c.next_line("the header");
    assert!(header.starts_with("t,accel,pendulum,alg1,alg2"), "{header}");
    assert!(
        header.contains("theta") && header.contains("alg2_flags"),
        "{header}"
    );
    let ncol = header.split(',').count();
    for (k, line) in data.iter().enumerate() {
        c.send(line);
        // Slow feed: nothing more is sent until this sample's estimate is out.
        let out = c.next_line(&format!("input row {k}"));
        let fields: Vec<&str> = out.split(',').collect();
        assert_eq!(fields.len(), ncol, "{out}");
        let t_in: f64 = line.split(',').next().unwrap().parse().unwrap();
        let t_out: f64 = fields[0].parse().unwrap();
        assert_eq!(t_out, t_in, "row {k}: estimate for another sample");
        // Nothing else is pending: exactly one line per input line.
        assert!(
            c.lines.try_recv().is_err(),
            "more than one line for row {k}"
        );
        if k % 20 == 0 {
            std::thread::sleep(Duration::from_millis(5));
        }
    }
    let (status, stderr, rest) = c.finish();
    assert!(status.success(), "{stderr}");
    assert!(rest.is_empty(), "{rest:?}");
}

#[test]
fn stream_matches_estimate_on_the_same_log() {
    let data = sim_lines(0.5);
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("ride.csv");
    let out = dir.path().join("est.csv");
    let mut text = String::from("t,phi,gyro,ax,ay,theta\n");
    for l in &data {
        text.push_str(l);
        text.push('\n');
    }
    std::fs::write(&log, &text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args(["estimate", "-q", "--flags", "-o"])
        .arg(&out)
        .arg(&log)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut c = Child::spawn(&["--flags", "-q"]);
    c.stdin
        .as_mut()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let mut got = vec![c.next_line("the header")];
    for k in 0..data.len() {
        got.push(c.next_line(&format!("row {k}")));
    }
    let (status, stderr, rest) = c.finish();
    assert!(status.success(), "{stderr}");
    assert!(rest.is_empty());
    let want: Vec<String> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    assert_eq!(got, want);
}

/// A glitch on a live feed (a cell that is no number, a line with too many fields) is
/// skipped and flagged: one output row of NaN flagged `bad_line`, said on standard error
/// with its line, and the stream goes on (it used to end there with exit 1). What a live
/// feed cannot recover from (the header again: a logger that restarted) still stops it.
#[test]
fn a_bad_line_is_skipped_flagged_and_the_stream_goes_on() {
    let mut c = Child::spawn(&["--only", "pendulum", "--flags"]);
    c.send("t,phi");
    assert_eq!(c.next_line("the header"), "t,pendulum,pendulum_flags");
    c.send("0,0.1");
    assert_eq!(c.next_line("row 0"), "0.0,0.1,");
    c.send("0.001,abc");
    assert_eq!(c.next_line("the bad cell"), "NaN,NaN,bad_line");
    c.send("0.002,0.2");
    assert_eq!(c.next_line("row 2"), "0.002,0.2,");
    c.send("0.003,0.3,7,8");
    assert_eq!(c.next_line("the long line"), "NaN,NaN,bad_line");
    c.send("0.004,0.4");
    assert_eq!(c.next_line("row 4"), "0.004,0.4,");
    c.send("t,phi");
    let (status, stderr, rest) = c.finish();
    assert!(
        stderr.contains("<stdin>:3: column 2 (`phi`): not a number: `abc`: the line is skipped; its output row is NaN, flagged bad_line"),
        "{stderr}"
    );
    assert!(
        stderr.contains("<stdin>:5: 4 fields, the header has 2: the line is skipped"),
        "{stderr}"
    );
    assert!(!status.success());
    assert_ne!(status.code(), Some(101), "{stderr}");
    assert!(stderr.contains("<stdin>:7"), "{stderr}");
    assert!(rest.is_empty(), "{rest:?}");
}

#[test]
fn missing_and_wrapped_samples_stream_flagged() {
    let mut c = Child::spawn(&["--only", "pendulum,alg1", "--flags", "-q"]);
    c.send("t,phi");
    assert_eq!(
        c.next_line("the header"),
        "t,pendulum,alg1,pendulum_flags,alg1_flags"
    );
    c.send("0,0.1");
    c.next_line("row 0");
    c.send("0.001,nan");
    let l = c.next_line("row 1");
    assert!(l.ends_with("sample_missing,sample_missing"), "{l}");
    c.send(&format!("0.002,{}", 0.1 + std::f64::consts::TAU));
    let l = c.next_line("row 2");
    assert!(l.contains("encoder_wrapped"), "{l}");
    let (status, stderr, _) = c.finish();
    assert!(status.success(), "{stderr}");
}

#[test]
fn a_line_the_input_ends_in_streams_with_its_cut_cell_missing() {
    // The producer stopped in the middle of a line: `0.004,-0.02` was `0.004,-0.0215,...`.
    // Its row still comes out, the cut `phi` missing and flagged (earlier: it was read
    // as -0.02 and the pendulum estimate moved to it).
    let mut text = String::from("t,phi,gyro,ax,ay\n");
    for k in 0..4 {
        text.push_str(&format!("{},-0.0215,0,0,9.80665\n", k as f64 * 1e-3));
    }
    text.push_str("0.004,-0.02");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args(["stream", "--only", "pendulum", "--flags"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success());
    let out = String::from_utf8(o.stdout).unwrap();
    let last = out.lines().last().unwrap();
    assert_eq!(last, "0.004,-0.0215,sample_missing", "{out}");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("<stdin>:6: 2 fields, the header has 5 (a truncated line?)")
            && e.contains("its last cell `-0.02` (field 2, `phi`) may be cut short"),
        "{e}"
    );
}

/// A 3-D log streams through the 3-D estimators, told by its header: each row out before
/// the next line is sent, a bad line skipped and flagged, and, fed at once, the same
/// estimates as `estimate` on the file.
#[test]
fn a_3d_log_streams_live_through_the_3d_estimators() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = d.join("s3.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args([
            "simulate",
            "--scenario",
            "scooter3d",
            "--duration",
            "0.5",
            "-q",
            "-o",
        ])
        .arg(&log)
        .output()
        .unwrap();
    assert!(o.status.success());
    let rig = d.join("s3.rig.toml");
    let text = std::fs::read_to_string(&log).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap();
    let data: Vec<&str> = lines.collect();
    let mut c = Child::spawn(&["--params", rig.to_str().unwrap(), "--flags"]);
    c.send(head);
    let header = c.next_line("the header");
    assert!(
        header.starts_with("t,pendulum3d_roll,pendulum3d_pitch,"),
        "{header}"
    );
    assert!(header.contains("ekf3d_flags"), "{header}");
    let ncol = header.split(',').count();
    for (k, line) in data.iter().take(80).enumerate() {
        if k == 40 {
            c.send("0.04,1,2,abc,4,5,6,7,8");
            let out = c.next_line("the bad line");
            assert!(out.starts_with("NaN,") && out.contains("bad_line"), "{out}");
        }
        c.send(line);
        let out = c.next_line(&format!("input row {k}"));
        let fields: Vec<&str> = out.split(',').collect();
        assert_eq!(fields.len(), ncol, "{out}");
        assert_eq!(fields[0], line.split(',').next().unwrap(), "row {k}");
        assert!(
            c.lines.try_recv().is_err(),
            "more than one line for row {k}"
        );
    }
    let (status, stderr, _) = c.finish();
    assert!(status.success(), "{stderr}");
    assert!(
        stderr.contains("<stdin>:42: column 4 (`gyro_x`): not a number: `abc`")
            && stderr.contains("flagged bad_line"),
        "{stderr}"
    );
    // All at once: the file's estimates, byte for byte.
    let est = d.join("est.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .arg("estimate")
        .arg(&log)
        .args(["--params", rig.to_str().unwrap(), "--flags", "-q", "-o"])
        .arg(&est)
        .output()
        .unwrap();
    assert!(o.status.success());
    let o = Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args(["stream", "--params", rig.to_str().unwrap(), "--flags", "-q"])
        .stdin(std::fs::File::open(&log).unwrap())
        .output()
        .unwrap();
    assert!(o.status.success());
    assert_eq!(
        String::from_utf8(o.stdout).unwrap(),
        std::fs::read_to_string(&est).unwrap()
    );
}
