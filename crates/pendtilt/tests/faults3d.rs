//! Sensor faults and bad readings on 3-D logs (every 3-D estimator survives the
//! bad-input and fault tests the planar ones pass; docs/reliability.md section 8).
//!
//! One simulated `scooter3d` ride (seed 3, 30 s, 1 kHz) is written by `pendtilt simulate`;
//! each fault is injected into a copy of its CSV from t = 8 s (`gyro_range`: a gyro of a
//! smaller range, clipping the whole log, with the rig saying so), and `pendtilt estimate
//! --flags` runs every estimator of the 3-D registry on the clean and on the faulty log,
//! as a user would. For every fault and estimator the test checks: one output row per
//! input row; every output finite or flagged; the flag on the fault's first row for every
//! estimator reading the faulty sensor; and recovery: the time after the fault's end
//! from which the output stays within 0.05 deg (inclination, MODEL.md 7.9) of the
//! fault-free run to the end of the log, and the largest difference from 2 s after the end;
//! and against the simulator's truth (the log's `roll`, `pitch`): the inclination RMS error
//! from 2 s after the fault's end to the log's end is no worse than the fault-free run's
//! over the same rows by more than 10 % + 0.01 deg (no bad reading poisons a run, also for
//! a peer that cannot meet its own fault-free run within 0.05 deg). The faults include a
//! burst of 100 rows of an impossible gyro, accelerometer and encoder cell.
//!
//! The table of docs/reliability.md section 8 is printed by
//! `cargo test --release -p pendtilt --test faults3d -- --nocapture`.
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pendtilt::bank::Inputs;
use pendtilt::bank3d::REGISTRY3D;
use pendtilt::core::spatial::attitude::inclination_error;

mod common;
use common::{pendtilt, s, stderr};

/// When every fault starts \[s\].
const T_FAULT: f64 = 8.0;
/// The recovery bound \[deg\].
const BOUND_DEG: f64 = 0.05;
/// The second criterion (against the truth): from 2 s after a fault's end to the log's end,
/// an estimator's inclination RMS error may exceed its fault-free run's over the same rows by
/// at most this fraction of it plus [`TRUTH_ABS_DEG`] (docs/reliability.md section 8 gives
/// the reasons).
const TRUTH_REL: f64 = 0.10;
/// See [`TRUTH_REL`] \[deg\].
const TRUTH_ABS_DEG: f64 = 0.01;
/// Clip levels of the saturation cases: below the ride's largest readings (gyro up to
/// 0.27 rad/s, |az| up to 21 m/s^2), so the clip bites on a quarter of the samples or more.
const GYRO_CLIP: f64 = 0.1;
const ACCEL_CLIP: f64 = 12.0;
/// The full scale \[rad/s\] of the gyro in the `gyro_range` case: every gyro cell clipped
/// at it and the rig saying so (`[gyro] full_scale`). The ride's readings pass it in three
/// short stretches (vibration peaks on the largest swings, from 14.5 s, 23.3 s and 28.5 s);
/// the log is cut at [`RANGE_LOG_END`] so that one stretch is followed by 7 s without any.
const GYRO_RANGE: f64 = 0.35;
const RANGE_LOG_END: f64 = 22.0;

