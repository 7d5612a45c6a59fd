//! `pendtilt report LOG.csv --params RIG.toml -o DIR`: metrics (unfiltered and after the
//! paper's 20 Hz FIR), figures, Markdown, JSON and one HTML page for a log with a true angle.
//! A 3-D log (MODEL.md 7.6 columns) goes to [`super::report3d`].
use std::path::PathBuf;

use anyhow::Context;

use crate::config::RigConfig;
use crate::experiment::claims::{self as paper, DifferentiatorInfo};
use crate::experiment::estimate::{alg2_delay_compensated, run_estimators};
use crate::experiment::progress::{Progress, CHUNK};
use crate::experiment::standard::standard_report;
use crate::experiment::Ride;
use crate::io::output::{self, NamedPath, OutputDir};
use crate::io::plateau::LOOK_AHEAD_ROWS;
use crate::io::{Column, LogReader, ReaderOptions};
use crate::pipeline::{self, duration, ClipFinder, Window, DEFAULT_SCORE_FROM, SHORT_LOG};
use crate::report::markdown::{claims_markdown, metrics_markdown};
use crate::report::metrics::MetricsConfig;

use super::options::rig_bank_settings;
use super::reproduce::Bars;

/// Options of `pendtilt report`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sensor log (CSV, MODEL.md section 5); it must have the true angle `theta`. A 3-D
    /// log (MODEL.md 7.6) must have the true `roll` and `pitch`.
    pub log: PathBuf,
    /// The rig file (TOML; a 3-D rig for a 3-D log). Without it the MODEL.md default rig is
    /// used, and said so.
    #[arg(long, short = 'p')]
    pub params: Option<PathBuf>,
    /// Directory to write into (created): index.html, report.md, report.json, figures.
    /// Files already there that the report does not write are left alone.
    #[arg(long, short = 'o', visible_alias = "out")]
    pub output: PathBuf,
    /// How the log's columns are named and in which units.
    #[command(flatten)]
    pub columns: crate::cli::options::LogColumns,
    /// Title of the report (default: the log's file name).
    #[arg(long)]
    pub title: Option<String>,
    /// No progress bars and no notes on standard error.
    #[arg(long, short = 'q')]
    pub quiet: bool,
    /// 3-D logs: the scenario file `simulate` wrote beside the log (sensor noise figures,
    /// scoring start, and the rig when there is no --params), as for `estimate`. Default:
    /// none (the filters' default noise figures).
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Score the error against the truth from this long after the first row (s); the
    /// figures still show the whole log. Default: the --scenario file's score_from (3-D),
    /// else 5 s, as `estimate` (the whole log when it lasts less than 10 s).
    #[arg(long, value_name = "SECONDS")]
    pub score_from: Option<f64>,
}

