//! `pendtilt tune LOG.csv --params RIG.toml -o TUNED.toml`: every estimator's settings
//! from the log itself ([`crate::tune`]), written as a rig file that `pendtilt estimate`
//! reads as it is, each tuned value with a comment saying how it was found.
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::config::RigConfig;
use crate::io::output::{self, NamedPath};
use crate::io::{Column, LogReader};
use crate::tune::{self, rig_file, Options, Start, Target, Tuned};
use pendtilt_core::Sample;

/// What `tune` tunes the filters against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TuneTarget {
    /// No true angle needed: the filters' own innovations, and for the kf_* filters' Q and
    /// R (with a gyro) a surrogate of their error built from the gyro.
    Likelihood,
    /// The RMS error against the log's `theta` column (a calibration ride).
    Truth,
}

/// Options of `pendtilt tune`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sensor log (CSV): planar (MODEL.md section 5: t, phi and, for most values,
    /// gyro, ax, ay) or 3-D (MODEL.md 7.6: t, phi_x, phi_y, gyro_x..z, ax..az, speed
    /// optional; ekf3d's `[ekf3d]` table is tuned). No true angle needed.
    pub log: PathBuf,
    /// Where to write the tuned rig file (TOML). Never one of the inputs.
    #[arg(long, short = 'o', visible_alias = "out")]
    pub output: PathBuf,
    /// The rig file to start from (its pendulum, and every value the log cannot tell; a
    /// 3-D rig file for a 3-D log). Default: the MODEL.md rig.
    #[arg(long, short = 'p')]
    pub params: Option<PathBuf>,
    /// What the Kalman filters and the EKF are tuned against: `likelihood` (no true angle:
    /// their own innovations, and the gyro's surrogate of the kf_* filters' error) or
    /// `truth` (the log's `theta` column).
    #[arg(long, value_enum, default_value = "likelihood")]
    pub target: TuneTarget,
    /// Stop the searches after this many seconds and write the best found so far (the
    /// file says so). Default: no limit.
    #[arg(long, value_name = "SECONDS")]
    pub time_limit: Option<f64>,
    /// The filters are fitted on at most this much of the log (s) (the noise figures
    /// use all of it).
    #[arg(long, default_value_t = 60.0, value_name = "SECONDS")]
    pub fit_seconds: f64,
    /// How the log's columns are named and in which units.
    #[command(flatten)]
    pub columns: crate::cli::options::LogColumns,
    /// Print nothing but errors.
    #[arg(long, short = 'q')]
    pub quiet: bool,
}

/// Runs `pendtilt tune`: refuses an output that is an input, tunes, and writes the rig
/// file all at once (an earlier file stays as it was when tuning fails).
pub fn run(args: Args) -> anyhow::Result<()> {
    let mut inputs = vec![NamedPath::new("LOG", &args.log)];
    if let Some(p) = &args.params {
        inputs.push(NamedPath::new("--params", p));
    }
    output::check_distinct(&inputs, &[NamedPath::new("-o", &args.output)])?;
    let text = tuned_text(&args).with_context(|| output::not_written(&args.output))?;
    output::write_atomic("-o", &args.output, text.as_bytes())?;
    if !args.quiet {
        super::summary::say_err!("wrote {}", args.output.display());
    }
    Ok(())
}

/// The log's rows as samples, and the true angle per row (NaN without one).
struct TuneLog {
    samples: Vec<Sample<f64>>,
    truth: Option<Vec<f64>>,
    /// The unit check's findings (a gyro in deg/s, ...), as `estimate` says them.
    units: Vec<crate::units::Finding>,
    /// The reader's summary line (rows, time span, warnings by kind).
    summary: String,
}

