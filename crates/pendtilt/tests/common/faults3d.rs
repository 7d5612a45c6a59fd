//! Shared by the faults3d tests: the simulated ride's CSV and its edits, running
//! `pendtilt estimate` on it, and how each estimator came through against the fault-free
//! run and the truth.
use super::{pendtilt, s, stderr};
use pendtilt::bank::spatial::REGISTRY3D;
use pendtilt::core::spatial::attitude::inclination_error;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// When every fault starts \[s\].
pub const T_FAULT: f64 = 8.0;

/// The recovery bound \[deg\].
pub const BOUND_DEG: f64 = 0.05;

/// The second criterion (against the truth): from 2 s after a fault's end to the log's end,
/// an estimator's inclination RMS error may exceed its fault-free run's over the same rows by
/// at most this fraction of it plus [`TRUTH_ABS_DEG`] (docs/reliability.md section 8 gives
/// the reasons).
pub const TRUTH_REL: f64 = 0.10;

/// See [`TRUTH_REL`] \[deg\].
pub const TRUTH_ABS_DEG: f64 = 0.01;

/// Clip levels of the saturation cases: below the ride's largest readings (gyro up to
/// 0.27 rad/s, |az| up to 21 m/s^2), so the clip bites on a quarter of the samples or more.
pub const GYRO_CLIP: f64 = 0.1;

/// A log as header and text cells (the faults edit cells as text).
#[derive(Clone)]
pub struct Csv {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Csv {
    pub fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines();
        let header = lines.next().unwrap().split(',').map(String::from).collect();
        let rows = lines
            .map(|l| l.split(',').map(String::from).collect())
            .collect();
        Self { header, rows }
    }

    pub fn write(&self, path: &Path) {
        let mut out = self.header.join(",");
        out.push('\n');
        for r in &self.rows {
            out.push_str(&r.join(","));
            out.push('\n');
        }
        std::fs::write(path, out).unwrap();
    }

    pub fn col(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    }

    /// The first and the last row where `self` differs from `other`.
    pub fn differs(&self, other: &Csv) -> Option<(usize, usize)> {
        let d: Vec<usize> = (0..self.rows.len().min(other.rows.len()))
            .filter(|&i| self.rows[i] != other.rows[i])
            .collect();
        Some((*d.first()?, *d.last()?))
    }

    pub fn t(&self, row: usize) -> f64 {
        self.rows[row][0].parse().unwrap()
    }

    /// The first row at or after `t`.
    pub fn row_at(&self, t: f64) -> usize {
        (0..self.rows.len()).find(|&i| self.t(i) >= t).unwrap()
    }

    /// Applies `f` to the cells of `columns` on the rows with `from <= t < to`.
    pub fn edit(&mut self, columns: &[&str], from: f64, to: f64, f: impl Fn(f64) -> String) {
        let cols: Vec<usize> = columns.iter().map(|c| self.col(c)).collect();
        for i in 0..self.rows.len() {
            let t = self.t(i);
            if t >= from && t < to {
                for &c in &cols {
                    let v: f64 = self.rows[i][c].parse().unwrap_or(f64::NAN);
                    self.rows[i][c] = f(v);
                }
            }
        }
    }

    /// Clips the cells of `columns` beyond +-`level` on the rows with `from <= t < to`
    /// (the others keep their text: the first edited row is the first clipped one).
    pub fn clip(&mut self, columns: &[&str], from: f64, to: f64, level: f64) {
        let cols: Vec<usize> = columns.iter().map(|c| self.col(c)).collect();
        for i in 0..self.rows.len() {
            let t = self.t(i);
            if t >= from && t < to {
                for &c in &cols {
                    let v: f64 = self.rows[i][c].parse().unwrap();
                    if v.abs() > level {
                        self.rows[i][c] = v.clamp(-level, level).to_string();
                    }
                }
            }
        }
    }
}

pub const SENSORS: [&str; 8] = [
    "phi_x", "phi_y", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az",
];

/// The estimates of one run: per estimator, (roll, pitch, flagged) per row, and the times.
pub struct Run {
    pub t: Vec<f64>,
    pub est: BTreeMap<String, Vec<(f64, f64, String)>>,
    pub stderr: String,
}