/// Reads a whole log with a true angle into memory (rows without `theta` get NaN), with
/// the clips found in it for the sensors whose full scale `settings` does not give
/// ([`crate::io::plateau`]). Every warning goes through `progress` and is returned too,
/// for the page, with the count of all of them (the reader lists the first ten of a kind
/// and counts the rest).
pub fn read_log(
    path: &std::path::Path,
    options: ReaderOptions,
    settings: &crate::bank::planar::BankSettings,
    progress: &dyn Progress,
) -> anyhow::Result<(Ride, crate::sensors::Inputs, Vec<String>, usize)> {
    let mut said = Vec::new();
    let mut warn = |w: String| {
        progress.message(&format!("warning: {w}"));
        said.push(w);
    };
    let mut log = LogReader::open(path, options)?;
    anyhow::ensure!(
        log.columns().has(Column::Theta),
        "{}: the log has no `theta` column (the true angle): a report compares the \
         estimates with it (map another name with --map theta=NAME)",
        log.file()
    );
    let inputs = pipeline::inputs_of(&log);
    let mut ride = Ride {
        label: log.file().to_string(),
        t: Vec::new(),
        samples: Vec::new(),
        theta: Vec::new(),
        theta_dd: Vec::new(),
        clipped: Vec::new(),
    };
    progress.stage(&format!("reading {}", log.file()), 0);
    let mut clips = ClipFinder::new(&log, settings, LOOK_AHEAD_ROWS);
    let (mut end, mut clip_warnings) = (false, 0usize);
    loop {
        // Past the end only the rows held are left.
        let read = if end { None } else { log.next_record()? };
        for w in log.drain_warnings() {
            warn(w.to_string());
        }
        end = read.is_none();
        let next = match read {
            Some(rec) => clips.push(rec),
            None => clips.pop(),
        };
        for w in clips.drain_warnings() {
            clip_warnings += 1;
            warn(w.to_string());
        }
        let Some((rec, clipped)) = next else {
            if end {
                break;
            }
            continue;
        };
        ride.t.push(rec.t);
        ride.samples.push(rec.sample);
        ride.theta.push(rec.theta.unwrap_or(f64::NAN));
        ride.clipped.push(clipped);
        if ride.t.len() as u64 % CHUNK == 0 {
            progress.advance(CHUNK);
        }
    }
    for w in log.drain_warnings() {
        warn(w.to_string());
    }
    // A column in the wrong unit leads the page's few: it explains the rest (a gyro in
    // deg/s is also thousands of readings beyond its full scale, listed first).
    let is_unit = |w: &String| log.unit_findings().iter().any(|f| w.ends_with(&f.message));
    let (mut first, rest): (Vec<String>, Vec<String>) = said.into_iter().partition(is_unit);
    first.extend(rest);
    let said = first;
    if log.summary().total_warnings() > 0 {
        progress.message(&log.summary().to_string());
    }
    anyhow::ensure!(ride.len() >= 2, "{}: fewer than two data rows", log.file());
    // The reader's own count, with what it did not list, and the clips found.
    let total = log.summary().total_warnings() as usize + clip_warnings;
    Ok((ride, inputs, said, total))
}

/// Runs `pendtilt report`: writes every file into a staging directory beside `-o` and
/// moves them in only when the whole report was made, after checking that none of them is
/// the log or the rig file.
pub fn run(args: Args) -> anyhow::Result<()> {
    if crate::pipeline::spatial::is_3d_log(&args.log, &args.columns.map) {
        return super::report3d::run(args);
    }
    crate::pipeline::spatial::refuse_3d_options(
        &[("--scenario", args.scenario.is_some())],
        &args.log,
    )?;
    let bars = Bars::new(args.quiet);
    let out = OutputDir::create("-o", &args.output)?;
    let result = report(&args, out.staging(), &bars);
    bars.finish();
    let html = result.with_context(|| output::not_written(&args.output))?;
    let html = out.final_path(&html);
    let mut inputs = vec![NamedPath::new("LOG", &args.log)];
    if let Some(p) = &args.params {
        inputs.push(NamedPath::new("--params", p));
    }
    out.commit(&inputs)?;
    super::summary::say!("wrote {}", html.display());
    Ok(())
}

/// Makes the report in `dir`; returns the page's path.
fn report(args: &Args, dir: &std::path::Path, bars: &Bars) -> anyhow::Result<PathBuf> {
    let rig = match &args.params {
        Some(p) => super::options::load_rig(p, args.quiet)?,
        None => {
            bars.message("note: no --params: using the default rig of MODEL.md section 5");
            RigConfig::default()
        }
    };
    let settings = rig_bank_settings(&rig);
    let options = args.columns.reader_options(&rig);
    let (ride, inputs, warnings, total) = read_log(&args.log, options, &settings, bars)?;
    let extras = if inputs.covers(crate::sensors::Inputs::PHI_GYRO) {
        vec![alg2_delay_compensated(&settings)]
    } else {
        Vec::new()
    };
    let series = run_estimators(&ride, &settings, inputs, extras, bars)
        .map_err(|e| anyhow::anyhow!("{}: {e}", ride.label))?;
    anyhow::ensure!(
        !series.is_empty(),
        "{}: no estimator can run on this log's columns",
        ride.label
    );
    bars.stage("metrics and figures", 0);
    let title = args.title.clone().unwrap_or_else(|| {
        args.log
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| ride.label.clone())
    });
    let label = ride.label.clone();
    let window = score_window(&ride.t, args.score_from, &label)?;
    let (report, _) = standard_report(&title, ride.t, ride.theta, series)
        .with_context(|| format!("{label}: cannot build the report"))?;
    let config = MetricsConfig {
        score_from_s: window.from,
        ..MetricsConfig::default()
    };
    let mut report = report.config(config).intro(&window_paragraph(&window));
    if let Some(text) = warnings_paragraph(&warnings, total) {
        report = report.intro(&text);
    }
    // The paper's claims, on this log's metrics (claim 4's overshoot only on a step).
    let computed = report.compute()?;
    let view = computed
        .views
        .iter()
        .find(|v| v.view == computed.claims_view)
        .unwrap_or(&computed.views[0]);
    for c in paper_claims(&view.metrics, &settings, &rig) {
        report = report.claim(c);
    }
    let out = report
        .write(dir)
        .with_context(|| format!("cannot write the report into {}", args.output.display()))?;
    bars.finish();
    for v in &out.data.views {
        super::summary::say!("Metrics ({}):\n{}", v.view, metrics_markdown(&v.metrics));
    }
    if !out.data.claims.is_empty() {
        super::summary::say!(
            "Claims ({}):\n{}",
            out.data.claims_view,
            claims_markdown(&out.data.claims)
        );
    }
    Ok(out.html)
}

