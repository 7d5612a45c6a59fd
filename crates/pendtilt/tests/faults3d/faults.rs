//! The fault table: every 3-D estimator through each fault (gaps, glitches, impossible
//! cells, saturation, time glitches), its flags, its recovery and its error from the truth.
use crate::common::faults3d::{
    estimate, fmt_recovery, outcome, simulate, truth, Csv, Outcome, Run, BOUND_DEG, GYRO_CLIP,
    SENSORS, TRUTH_ABS_DEG, TRUTH_REL, T_FAULT,
};

use pendtilt::bank::spatial::REGISTRY3D;
use pendtilt::sensors::Inputs;
use pendtilt::sensors::Sensor;

const ACCEL_CLIP: f64 = 12.0;

/// The full scale \[rad/s\] of the gyro in the `gyro_range` case: every gyro cell clipped
/// at it and the rig saying so (`[gyro] full_scale`). The ride's readings pass it in three
/// short stretches (vibration peaks on the largest swings, from 14.5 s, 23.3 s and 28.5 s);
/// the log is cut at [`RANGE_LOG_END`] so that one stretch is followed by 7 s without any.
const GYRO_RANGE: f64 = 0.35;

const RANGE_LOG_END: f64 = 22.0;

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
        flag: Some(("implausible", |r| r.has(Sensor::Gyro))),
        rig: "",
    },
    Fault {
        name: "accel_-1e308",
        what: "one ax cell -1e308",
        apply: |c| one_row(c, "ax", |_| "-1e308".into()),
        warns: "column 7 (`ax`): -1e308 m/s^2 is beyond 500 m/s^2, impossible: read as missing",
        never_warns: &[],
        flag: Some(("implausible", |r| r.has(Sensor::Accel))),
        rig: "",
    },
    Fault {
        name: "burst_gyro",
        what: "100 rows of gyro_x 1e6",
        apply: |c| burst(c, "gyro_x", "1e6"),
        warns: "column 4 (`gyro_x`): 1e6 rad/s is beyond 100 rad/s, impossible: read as missing",
        // 100 identical impossible readings are no clip; 1e6 deg/s is impossible too.
        never_warns: &["unknown full scale", "--deg"],
        flag: Some(("implausible", |r| r.has(Sensor::Gyro))),
        rig: "",
    },
    Fault {
        name: "burst_accel",
        what: "100 rows of ax -1e308",
        apply: |c| burst(c, "ax", "-1e308"),
        warns: "column 7 (`ax`): -1e308 m/s^2 is beyond 500 m/s^2, impossible: read as missing",
        never_warns: &["unknown full scale"],
        flag: Some(("implausible", |r| r.has(Sensor::Accel))),
        rig: "",
    },
    Fault {
        name: "burst_phi",
        what: "100 rows of phi_x 1e300",
        apply: |c| burst(c, "phi_x", "1e300"),
        warns: "column 2 (`phi_x`): 1e300 rad is beyond 3.14",
        never_warns: &["--deg"],
        flag: Some(("implausible", |r| r.has(Sensor::Encoder))),
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
        flag: Some(("saturated", |r| r.has(Sensor::Gyro))),
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
        flag: Some(("saturated", |r| r.has(Sensor::Gyro))),
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
        flag: Some(("saturated", |r| r.has(Sensor::Accel))),
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
        check_warnings(fault, &run);
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
            failures.extend(judge(fault.name, e.name, &o));
        }
    }
    print_tables(&table);
    oracle_restarts(&clean, &clean_csv);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Prints the fault's warnings (the first three) and checks that it warned as it should.
fn check_warnings(fault: &Fault, run: &Run) {
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
}

/// What estimator `e` did wrong on fault `fault`: NaN rows unflagged, a run from the truth
/// worse than allowed, a recovery slower than allowed.
fn judge(fault: &str, e: &str, o: &Outcome) -> Vec<String> {
    let mut failures = Vec::new();
    if o.unflagged_nan > 0 {
        failures.push(format!(
            "{fault} {e}: {} unflagged NaN rows",
            o.unflagged_nan
        ));
    }
    let [faulty, fault_free] = o.truth_rms;
    let bound = truth_allowed(e, fault).unwrap_or(fault_free * (1.0 + TRUTH_REL) + TRUTH_ABS_DEG);
    if faulty > bound || faulty.is_nan() {
        failures.push(format!(
            "{fault} {e}: {faulty:.3} deg RMS from the truth from 2 s after the fault on, \
             fault-free {fault_free:.3}, allowed {bound:.3}"
        ));
    }
    let a = allowed(e, fault);
    if o.recovery > a.recovery || o.after_2s > a.after_2s {
        failures.push(format!(
            "{fault} {e}: back after {} ({:.4} deg from 2 s on)",
            fmt_recovery(o.recovery),
            o.after_2s
        ));
    }
    failures
}

/// The two tables of docs/reliability.md section 8, one row per estimator, one column
/// per fault: the recovery, and the RMS from the truth, faulty (fault-free), from 2 s
/// after the fault.
fn print_tables(table: &[(&str, &str, Outcome)]) {
    let cell = |f: &str, e: &str| table.iter().find(|x| x.0 == f && x.1 == e).unwrap().2;
    print!("\n| estimator |");
    for f in &FAULTS {
        print!(" {} |", f.name);
    }
    println!();
    for e in REGISTRY3D {
        print!("| {} |", e.name);
        for f in &FAULTS {
            let o = cell(f.name, e.name);
            if o.recovery > 2.0 {
                print!(" {} ({:.3}) |", fmt_recovery(o.recovery), o.after_2s);
            } else {
                print!(" {} |", fmt_recovery(o.recovery));
            }
        }
        println!();
    }
    print!("\n| estimator |");
    for f in &FAULTS {
        print!(" {} |", f.name);
    }
    println!();
    for e in REGISTRY3D {
        print!("| {} |", e.name);
        for f in &FAULTS {
            let [faulty, clean] = cell(f.name, e.name).truth_rms;
            let worse = faulty > clean * (1.0 + TRUTH_REL) + TRUTH_ABS_DEG;
            let b = if worse { "**" } else { "" };
            print!(" {b}{faulty:.3} ({clean:.3}){b} |");
        }
        println!();
    }
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