pub fn estimate(dir: &Path, log: &Path, name: &str, rig: &str) -> Run {
    let out = dir.join(format!("{name}.est.csv"));
    let params = if rig.is_empty() {
        dir.join("ride.rig.toml")
    } else {
        let p = dir.join(format!("{name}.rig.toml"));
        let base = std::fs::read_to_string(dir.join("ride.rig.toml")).unwrap();
        std::fs::write(&p, format!("{base}\n{rig}")).unwrap();
        p
    };
    let o = pendtilt(&[
        "estimate",
        s(log),
        "--params",
        s(&params),
        "--scenario",
        s(&dir.join("ride.scenario.toml")),
        "--flags",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{name}: {}", stderr(&o));
    let c = Csv::read(&out);
    let mut est = BTreeMap::new();
    for e in REGISTRY3D {
        let (r, p) = (
            c.col(&format!("{}_roll", e.name)),
            c.col(&format!("{}_pitch", e.name)),
        );
        let f = c.col(&format!("{}_flags", e.name));
        let v = c
            .rows
            .iter()
            .map(|x| {
                let num = |i: usize| x[i].parse::<f64>().unwrap();
                (num(r), num(p), x.get(f).cloned().unwrap_or_default())
            })
            .collect();
        est.insert(e.name.to_string(), v);
    }
    Run {
        t: c.rows.iter().map(|x| x[0].parse().unwrap()).collect(),
        est,
        stderr: stderr(&o),
    }
}

/// How one estimator came through one fault.
#[derive(Debug, Clone, Copy)]
pub struct Outcome {
    /// Time after the fault's end from which it stays within the bound \[s\]; infinite
    /// when it is not within it at the end of the log.
    pub recovery: f64,
    /// The largest difference from 2 s after the fault's end on \[deg\].
    pub after_2s: f64,
    /// Rows with a non-finite output and no flag, after the first second.
    pub unflagged_nan: usize,
    /// Inclination RMS error against the truth from 2 s after the fault's end to the log's
    /// end \[deg\], of the faulty run and of the fault-free run over the same rows.
    pub truth_rms: [f64; 2],
}

/// Inclination RMS error \[deg\] of `est` against the log's truth `truth` (roll, pitch per
/// row) over the rows at or after `from` (infinite if an output there is not finite).
pub fn truth_rms(est: &[(f64, f64, String)], truth: &[(f64, f64)], t: &[f64], from: f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for ((e, tr), &ti) in est.iter().zip(truth).zip(t) {
        if ti < from {
            continue;
        }
        let d = inclination_error(e.0, e.1, tr.0, tr.1).to_degrees();
        if !d.is_finite() {
            return f64::INFINITY;
        }
        sum += d * d;
        n += 1;
    }
    (sum / n as f64).sqrt()
}

pub fn outcome(
    clean: &[(f64, f64, String)],
    faulty: &[(f64, f64, String)],
    truth: &[(f64, f64)],
    t: &[f64],
    end: f64,
) -> Outcome {
    let mut last_out = None;
    let mut after_2s = 0.0f64;
    let mut unflagged_nan = 0;
    for (i, (c, f)) in clean.iter().zip(faulty).enumerate() {
        let finite = f.0.is_finite() && f.1.is_finite();
        if !finite && f.2.is_empty() && t[i] >= 1.0 {
            unflagged_nan += 1;
        }
        if t[i] < end {
            continue;
        }
        let d = inclination_error(c.0, c.1, f.0, f.1).to_degrees();
        let d = if d.is_finite() { d } else { f64::INFINITY };
        if d > BOUND_DEG {
            last_out = Some(i);
        }
        if t[i] >= end + 2.0 {
            after_2s = after_2s.max(d);
        }
    }
    let recovery = match last_out {
        None => 0.0,
        Some(i) if i + 1 == t.len() => f64::INFINITY,
        Some(i) => t[i + 1] - end,
    };
    Outcome {
        recovery,
        after_2s,
        unflagged_nan,
        truth_rms: [
            truth_rms(faulty, truth, t, end + 2.0),
            truth_rms(clean, truth, t, end + 2.0),
        ],
    }
}

/// The simulator's roll and pitch \[rad\] per row of `csv`.
pub fn truth(csv: &Csv) -> Vec<(f64, f64)> {
    let (roll, pitch) = (csv.col("roll"), csv.col("pitch"));
    csv.rows
        .iter()
        .map(|r| (r[roll].parse().unwrap(), r[pitch].parse().unwrap()))
        .collect()
}

/// Simulates the ride into `dir` (ride.csv, ride.rig.toml, ride.scenario.toml).
pub fn simulate(dir: &Path) -> PathBuf {
    simulate_as(dir, "ride", &[])
}

/// Simulates the ride with the further `args` into `dir/name.csv`.
pub fn simulate_as(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let log = dir.join(format!("{name}.csv"));
    let mut all = vec![
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        "30",
        "--seed",
        "3",
        "-q",
        "-o",
        s(&log),
    ];
    all.extend_from_slice(args);
    let o = pendtilt(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    log
}

pub fn fmt_recovery(r: f64) -> String {
    if r == 0.0 {
        "0".into()
    } else if r.is_finite() {
        format!("{r:.2} s")
    } else {
        "not within".into()
    }
}
