//! Shared by the plausibility tests: a simulated ride as log text, a pass of the bank
//! over it, and when each estimator is back within 0.05 deg of the clean run.
use pendtilt::bank::planar::{Bank, Inputs};
use pendtilt::cli::options::rig_bank_settings;
use pendtilt::config::RigConfig;
use pendtilt::core::Estimate;
use pendtilt::io::{EstimatesWriter, LogReader, LogWarning, ReaderOptions, WarningKind};
use pendtilt::pipeline::{self, PassError, PassSummary};
use pendtilt::sim::planar::{simulate, Scenario, SimRow};

/// A simulated ride and the rig file `simulate` writes for it (with the full scales).
pub fn ride(name: &str, secs: f64, seed: u64) -> (Vec<SimRow>, RigConfig) {
    let mut s = Scenario::named(name).unwrap();
    s.duration = secs;
    (simulate(&s, seed).unwrap(), s.rig().unwrap())
}

/// The cells of each row as text (t, phi, gyro, ax, ay, theta).
pub fn cells(rows: &[SimRow]) -> Vec<[String; 6]> {
    rows.iter()
        .map(|r| {
            let s = r.sample();
            [r.t, s.phi, s.gyro, s.ax, s.ay, r.truth.theta].map(|v| format!("{v}"))
        })
        .collect()
}

pub fn text(cells: &[[String; 6]]) -> String {
    let mut s = String::from("t,phi,gyro,ax,ay,theta\n");
    for c in cells {
        s.push_str(&c.join(","));
        s.push('\n');
    }
    s
}

/// One pass of the reader and the bank over a log text.
pub struct Run {
    pub names: Vec<&'static str>,
    pub t: Vec<f64>,
    pub est: Vec<Vec<Estimate<f64>>>,
    pub warnings: Vec<LogWarning>,
    pub result: Result<PassSummary, PassError>,
    pub implausible_count: u64,
}

pub fn run_with(log: &str, rig: &RigConfig, options: ReaderOptions) -> Run {
    let mut r = LogReader::new(log.as_bytes(), "ride.csv", options).unwrap();
    let mut bank = Bank::new(&rig_bank_settings(rig), pipeline::inputs_of(&r), None).unwrap();
    let names = bank.names().to_vec();
    let mut est = Vec::new();
    let mut warnings = Vec::new();
    let result = pipeline::run(
        &mut r,
        &mut bank,
        None::<&mut EstimatesWriter<Vec<u8>>>,
        false,
        Some(0.0),
        |w| warnings.push(w.clone()),
        |_, _, e| est.push(e.to_vec()),
    );
    let t: Vec<f64> = log
        .lines()
        .skip(1)
        .take(est.len())
        .map(|l| l.split(',').next().unwrap().parse().unwrap_or(f64::NAN))
        .collect();
    Run {
        names,
        t,
        est,
        warnings,
        result,
        implausible_count: r.summary().count(WarningKind::Implausible),
    }
}

pub fn run(log: &str, rig: &RigConfig) -> Run {
    run_with(
        log,
        rig,
        ReaderOptions {
            limits: pendtilt::io::SensorLimits::of_rig(rig),
            ..ReaderOptions::default()
        },
    )
}

pub const TOLERANCE_DEG: f64 = 0.05;

/// How far apart two Madgwick runs can stay for good [deg]: its normalised gradient step
/// moves the tilt by 2 beta dt per sample whatever the error (the quaternion's half angle),
/// so when the accelerometer angle falls between two runs they swap sides by 4 beta dt
/// (0.27 deg at beta = 1.18 rad/s and 1 kHz) and never close the gap below that.
pub fn madgwick_resolution_deg() -> f64 {
    (4.0 * pendtilt::peers::ahrs_planar::MADGWICK_BETA * 1e-3).to_degrees()
}

