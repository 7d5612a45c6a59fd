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
use crate::tune::log::{header, TuneLog};
use crate::tune::{self, rig_file, Options, Start, Target};

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
    let log = TuneLog::read(&args.log, args.columns.reader_options(&rig), |m| {
        if !args.quiet {
            eprintln!("{m}");
        }
    })?;
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
    let header = header(&args.log, args.params.as_deref(), args.time_limit, &log, &t);
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