/// A log as header and text cells (the faults edit cells as text).
#[derive(Clone)]
struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Csv {
    fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines();
        let header = lines.next().unwrap().split(',').map(String::from).collect();
        let rows = lines
            .map(|l| l.split(',').map(String::from).collect())
            .collect();
        Self { header, rows }
    }

    fn write(&self, path: &Path) {
        let mut out = self.header.join(",");
        out.push('\n');
        for r in &self.rows {
            out.push_str(&r.join(","));
            out.push('\n');
        }
        std::fs::write(path, out).unwrap();
    }

    fn col(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    }

    /// The first and the last row where `self` differs from `other`.
    fn differs(&self, other: &Csv) -> Option<(usize, usize)> {
        let d: Vec<usize> = (0..self.rows.len().min(other.rows.len()))
            .filter(|&i| self.rows[i] != other.rows[i])
            .collect();
        Some((*d.first()?, *d.last()?))
    }

    fn t(&self, row: usize) -> f64 {
        self.rows[row][0].parse().unwrap()
    }

    /// The first row at or after `t`.
    fn row_at(&self, t: f64) -> usize {
        (0..self.rows.len()).find(|&i| self.t(i) >= t).unwrap()
    }

    /// Applies `f` to the cells of `columns` on the rows with `from <= t < to`.
    fn edit(&mut self, columns: &[&str], from: f64, to: f64, f: impl Fn(f64) -> String) {
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
    fn clip(&mut self, columns: &[&str], from: f64, to: f64, level: f64) {
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

const SENSORS: [&str; 8] = [
    "phi_x", "phi_y", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az",
];

/// One fault: its name, what it does, and the log with it (and when it ends \[s\]).
struct Fault {
    name: &'static str,
    what: &'static str,
    apply: fn(&mut Csv) -> f64,
    /// What `estimate` must warn ("" for nothing).
    warns: &'static str,
    /// What it must not warn.
    never_warns: &'static [&'static str],
    /// The flag every estimator reading the faulty sensor must carry on the fault's first
    /// row (`reads` picks them; None: no flag is required).
    flag: Option<(&'static str, Reads)>,
    /// TOML added to the rig file for the faulty run ("" for none).
    rig: &'static str,
}

/// Picks the estimators that read a sensor, by their [`Inputs`].
type Reads = fn(&Inputs) -> bool;

fn one_row(c: &mut Csv, column: &str, f: impl Fn(f64) -> String) -> f64 {
    let i = c.row_at(T_FAULT);
    let (t, next) = (c.t(i), c.t(i + 1));
    c.edit(&[column], t, next, f);
    next
}

/// How many rows a burst of bad cells lasts ("a burst of 100").
const BURST: usize = 100;

/// `BURST` consecutive rows of `column` written as `value`, from `T_FAULT`.
fn burst(c: &mut Csv, column: &str, value: &'static str) -> f64 {
    let i = c.row_at(T_FAULT);
    let (t, end) = (c.t(i), c.t(i + BURST));
    c.edit(&[column], t, end, |_| value.into());
    end
}

const FAULTS: [Fault; 12] = [
    Fault {
        name: "gap_10s",
        what: "every sensor cell empty for 10 s (rows kept)",
        apply: |c| {
            c.edit(&SENSORS, T_FAULT, T_FAULT + 10.0, |_| String::new());
            T_FAULT + 10.0
        },
        warns: "phi_x/phi_y, gyro_x/y/z, ax/ay/az back after a gap of 10.001 s (longer than \
                the restart gap 0.5 s): 10 estimators",
        never_warns: &[],
        flag: Some(("sample_missing", |_| true)),
        rig: "",
    },
    Fault {
        name: "gyro_1e6",
        what: "one gyro_x cell 1e6",
        apply: |c| one_row(c, "gyro_x", |_| "1e6".into()),
        warns: "column 4 (`gyro_x`): 1e6 rad/s is beyond 100 rad/s, impossible: read as missing",
        never_warns: &["--deg"],
        flag: Some(("implausible", |r| r.gyro)),
        rig: "",
    },
    Fault {
        name: "accel_-1e308",
        what: "one ax cell -1e308",
        apply: |c| one_row(c, "ax", |_| "-1e308".into()),
        warns: "column 7 (`ax`): -1e308 m/s^2 is beyond 500 m/s^2, impossible: read as missing",
        never_warns: &[],
        flag: Some(("implausible", |r| r.accel)),
        rig: "",
    },
    Fault {
        name: "burst_gyro",
        what: "100 rows of gyro_x 1e6",
        apply: |c| burst(c, "gyro_x", "1e6"),
        warns: "column 4 (`gyro_x`): 1e6 rad/s is beyond 100 rad/s, impossible: read as missing",
        // 100 identical impossible readings are no clip; 1e6 deg/s is impossible too.
        never_warns: &["unknown full scale", "--deg"],
        flag: Some(("implausible", |r| r.gyro)),
        rig: "",
    },
    Fault {
        name: "burst_accel",
        what: "100 rows of ax -1e308",
        apply: |c| burst(c, "ax", "-1e308"),
        warns: "column 7 (`ax`): -1e308 m/s^2 is beyond 500 m/s^2, impossible: read as missing",
        never_warns: &["unknown full scale"],
        flag: Some(("implausible", |r| r.accel)),
        rig: "",
    },
    Fault {
        name: "burst_phi",
        what: "100 rows of phi_x 1e300",
        apply: |c| burst(c, "phi_x", "1e300"),
        warns: "column 2 (`phi_x`): 1e300 rad is beyond 3.14",
        never_warns: &["--deg"],
        flag: Some(("implausible", |r| r.phi)),
        rig: "",
    },
    Fault {
        name: "phi_spike",
        what: "one phi_x cell 1 rad off (plausible, wrong)",
        apply: |c| one_row(c, "phi_x", |v| (v + 1.0).to_string()),
        warns: "",
        never_warns: &[],
        flag: None,
        rig: "",
    },
    Fault {
        name: "gyro_clipped",
        what: "every gyro axis clipped at 0.1 rad/s for 2 s, full scale unknown",
        apply: |c| {
            c.clip(
                &["gyro_x", "gyro_y", "gyro_z"],
                T_FAULT,
                T_FAULT + 2.0,
                GYRO_CLIP,
            );
            T_FAULT + 2.0
        },
        // Found by its runs of identical readings (io::plateau).
        warns: "(`gyro_y`): -0.1 rad/s on 5 rows in a row up to here, which a sensor with \
                noise never writes: a clip at an unknown full scale",
        never_warns: &[],
        // Found 500 rows ahead: flagged from the clip's first row on.
        flag: Some(("saturated", |r| r.gyro)),
        rig: "",
    },
    Fault {
        name: "gyro_range",
        what: "a gyro of full scale 0.35 rad/s (rig [gyro] full_scale): every cell clipped \
               at it, log cut at 22 s",
        apply: |c| {
            let cols: Vec<usize> = ["gyro_x", "gyro_y", "gyro_z"]
                .iter()
                .map(|n| c.col(n))
                .collect();
            c.rows
                .retain(|r| r[0].parse::<f64>().unwrap() < RANGE_LOG_END);
            for r in &mut c.rows {
                for &i in &cols {
                    let v: f64 = r[i].parse().unwrap();
                    if v.abs() > GYRO_RANGE {
                        r[i] = v.clamp(-GYRO_RANGE, GYRO_RANGE).to_string();
                    }
                }
            }
            f64::NAN
        },
        warns: "",
        never_warns: &[],
        flag: Some(("saturated", |r| r.gyro)),
        rig: "[gyro]\nfull_scale = 0.35\n",
    },
    Fault {
        name: "accel_clipped",
        what: "every accelerometer axis clipped at 12 m/s^2 for 2 s",
        apply: |c| {
            c.clip(&["ax", "ay", "az"], T_FAULT, T_FAULT + 2.0, ACCEL_CLIP);
            T_FAULT + 2.0
        },
        warns: "(`az`): 12 m/s^2 on 5 rows in a row up to here, which a sensor with noise \
                never writes: a clip at an unknown full scale",
        never_warns: &[],
        flag: Some(("saturated", |r| r.accel)),
        rig: "",
    },
    Fault {
        name: "time_back",
        what: "one time stamp 1 s back",
        apply: |c| one_row(c, "t", |v| (v - 1.0).to_string()),
        warns: "",
        never_warns: &[],
        flag: Some(("bad_time_step", |_| true)),
        rig: "",
    },
    Fault {
        name: "time_ahead",
        what: "one time stamp 50 ms ahead",
        apply: |c| {
            let end = one_row(c, "t", |v| (v + 0.05).to_string());
            end + 0.05
        },
        warns: "8.05 s is after the next row's 8.001 s: a lone bad time stamp",
        never_warns: &[],
        flag: Some(("bad_time_step", |_| true)),
        rig: "",
    },
];

/// The estimates of one run: per estimator, (roll, pitch, flagged) per row, and the times.
struct Run {
    t: Vec<f64>,
    est: BTreeMap<String, Vec<(f64, f64, String)>>,
    stderr: String,
}

fn estimate(dir: &Path, log: &Path, name: &str, rig: &str) -> Run {
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
struct Outcome {
    /// Time after the fault's end from which it stays within the bound \[s\]; infinite
    /// when it is not within it at the end of the log.
    recovery: f64,
    /// The largest difference from 2 s after the fault's end on \[deg\].
    after_2s: f64,
    /// Rows with a non-finite output and no flag, after the first second.
    unflagged_nan: usize,
    /// Inclination RMS error against the truth from 2 s after the fault's end to the log's
    /// end \[deg\], of the faulty run and of the fault-free run over the same rows.
    truth_rms: [f64; 2],
}

/// Inclination RMS error \[deg\] of `est` against the log's truth `truth` (roll, pitch per
/// row) over the rows at or after `from` (infinite if an output there is not finite).
fn truth_rms(est: &[(f64, f64, String)], truth: &[(f64, f64)], t: &[f64], from: f64) -> f64 {
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

fn outcome(
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
fn truth(csv: &Csv) -> Vec<(f64, f64)> {
    let (roll, pitch) = (csv.col("roll"), csv.col("pitch"));
    csv.rows
        .iter()
        .map(|r| (r[roll].parse().unwrap(), r[pitch].parse().unwrap()))
        .collect()
}

/// Simulates the ride into `dir` (ride.csv, ride.rig.toml, ride.scenario.toml).
fn simulate(dir: &Path) -> PathBuf {
    simulate_as(dir, "ride", &[])
}

/// Simulates the ride with the further `args` into `dir/name.csv`.
fn simulate_as(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
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

fn fmt_recovery(r: f64) -> String {
    if r == 0.0 {
        "0".into()
    } else if r.is_finite() {
        format!("{r:.2} s")
    } else {
        "not within".into()
    }
}

/// What an estimator is held to after a fault: back within the bound by `recovery` [s]
/// after the fault's end, and no further than `after_2s` [deg] from the fault-free run from
/// 2 s after it on.
#[derive(Debug, Clone, Copy)]
struct Allowance {
    recovery: f64,
    after_2s: f64,
}

/// 2 s and the 0.05 deg bound for every estimator and fault, except the measured
/// exceptions of docs/reliability.md section 8 (each with its reason there), held to about
/// 1.5 times their measured figures so that a regression shows.
fn allowed(estimator: &str, fault: &str) -> Allowance {
    let never = |after_2s| Allowance {
        recovery: f64::INFINITY,
        after_2s,
    };
    let slow = |recovery, after_2s| Allowance { recovery, after_2s };
    match (fault, estimator) {
        ("gap_10s", "vqf") => never(0.7),
        ("gap_10s", "mahony3d") => slow(10.5, 0.6),
        ("gap_10s", "fusion3d") => never(15.0),
        ("gyro_clipped", "vqf") => never(1.3),
        ("gyro_clipped", "mahony3d") => slow(5.7, 0.16),
        ("gyro_clipped", "fusion3d") => never(9.7),
        ("gyro_range", "vqf") => slow(4.0, 0.1),
        ("gyro_range", "fusion3d") => never(0.13),
        ("accel_clipped", "vqf") => slow(8.0, 0.16),
        ("accel_clipped", "mahony3d") => slow(5.5, 0.14),
        // imu3d, the pendulum left out: as the peers, it forgets a fault only at its
        // accelerometer's rate, which its adaptation lowers on a vehicle.
        ("gap_10s", "imu3d") => never(1.3),
        ("burst_gyro", "imu3d") => slow(33.0, 0.16),
        ("gyro_clipped", "imu3d") => never(0.43),
        ("accel_clipped", "imu3d") => slow(6.5, 0.13),
        _ => Allowance {
            recovery: 2.0,
            after_2s: BOUND_DEG,
        },
    }
}

/// The measured exceptions to the truth criterion ([`TRUTH_REL`]): the largest RMS error
/// from the truth \[deg\] allowed from 2 s after the fault on (about 1.2 times the measured
/// figure), with the reason in docs/reliability.md section 8; `None`: the criterion.
fn truth_allowed(estimator: &str, fault: &str) -> Option<f64> {
    match (fault, estimator) {
        ("gap_10s", "vqf") => Some(0.95),
        ("gap_10s", "imu3d") => Some(0.45),
        ("burst_gyro", "imu3d") => Some(0.31),
        ("gyro_clipped", "imu3d") => Some(0.29),
        _ => None,
    }
}

#[test]
fn every_3d_estimator_survives_gaps_glitches_saturation_and_time_glitches() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path());
    let clean_csv = Csv::read(&log);
    let clean = estimate(dir.path(), &log, "clean", "");
    let mut table = Vec::new();
    let mut failures = Vec::new();
    for fault in &FAULTS {
        let mut c = clean_csv.clone();
        let end = (fault.apply)(&mut c);
        // The fault's first and last edited rows; NaN from `apply`: it ends after the last.
        let (first, last) = c.differs(&clean_csv).unwrap();
        let end = if end.is_nan() { c.t(last + 1) } else { end };
        let path = dir.path().join(format!("{}.csv", fault.name));
        c.write(&path);
        let run = estimate(dir.path(), &path, fault.name, fault.rig);
        assert_eq!(run.t.len(), c.rows.len(), "{}: rows", fault.name);
        let t = &clean.t[..run.t.len()];
        // The simulator's truth, the same in both logs (the faults edit sensor cells only).
        let truth = truth(&c);
        let warned: Vec<&str> = run
            .stderr
            .lines()
            .filter(|l| l.contains("warning"))
            .collect();
        println!(
            "{} ({}): {} warning line(s)",
            fault.name,
            fault.what,
            warned.len()
        );
        for w in warned.iter().take(3) {
            println!("    {w}");
        }
        assert!(
            run.stderr.contains(fault.warns),
            "{}: {}",
            fault.name,
            run.stderr
        );
        for never in fault.never_warns {
            assert!(
                !run.stderr.contains(never),
                "{}: `{never}` in {}",
                fault.name,
                run.stderr
            );
        }
        for e in REGISTRY3D {
            if let Some((flag, reads)) = fault.flag {
                let got = &run.est[e.name][first].2;
                if reads(&e.reads()) && !got.contains(flag) {
                    failures.push(format!(
                        "{} {}: flags `{got}`, not {flag}",
                        fault.name, e.name
                    ));
                }
            }
            let o = outcome(&clean.est[e.name], &run.est[e.name], &truth, t, end);
            table.push((fault.name, e.name, o));
            if o.unflagged_nan > 0 {
                failures.push(format!(
                    "{} {}: {} unflagged NaN rows",
                    fault.name, e.name, o.unflagged_nan
                ));
            }
            let [faulty, fault_free] = o.truth_rms;
            let bound = truth_allowed(e.name, fault.name)
                .unwrap_or(fault_free * (1.0 + TRUTH_REL) + TRUTH_ABS_DEG);
            if faulty > bound || faulty.is_nan() {
                failures.push(format!(
                    "{} {}: {faulty:.3} deg RMS from the truth from 2 s after the fault on, \
                     fault-free {fault_free:.3}, allowed {bound:.3}",
                    fault.name, e.name
                ));
            }
            let a = allowed(e.name, fault.name);
            if o.recovery > a.recovery || o.after_2s > a.after_2s {
                failures.push(format!(
                    "{} {}: back after {} ({:.4} deg from 2 s on)",
                    fault.name,
                    e.name,
                    fmt_recovery(o.recovery),
                    o.after_2s
                ));
            }
        }
    }
    // The table: one row per estimator, one column per fault.
    print!("\n| estimator |");
    for f in &FAULTS {
        print!(" {} |", f.name);
    }
    println!();
    for e in REGISTRY3D {
        print!("| {} |", e.name);
        for f in &FAULTS {
            let (_, _, o) = table
                .iter()
                .find(|x| x.0 == f.name && x.1 == e.name)
                .unwrap();
            if o.recovery > 2.0 {
                print!(" {} ({:.3}) |", fmt_recovery(o.recovery), o.after_2s);
            } else {
                print!(" {} |", fmt_recovery(o.recovery));
            }
        }
        println!();
    }
    // The second table: RMS from the truth, faulty (fault-free), from 2 s after the fault.
    print!("\n| estimator |");
    for f in &FAULTS {
        print!(" {} |", f.name);
    }
    println!();
    for e in REGISTRY3D {
        print!("| {} |", e.name);
        for f in &FAULTS {
            let (_, _, o) = table
                .iter()
                .find(|x| x.0 == f.name && x.1 == e.name)
                .unwrap();
            let [faulty, clean] = o.truth_rms;
            let worse = faulty > clean * (1.0 + TRUTH_REL) + TRUTH_ABS_DEG;
            let b = if worse { "**" } else { "" };
            print!(" {b}{faulty:.3} ({clean:.3}){b} |");
        }
        println!();
    }
    oracle_restarts(&clean, &clean_csv);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Why three peers cannot be back within 0.05 deg of their fault-free run 2 s after the
/// 10 s gap, whatever their restart: a restart knowing the truth (an oracle) would start at
/// the truth plus the fault-free run's mean error over the next 10 s, yet the fault-free
/// run at the gap's end stands `d` from that (its own error then, which depends on the
/// readings the gap took away), and two runs of a filter close their difference only at
/// its accelerometer rate: Mahony kp = 0.45 /s; VQF 1 / tau_acc = 1/3 s; fusion3d its gain
/// 0.5 /s times the share of readings its acceleration rejection takes on this ride (17 %,
/// docs/reliability.md section 8). The oracle is back after ln(d / 0.05) time constants:
/// measured 4.02 s, 3.98 s and 45.9 s, and beyond 2 s for at least half the gaps ending
/// anywhere from 10 s to 20 s (Mahony 7 of 11, VQF and fusion3d all 11). Figures:
/// `cargo test --release -p pendtilt --test faults3d -- --nocapture`.
fn oracle_restarts(clean: &Run, csv: &Csv) {
    let truth = truth(csv);
    let row = |at: f64| clean.t.iter().position(|t| *t >= at).unwrap();
    let rates = [
        ("mahony3d", pendtilt::peers::spatial::MAHONY3D_GAINS[0]),
        ("vqf", 1.0 / pendtilt::peers::spatial::VQF_TAU_ACC),
        ("fusion3d", 0.5 * 0.17),
    ];
    for (name, rate) in rates {
        let est = &clean.est[name];
        // The error as a (roll, pitch) vector: small angles, about the same tilt.
        let err = |k: usize| [est[k].0 - truth[k].0, est[k].1 - truth[k].1];
        let oracle = |k1: usize| {
            let k2 = (k1 + 10_000).min(clean.t.len());
            let n = (k2 - k1) as f64;
            let mean = (k1..k2)
                .map(err)
                .fold([0.0, 0.0], |m, e| [m[0] + e[0] / n, m[1] + e[1] / n]);
            let e = err(k1);
            let d = (e[0] - mean[0]).hypot(e[1] - mean[1]).to_degrees();
            (d, ((d / BOUND_DEG).ln() / rate).max(0.0))
        };
        let (d, back) = oracle(row(T_FAULT + 10.0));
        println!(
            "{name}: the fault-free run {d:.3} deg from the truth plus its mean error at the \
             gap's end: an oracle restart back after {back:.2} s"
        );
        assert!(back > 2.0, "{name}: an oracle would be back after {back} s");
        // And at the end of gaps ending anywhere from 10 s to 20 s, each second.
        let elsewhere: Vec<f64> = (10..=20).map(|s| oracle(row(s as f64)).1).collect();
        let beyond = elsewhere.iter().filter(|b| **b > 2.0).count();
        println!(
            "    gaps ending at 10, 11, .., 20 s: beyond 2 s in {beyond} of 11: {elsewhere:.2?}"
        );
        // Measured: Mahony 7 of 11, VQF and fusion3d all 11.
        assert!(beyond >= 6, "{name}: {elsewhere:?}");
    }
}

/// The clip finder (`io::plateau`) never fires on a correct log: the four 3-D scenarios
/// as simulated (noisy, and with ideal sensors: readings that repeat whenever the body is
/// still), and a still3d log written as a quantised IMU would (gyro steps of 0.061 deg/s,
/// accelerometer steps of 0.0024 m/s^2: readings repeat at rest). No warning, no row
/// flagged `saturated`.
#[test]
fn correct_logs_never_look_clipped() {
    let dir = tempfile::tempdir().unwrap();
    let mut cases = Vec::new();
    for scenario in ["still3d", "scooter3d", "ship3d", "ride3d"] {
        for ideal in [false, true] {
            let log = dir.path().join(format!("{scenario}{ideal}.csv"));
            let mut args = vec![
                "simulate",
                "--scenario",
                scenario,
                "--duration",
                "20",
                "--seed",
                "4",
                "-q",
                "-o",
                s(&log),
            ];
            if ideal {
                args.push("--ideal-sensors");
            }
            let o = pendtilt(&args);
            assert!(o.status.success(), "{}", stderr(&o));
            cases.push(log);
        }
    }
    // still3d quantised: every gyro and accelerometer cell rounded to its step.
    let still = dir.path().join("still3dfalse.csv");
    let mut c = Csv::read(&still);
    let lsb_gyro = 0.061f64.to_radians();
    let q = |v: f64, lsb: f64| ((v / lsb).round() * lsb).to_string();
    c.edit(
        &["gyro_x", "gyro_y", "gyro_z"],
        f64::NEG_INFINITY,
        f64::INFINITY,
        |v| q(v, lsb_gyro),
    );
    c.edit(&["ax", "ay", "az"], f64::NEG_INFINITY, f64::INFINITY, |v| {
        q(v, 0.0024)
    });
    let quantised = dir.path().join("still3d_quantised.csv");
    c.write(&quantised);
    // Copy the rig and scenario beside it under its name.
    for ext in ["rig.toml", "scenario.toml"] {
        std::fs::copy(
            dir.path().join(format!("still3dfalse.{ext}")),
            dir.path().join(format!("still3d_quantised.{ext}")),
        )
        .unwrap();
    }
    let repeats = (1..c.rows.len())
        .filter(|&i| c.rows[i][c.col("gyro_x")] == c.rows[i - 1][c.col("gyro_x")])
        .count();
    assert!(
        repeats * 2 > c.rows.len(),
        "quantised, at rest: {repeats} repeats"
    );
    cases.push(quantised);
    for log in &cases {
        let stem = log.file_stem().unwrap().to_str().unwrap();
        let out = dir.path().join(format!("{stem}.est.csv"));
        let o = pendtilt(&[
            "estimate",
            s(log),
            "--params",
            s(&dir.path().join(format!("{stem}.rig.toml"))),
            "--scenario",
            s(&dir.path().join(format!("{stem}.scenario.toml"))),
            "--flags",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{stem}: {}", stderr(&o));
        assert!(
            !stderr(&o).contains("unknown full scale"),
            "{stem}: {}",
            stderr(&o)
        );
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            !text.contains("saturated"),
            "{stem}: a row flagged saturated"
        );
    }
}

/// A rig that overstates the gyro's range: the gyro clipped at 0.1 rad/s for 2 s (the
/// `gyro_clipped` fault) read with `[gyro] full_scale = 8.7` in the rig. The clip is below
/// the rig's full scale, so the finder still looks (it looked only without a full scale,
/// and said nothing): warned as a range smaller than the rig says, and every estimate is
/// the same as without a full scale in the rig.
#[test]
fn a_gyro_clip_below_the_rigs_full_scale_is_found_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path());
    let mut c = Csv::read(&log);
    c.clip(
        &["gyro_x", "gyro_y", "gyro_z"],
        T_FAULT,
        T_FAULT + 2.0,
        GYRO_CLIP,
    );
    let bad = dir.path().join("clipped.csv");
    c.write(&bad);
    let unknown = estimate(dir.path(), &bad, "unknown", "");
    let told = estimate(dir.path(), &bad, "told", "[gyro]\nfull_scale = 8.7\n");
    assert!(
        told.stderr.contains(
            "(`gyro_y`): -0.1 rad/s on 5 rows in a row up to here, which a sensor with noise \
             never writes: a clip below the rig's [gyro] full_scale 8.7 rad/s: the sensor's \
             range is smaller than the rig says"
        ),
        "{}",
        told.stderr
    );
    assert!(
        !told.stderr.contains("unknown full scale"),
        "{}",
        told.stderr
    );
    assert_eq!(unknown.est, told.est, "the same estimates and flags");
}

/// A twin of the ride: the same readings but over `[from, to)` \[s\], where `edit` changes
/// them (`edit(twin, row)`).
fn twin(ride: &Csv, from: f64, to: f64, edit: impl Fn(&mut Vec<String>, usize)) -> Csv {
    let mut c = ride.clone();
    for i in 0..c.rows.len() {
        if (from..to).contains(&c.t(i)) {
            edit(&mut c.rows[i], i);
        }
    }
    c
}

/// Why no restart can bring mahony3d, VQF and fusion3d back within 0.05 deg of their
/// fault-free run 2 s after the 10 s gap (8-18 s): the planar argument
/// (`plausibility::no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap`)
/// on the 3-D ride, with two twins that differ from it only inside the gap, where the gap
/// took every reading away: one brakes gently along the body's forward axis over the gap's
/// last 2 s (`1 m/s^2 sin^2`, 0.1 g at its peak: the accelerometer reads it), one rides a
/// smooth road over the gap's last 5 s (the accelerometer as `simulate --no-vibration`
/// gives it, same seed). The faulty logs of the three are one log, so any restart gives one
/// output on all three; but their fault-free runs stand up to `D` apart from 2 s after the
/// gap on, and a restart within 0.05 deg of two of them there needs `D <= 0.1 deg`.
/// Measured D (braking / smooth road): mahony3d 0.69 / 1.32 deg, VQF 1.30 / 0.03, fusion3d
/// 0.02 / 3.90;
/// madgwick3d, which meets 2 s, 0 / 0. Figures: `cargo test --release -p pendtilt --test
/// faults3d -- --nocapture twin`.
#[test]
fn no_restart_meets_2_s_on_both_a_3d_ride_and_its_twins_in_the_gap() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path());
    let ride = Csv::read(&log);
    let end = T_FAULT + 10.0;
    let smooth = Csv::read(&simulate_as(dir.path(), "smooth", &["--no-vibration"]));
    let accel = ["ax", "ay", "az"].map(|c| ride.col(c));
    let braking = twin(&ride, end - 2.0, end, |row, _| {
        let t: f64 = row[0].parse().unwrap();
        let s = ((t - (end - 2.0)) / 2.0 * std::f64::consts::PI).sin();
        let v: f64 = row[accel[0]].parse().unwrap();
        row[accel[0]] = format!("{}", v + s * s);
    });
    let smooth_road = twin(&ride, end - 5.0, end, |row, i| {
        for c in accel {
            row[c] = smooth.rows[i][c].clone();
        }
    });
    let gapped = |c: &Csv| {
        let mut c = c.clone();
        c.edit(&SENSORS, T_FAULT, end, |_| String::new());
        c
    };
    let g = gapped(&ride);
    for t in [&braking, &smooth_road] {
        assert!(g.differs(&gapped(t)).is_none(), "the faulty logs differ");
    }
    let path = |n: &str| dir.path().join(format!("{n}.csv"));
    braking.write(&path("braking"));
    smooth_road.write(&path("smooth_road"));
    g.write(&path("gapped"));
    let clean = estimate(dir.path(), &log, "clean", "");
    let twins = [
        estimate(dir.path(), &path("braking"), "braking", ""),
        estimate(dir.path(), &path("smooth_road"), "smooth_road", ""),
    ];
    let bad = estimate(dir.path(), &path("gapped"), "gapped", "");
    let truth = truth(&ride);
    let at = ride.row_at(end + 2.0);
    for e in REGISTRY3D {
        let c = &clean.est[e.name];
        let back = |clean: &[(f64, f64, String)]| {
            outcome(clean, &bad.est[e.name], &truth, &bad.t, end).recovery
        };
        let b = back(c);
        let mut apart = Vec::new();
        for (tw, what) in twins.iter().zip(["brakes", "rides a smooth road"]) {
            let w = &tw.est[e.name];
            // From 2 s after the gap on, the largest difference.
            let d = (at..c.len())
                .map(|k| inclination_error(c[k].0, c[k].1, w[k].0, w[k].1))
                .fold(0.0, f64::max)
                .to_degrees();
            let b_twin = back(w);
            println!(
                "  {:<12} the ride and its twin that {what}: fault-free runs {d:.3} deg apart \
                 from 2 s after the gap on; the restart back after {} on the ride, {} on the twin",
                e.name,
                fmt_recovery(b),
                fmt_recovery(b_twin)
            );
            apart.push((d, b_twin));
        }
        if ["mahony3d", "vqf", "fusion3d"].contains(&e.name) {
            // A twin whose fault-free run is beyond reach of any restart that meets 2 s on
            // the ride.
            let (d, b_twin) = apart
                .iter()
                .copied()
                .fold((0.0, 0.0), |a, x| if x.0 > a.0 { x } else { a });
            assert!(d > 2.0 * BOUND_DEG, "{}: {d} deg", e.name);
            assert!(b > 2.0 || b_twin > 2.0, "{}: {b} s, {b_twin} s", e.name);
        }
    }
}