/// Reads the whole log (warnings printed unless `--quiet`).
fn read_log(args: &Args, rig: &RigConfig) -> anyhow::Result<TuneLog> {
    let options = args.columns.reader_options(rig);
    let mut log = LogReader::open(&args.log, options)?;
    if !args.quiet {
        eprintln!("{}: {}", log.file(), log.columns());
    }
    anyhow::ensure!(
        log.columns().has(Column::Phi),
        "{}: no phi column: nothing to tune (map another name with --map phi=NAME)",
        log.file()
    );
    let has_theta = log.columns().has(Column::Theta);
    let (mut samples, mut truth) = (Vec::new(), Vec::new());
    while let Some(rec) = log.next_record()? {
        if !args.quiet {
            for w in log.drain_warnings() {
                eprintln!("warning: {w}");
            }
        }
        samples.push(rec.sample);
        truth.push(rec.theta.unwrap_or(f64::NAN));
    }
    // The end of the log's warnings: the unit check's (a gyro in deg/s tuned on silently
    // gave settings fitted to readings 57x too large, and said only the first ten of those
    // beyond the rig's full scale).
    if !args.quiet {
        for w in log.drain_warnings() {
            eprintln!("warning: {w}");
        }
    }
    let units = log.unit_findings().to_vec();
    Ok(TuneLog {
        samples,
        truth: has_theta.then_some(truth),
        units,
        summary: log.summary().to_string(),
    })
}