/// The rows the report scores ([`Window::resolve`], as `estimate`), or why none.
fn score_window(t: &[f64], requested: Option<f64>, file: &str) -> anyhow::Result<Window> {
    let (first, last) = (t.first().unwrap_or(&0.0), t.last().unwrap_or(&0.0));
    let span = last - first;
    let window = Window::resolve(requested, duration(*first, *last, t.len() as u64));
    anyhow::ensure!(
        window.from.is_finite() && window.from < span,
        "{file}: --score-from {} s leaves no row to score: the last row is at t0 + {span:.3} s",
        window.from
    );
    Ok(window)
}

/// What the page says of the rows it scores.
fn window_paragraph(window: &Window) -> String {
    let why = match window.short_log {
        Some(span) => format!(
            "the whole log: it lasts {span:.1} s, under the {SHORT_LOG} s from which the first \
             {DEFAULT_SCORE_FROM} s are left out"
        ),
        None if window.from == 0.0 => "the whole log, as asked".to_string(),
        None => "the estimators' start-up is left out, as pendtilt estimate leaves it; \
                 --score-from SECONDS sets the start, 0 for the whole log"
            .to_string(),
    };
    format!(
        "Errors, lags and the claims are scored from {} s after the first row on ({why}); the \
         figures show the whole log, and overshoot and settling time are measured on it.",
        window.from
    )
}

/// What the page says of the log's warnings (a clip found, an impossible reading, a gap):
/// how many, and the first few, so that the figures are not read as those of a clean log
/// (also at the top of the 3-D page, whose notes list them all).
/// `total` counts the warnings the reader did not list too (at least `warnings.len()`).
pub(crate) fn warnings_paragraph(warnings: &[String], total: usize) -> Option<String> {
    const SHOWN: usize = 3;
    let (first, n) = (warnings.iter().take(SHOWN), total.max(warnings.len()));
    if n == 0 {
        return None;
    }
    let mut text = format!(
        "Reading the log gave {n} warning{}, which the figures below carry: {}",
        if n == 1 { "" } else { "s" },
        first.cloned().collect::<Vec<_>>().join(" | ")
    );
    if n > SHOWN {
        text.push_str(&format!(
            " | and {} more ({} listed on the command's standard error, every one counted in \
             its summary)",
            n - SHOWN,
            warnings.len()
        ));
    }
    Some(text)
}

/// The paper's claims on `metrics` (claim 4 with the rig's gains unless they are Eq 21's),
/// and the delay-compensation claim when its estimator ran.
fn paper_claims(
    metrics: &[crate::report::metrics::Metrics],
    settings: &crate::bank::planar::BankSettings,
    rig: &RigConfig,
) -> Vec<crate::report::claims::ClaimSpec> {
    let info = DifferentiatorInfo::of(settings);
    let gains = if rig.alg3_gains_are_eq21() {
        paper::Alg3Gains::Eq21Equivalent
    } else {
        paper::Alg3Gains::FromRig
    };
    let mut claims = paper::paper_claims(metrics, false, &info, gains);
    if metrics.iter().any(|m| m.name == paper_dc()) {
        claims.push(paper::delay_compensation_claim(metrics));
    }
    claims
}

fn paper_dc() -> &'static str {
    crate::experiment::estimate::ALG2_DELAY_COMPENSATED
}
