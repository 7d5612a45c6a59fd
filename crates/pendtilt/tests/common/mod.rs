//! Shared by the sim_* and cli_* tests: running the binary, writing fixtures, an ideal
//! simulated scenario and a sine fit; and, one module per subject, what the tests split
//! over a folder of files share.
#![allow(dead_code)]
pub mod cli_estimate;
pub mod estimate3d;
pub mod faults3d;
pub mod log_reader;
pub mod plausibility;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use pendtilt::sim::planar::motion::Motion;
use pendtilt::sim::planar::Scenario;

/// The `pendtilt` binary built for the tests.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pendtilt"))
}

/// Runs `pendtilt args..`.
pub fn pendtilt(args: &[&str]) -> Output {
    bin().args(args).output().expect("run the pendtilt binary")
}

/// Runs `pendtilt command input extra.. -o out`.
pub fn run_on(command: &str, input: &Path, extra: &[&str], out: &str) -> Output {
    bin()
        .arg(command)
        .arg(input)
        .args(extra)
        .args(["-o", out])
        .output()
        .expect("run the pendtilt binary")
}

/// Standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A path as `&str` (the tests' temporary paths are UTF-8).
pub fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// Writes `text` to `dir/name`.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A scenario with `motion`, ideal sensors and no vibration.
pub fn ideal(motion: Motion, duration: f64) -> Scenario {
    let mut s = Scenario::with_motion(motion, duration);
    s.sensors = s.sensors.ideal();
    s
}

/// Least-squares fit of x = A sin(w t + p) + c; returns (A, p, c).
pub fn fit_sine(rows: &[(f64, f64)], w: f64) -> (f64, f64, f64) {
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for &(t, x) in rows {
        let f = [(w * t).sin(), (w * t).cos(), 1.0];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += f[i] * f[j];
            }
            r[i] += f[i] * x;
        }
    }
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    let solve = |k: usize| {
        let mut mk = m;
        for i in 0..3 {
            mk[i][k] = r[i];
        }
        det(&mk) / d
    };
    let (a, b, c) = (solve(0), solve(1), solve(2));
    (a.hypot(b), b.atan2(a), c)
}