/// Per estimator: the time after `t_end` from which it stays within 0.05 deg of the clean
/// run (0 when it never left), and the largest difference from `t_end + 2 s` on [deg].
pub fn recovery(clean: &Run, bad: &Run, t_end: f64) -> Vec<(&'static str, f64, f64)> {
    assert_eq!(clean.est.len(), bad.est.len(), "a row was lost");
    let mut out = Vec::new();
    for (j, name) in clean.names.iter().enumerate() {
        let mut last_out = None;
        let mut worst = 0.0f64;
        for (k, &t) in clean.t.iter().enumerate() {
            if t < t_end {
                continue;
            }
            let (a, b) = (clean.est[k][j].theta, bad.est[k][j].theta);
            let d = if a.is_nan() && b.is_nan() {
                0.0
            } else {
                (a - b).abs().to_degrees()
            };
            let d = if d.is_nan() { f64::INFINITY } else { d };
            if d > TOLERANCE_DEG {
                last_out = Some(t);
            }
            if t >= t_end + 2.0 {
                worst = worst.max(d);
            }
        }
        let back = last_out.map_or(0.0, |t| t - t_end + 1e-3);
        out.push((*name, back, worst));
    }
    out
}

/// The second criterion, for every estimator: from `t_from` on, what the fault left in its
/// output (RMS of the faulty run less the clean one) is no larger than its own error (RMS
/// of the clean run less the truth) over the same rows, or than the 0.05 deg tolerance for
/// an estimator more accurate than that: the fault poisoned nothing even where 0.05 deg of
/// the clean run is out of reach. Returns (name, left, own) [deg].
pub fn left_against_own_error(
    clean: &Run,
    bad: &Run,
    rows: &[SimRow],
    t_from: f64,
) -> Vec<(&'static str, f64, f64)> {
    let mut out = Vec::new();
    for (j, name) in clean.names.iter().enumerate() {
        let (mut left, mut own, mut n) = (0.0, 0.0, 0usize);
        for (k, &t) in clean.t.iter().enumerate() {
            let (a, b) = (clean.est[k][j].theta, bad.est[k][j].theta);
            if t < t_from || !a.is_finite() {
                continue;
            }
            left += (b - a).powi(2);
            own += (a - rows[k].truth.theta).powi(2);
            n += 1;
        }
        let rms = |x: f64| (x / n.max(1) as f64).sqrt().to_degrees();
        out.push((*name, rms(left), rms(own)));
    }
    out
}

/// Asserts [`left_against_own_error`] and prints it.
pub fn assert_nothing_poisoned(case: &str, clean: &Run, bad: &Run, rows: &[SimRow], t_from: f64) {
    assert_nothing_poisoned_but(case, clean, bad, rows, t_from, &[]);
}

/// [`assert_nothing_poisoned`] but for the estimators `except` (printed only).
pub fn assert_nothing_poisoned_but(
    case: &str,
    clean: &Run,
    bad: &Run,
    rows: &[SimRow],
    t_from: f64,
    except: &[&str],
) {
    for (name, left, own) in left_against_own_error(clean, bad, rows, t_from) {
        println!("  {case}: {name:<14} left {left:.4} deg RMS, own error {own:.4}");
        if except.contains(&name) {
            continue;
        }
        assert!(
            left.is_finite() && left <= own.max(TOLERANCE_DEG),
            "{case}: {name} left {left} deg RMS, more than its own error {own} and 0.05 deg"
        );
    }
}

pub fn print(case: &str, rec: &[(&str, f64, f64)]) {
    println!("{case}:");
    for (n, back, worst) in rec {
        println!(
            "  {n:<14} back within 0.05 deg after {back:.3} s; max diff from +2 s {worst:.4} deg"
        );
    }
}

pub fn gyro() -> Inputs {
    Inputs::GYRO
}

pub fn phi() -> Inputs {
    Inputs::PHI
}

pub fn retimed(rows: &[SimRow], scale: f64) -> String {
    let mut c = cells(rows);
    for (row, r) in c.iter_mut().zip(rows) {
        row[0] = format!("{}", (r.t * scale * 1e6).round() / 1e6);
    }
    text(&c)
}