/// A progress bar on standard error over the planned evaluations (hidden when quiet, not
/// a terminal, or the log is shorter than 20 s at 1 kHz).
fn progress_bar(rows: usize, quiet: bool) -> ProgressBar {
    if quiet || rows < 20_000 || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::with_draw_target(
        Some(tune::planned_evaluations()),
        ProgressDrawTarget::stderr(),
    );
    b.set_style(
        ProgressStyle::with_template("tuning {bar:40} {percent:>3}% {pos}/{len} passes, eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    b
}

/// Reads, tunes, prints what was found and returns the rig file's text (a 3-D log's
/// through [`super::tune3d`]).
fn tuned_text(args: &Args) -> anyhow::Result<String> {
    if super::estimate3d::is_3d_log(&args.log, &args.columns.map) {
        return super::tune3d::tuned_text(args);
    }
    let rig = match &args.params {
        Some(p) => super::options::load_rig(p, args.quiet)?,
        None => RigConfig::default(),
    };
    let log = read_log(args, &rig)?;
    let target = match (args.target, &log.truth) {
        (TuneTarget::Likelihood, _) => Target::Likelihood,
        (TuneTarget::Truth, Some(t)) => Target::Truth(t),
        (TuneTarget::Truth, None) => anyhow::bail!(
            "{}: --target truth needs a theta column (a true angle), and the log has none; \
             leave --target out to tune on the likelihood, which needs none",
            args.log.display()
        ),
    };
    let time_limit = match args.time_limit {
        Some(s) if s.is_finite() && s >= 0.0 => Some(Duration::from_secs_f64(s)),
        Some(s) => anyhow::bail!("--time-limit {s}: must be a number of seconds >= 0"),
        None => None,
    };
    anyhow::ensure!(
        args.fit_seconds.is_finite() && args.fit_seconds > 0.0,
        "--fit-seconds {}: must be > 0",
        args.fit_seconds
    );
    let bar = progress_bar(log.samples.len(), args.quiet);
    let tell = |n: u64, _total: u64| bar.set_position(n);
    let opts = Options {
        target,
        time_limit,
        progress: Some(&tell),
        fit_seconds: args.fit_seconds,
    };
    let start = Start::from_rig(&rig);
    let t = tune::tune(&log.samples, &start, &opts);
    bar.finish_and_clear();
    let header = header(args, &log, &t);
    if !args.quiet {
        let data_on_stdout = crate::io::output::is_stdout(&args.output);
        for h in &header {
            super::summary::print(data_on_stdout, h);
        }
        for n in &t.notes {
            let kept = if n.kept_default {
                " (kept default)"
            } else {
                ""
            };
            super::summary::print(data_on_stdout, &format!("  {} = {}{kept}", n.key, n.value));
        }
    }
    for n in t.notes.iter().filter(|n| n.fell_back && !args.quiet) {
        eprintln!(
            "warning: {}: {} = {}: {}",
            args.log.display(),
            n.key,
            n.value,
            n.how
        );
    }
    let tuned = rig_file::tuned_rig(&rig, &t);
    tuned.validate()?;
    Ok(rig_file::annotated_toml(&tuned, &t, &header))
}

/// What the file's first comment lines and standard output say: the log, the target, the
/// likelihood (or error) before and after each fit ([`fit_lines`]), and whether the time
/// limit cut in.
fn header(args: &Args, log: &TuneLog, t: &Tuned) -> Vec<String> {
    let rate = tune::sample_rate(&log.samples).unwrap_or(f64::NAN);
    let start = args
        .params
        .as_ref()
        .map_or("the default rig (MODEL.md)".to_string(), |p| {
            p.display().to_string()
        });
    let mut h = vec![
        format!(
            "pendtilt tune: {} ({} rows, {:.1} s at {:.0} Hz), starting from {start}",
            args.log.display(),
            log.samples.len(),
            log.samples.len() as f64 / rate,
            rate
        ),
        match t.target {
            "truth" => "target: the true angle (the log's theta column): RMS error [rad]".into(),
            _ => "target: the likelihood of the filters' own innovations (no true angle used): \
                  mean -log-likelihood per innovation, lower is better"
                .to_string(),
        },
    ];
    h.extend(fit_lines(t));
    if t.kalman_fit.is_none() {
        h.push("the filters were not fitted (see the notes): their noise kept as given".into());
    }
    h.push(format!("the log: {}", log.summary));
    for f in &log.units {
        h.push(format!(
            "NOT TO BE TRUSTED: tuned on a log whose units look wrong: {}",
            f.message
        ));
    }
    if t.stopped_by_time_limit {
        h.push(format!(
            "STOPPED EARLY by --time-limit {} s: the best values found so far are written",
            args.time_limit.unwrap_or(0.0)
        ));
    }
    h
}

/// One line per fit: the Kalman filters' Q and R, the accelerometer's R alone and beside
/// Algorithm 2, the EKF's process noise ([`ekf_line`]).
fn fit_lines(t: &Tuned) -> Vec<String> {
    let mut h = Vec::new();
    let what = if t.target == "truth" {
        "RMS error"
    } else {
        "innovation likelihood (mean -log L)"
    };
    match (&t.kalman_fit, &t.kalman_surrogate) {
        (Some(f), Some(s)) => {
            h.push(format!(
                "kf_alg2 {what}: before {:.5}, after {:.5} (its own optimum {:.5} not adopted: \
                 see [kalman])",
                f.nll_before, s.nll_at, f.nll_after
            ));
            h.push(format!(
                "kf_alg2 predicted RMS error (surrogate from the gyro) [deg]: before {:.4}, \
                 after {:.4}",
                s.rms_before.to_degrees(),
                s.rms_after.to_degrees()
            ));
        }
        (Some(f), None) => h.push(format!(
            "kf_alg2 {what}: before {:.5}, after {:.5}",
            f.nll_before, f.nll_after
        )),
        _ => {}
    }
    match t.accel_fit {
        Some(a) if a.surrogate => h.push(format!(
            "kf_accel predicted RMS error (surrogate from the gyro; the accelerometer's error \
             below {} Hz, the body's own acceleration, taken as its difference from Algorithm \
             2) [deg]: before {:.4}, after {:.4}",
            tune::reference::CORNER_HZ,
            a.before.to_degrees(),
            a.after.to_degrees()
        )),
        Some(a) => h.push(format!(
            "kf_accel {what}: before {:.5}, after {:.5}",
            a.before, a.after
        )),
        None => {}
    }
    if let Some(a) = t.fused_fit {
        let on = if a.surrogate {
            "predicted RMS error (surrogates from the gyro)"
        } else {
            "RMS error against the truth"
        };
        h.push(format!(
            "kf_fused {on} [deg], its accelerometer R alone fitted: before {:.4}, after {:.4}",
            a.before.to_degrees(),
            a.after.to_degrees()
        ));
    }
    if let Some(e) = &t.ekf_fit {
        h.push(ekf_line(t, e, what));
    }
    h
}

/// The EKF's fit: its cost before and after, and whether it was adopted and why.
fn ekf_line(t: &Tuned, e: &tune::ekf::EkfFitted, what: &str) -> String {
    let adopted = match (t.target, t.ekf_band) {
        ("truth", _) => "adopted".to_string(),
        (_, Some((k, f))) if f < k => format!(
            "adopted: error against the gyro's integral above 0.2 Hz {:.4} -> {:.4} deg",
            k.to_degrees(),
            f.to_degrees()
        ),
        (_, Some((k, f))) => format!(
            "not adopted: error against the gyro's integral above 0.2 Hz {:.4} deg with \
             it, {:.4} without",
            f.to_degrees(),
            k.to_degrees()
        ),
        _ => "not adopted (no gyro bias estimate to check it against)".to_string(),
    };
    format!(
        "ekf {what}: before {:.5}, after {:.5} ({adopted})",
        e.nll_before, e.nll_after
    )
}
