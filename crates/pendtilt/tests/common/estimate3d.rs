//! Shared by the estimate3d_cli tests: running the binary, simulating a 3-D log, reading
//! the written CSV and scoring it against the truth, and 3-D logs made wrong on purpose.
use super::{pendtilt, s, stderr};
use std::path::{Path, PathBuf};

pub fn ok(args: &[&str]) -> String {
    let out = pendtilt(args);
    assert!(out.status.success(), "pendtilt {args:?}: {}", stderr(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Simulates `scenario` into `dir` with `extra` options; the log's path.
pub fn simulate(dir: &Path, scenario: &str, extra: &[&str]) -> PathBuf {
    let log = dir.join(format!("{scenario}.csv"));
    let mut args = vec!["simulate", "--scenario", scenario, "-q", "-o", s(&log)];
    args.extend_from_slice(extra);
    ok(&args);
    log
}

/// The CSV as a header and rows of numbers (flags columns left out).
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .zip(&header)
                .filter(|(_, h)| !h.ends_with("_flags"))
                .map(|(v, _)| v.parse::<f64>().unwrap())
                .collect()
        })
        .collect();
    (header, rows)
}

pub const HEAD: &str = "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az";

/// A still, level log of `n` rows at 1 kHz with row `bad` replaced by `bad_row`.
pub fn level_log(n: usize, t_scale: f64, bad: Option<(usize, &str)>) -> String {
    let mut text = format!("{HEAD}\n");
    for k in 0..n {
        match bad {
            Some((b, row)) if b == k => text.push_str(row),
            _ => text.push_str(&format!(
                "{},0,0,0,0,0,0,0,9.80665",
                k as f64 * 1e-3 * t_scale
            )),
        }
        text.push('\n');
    }
    text
}

/// The printed RMS and max of estimator `name` from `estimate`'s score table.
pub fn printed(stdout: &str, name: &str) -> (f64, f64) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(&format!("{name} ")))
        .unwrap_or_else(|| panic!("no {name} row in {stdout}"));
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    (v[0], v[1])
}

/// What `estimate LOG -p RIG --only inv3d` says on standard error (it must succeed); the
/// estimates go beside the log.
pub fn inv3d_stderr(log: &Path, rig: &Path) -> String {
    let out = log.with_file_name("inv3d_est.csv");
    let o = pendtilt(&[
        "estimate",
        s(log),
        "-p",
        s(rig),
        "--only",
        "inv3d",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    stderr(&o)
}
