//! `pendtilt estimate LOG.csv --params RIG.toml -o OUT.csv`: a planar log through the bank
//! ([`crate::bank`]); a 3-D log (MODEL.md 7.6 columns) through [`super::estimate3d`].
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::options::BankOptions;
use crate::io::input::LogSource;
use crate::io::output::{self, NamedPath, OutputFile};
use crate::io::{Column, EstimatesWriter, LogReader};
use crate::pipeline;
pub use crate::pipeline::batch::{Outcome, Score};

/// Options of `pendtilt estimate`.
#[derive(Debug, clap::Args)]
#[command(after_help = super::help::estimate_after_help())]
pub struct Args {
    /// The sensor log (CSV, MODEL.md section 5; a 3-D log, MODEL.md 7.6); `-` for
    /// standard input.
    pub log: PathBuf,
    /// Where to write the estimates (CSV); `-` for standard output. Written to a temporary
    /// file and renamed into place only when the whole log was read.
    #[arg(long, short = 'o', visible_alias = "out")]
    pub output: PathBuf,
    /// Rig, column mapping, estimator choice and output form.
    #[command(flatten)]
    pub bank: BankOptions,
    /// 3-D logs: add `<name>_qw, _qx, _qy, _qz` (world <- body) for the estimators that
    /// have an attitude quaternion (ekf3d, ukf3d).
    #[arg(long)]
    pub quaternion: bool,
    /// 3-D logs: the scenario file `simulate` wrote beside the log; its sensor noise
    /// figures set ekf3d/ukf3d's, its `score_from` the scoring start, its rig the rig when
    /// there is no --params. Default: none (the filters' default noise figures).
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Score the error against the truth from this long after the first row (s), so the
    /// estimators' start-up is left out of the table. Default: the --scenario file's
    /// score_from (3-D), else 5 s (the whole log when it lasts less than 10 s).
    #[arg(long, value_name = "SECONDS")]
    pub score_from: Option<f64>,
}

/// Runs `pendtilt estimate`: refuses an output that is an input, writes the estimates to a
/// temporary file and renames it onto `-o` only when the whole log was read.
pub fn run(args: Args) -> anyhow::Result<()> {
    let outcome = estimate(&args)?;
    if !args.bank.quiet {
        super::summary::eprint(&format!(
            "{} rows -> {} ({} estimators)",
            outcome.rows,
            args.output.display(),
            outcome.estimators.len()
        ));
        for n in &outcome.notes {
            eprintln!("{n}");
        }
        if let Some(table) = &outcome.table {
            super::summary::print(crate::io::output::is_stdout(&args.output), table);
        }
    }
    Ok(())
}

/// `estimate` on one log, planar or 3-D, without the report at the end: the estimates
/// written to `-o` (committed only when the whole log was read) and what was found.
pub fn estimate(args: &Args) -> anyhow::Result<Outcome> {
    estimate_with(args, true)
}

/// [`estimate`] with a planar log read, estimated and written on three threads
/// (`parallel`, [`pipeline::run_parallel`]) or on this one (`batch` runs one log per core).
/// The output is the same bytes either way.
pub fn estimate_with(args: &Args, parallel: bool) -> anyhow::Result<Outcome> {
    output::check_distinct(
        &[NamedPath::new("LOG", &args.log)],
        &[NamedPath::new("-o", &args.output)],
    )?;
    // Standard input or a pipe is read as it comes: its header is peeked at, not copied.
    let (source, name) = LogSource::open(&args.log)?;
    // A map onto 3-D columns says the log is 3-D: the 3-D reader names what is amiss.
    let map = &args.bank.columns.map;
    let spatial = match &source {
        LogSource::File(p) => crate::pipeline::spatial::is_3d_log(p, map),
        LogSource::Stream { header, .. } => {
            (header.as_ref()).is_some_and(|h| crate::io::is_3d_header(&map.rename_spatial(h)))
        }
    };
    if spatial || !map.spatial_only().is_empty() {
        return super::estimate3d::estimate(args, source, &name);
    }
    crate::pipeline::spatial::refuse_3d_options(
        &[
            ("--quaternion", args.quaternion),
            ("--scenario", args.scenario.is_some()),
        ],
        std::path::Path::new(&name),
    )?;
    let opts = &args.bank;
    let mut inputs = vec![NamedPath::new("LOG", &args.log)];
    if let Some(p) = &opts.params {
        inputs.push(NamedPath::new("--params", p));
    }
    output::check_distinct(&inputs, &[NamedPath::new("-o", &args.output)])?;
    let out = OutputFile::create("-o", &args.output)?;
    let run = || -> anyhow::Result<_> {
        let rig = opts.rig()?;
        let reading = opts.reader_options(&rig);
        match source {
            LogSource::File(path) => {
                let log = LogReader::open_as(&path, &name, reading)?;
                estimate_into(args, &rig, log, &path, &out, parallel)
            }
            LogSource::Stream { reader, .. } => {
                let log = LogReader::new(reader, &name, reading)?;
                estimate_into(args, &rig, log, Path::new(""), &out, parallel)
            }
        }
    };
    let (names, log, summary) = run().with_context(|| output::not_written(&args.output))?;
    out.commit()?;
    let warnings = log.total_warnings();
    Ok(Outcome {
        rows: summary.rows,
        estimators: names,
        warnings,
        notes: (warnings > 0)
            .then(|| log.to_string())
            .into_iter()
            .collect(),
        table: (summary.errors.as_ref()).map(|e| pipeline::error_table(e, &summary.window)),
        scores: (summary.errors.iter().flatten())
            .map(|(name, e)| Score {
                name: name.clone(),
                rms: e.rms(),
                max: e.max_abs,
                scored: e.count,
            })
            .collect(),
    })
}

/// The log read through the bank into `out` (not yet committed): every row, flushed, or
/// an error. Returns the estimators, the reader's summary of warnings and the pass's.
fn estimate_into<R: std::io::BufRead + Send>(
    args: &Args,
    rig: &crate::config::RigConfig,
    mut log: LogReader<R>,
    path: &Path,
    out: &OutputFile,
    parallel: bool,
) -> anyhow::Result<(Vec<String>, crate::io::LogSummary, pipeline::PassSummary)> {
    let opts = &args.bank;
    let mut bank = opts.bank(rig, &log)?;
    let with_theta = log.columns().has(Column::Theta);
    let mut w = EstimatesWriter::new(
        out.writer()?,
        bank.names(),
        with_theta,
        opts.writer_options(),
    )?;
    let warn = |w: &crate::io::LogWarning| opts.warn(w);
    let bar = super::options::progress(
        path,
        "estimating {spinner} {human_pos} rows, {elapsed}",
        opts.quiet,
    );
    let each = |rows: u64, _: &crate::io::LogRecord, _: &[pendtilt_core::Estimate<f64>]| {
        // Every 64k rows: a counter the bar reads, not a draw per row.
        if rows % 65_536 == 0 {
            bar.set_position(rows);
        }
    };
    // run_parallel joins its writer thread before it returns: every row is in `w` here.
    let score_from = args.score_from;
    let summary = if parallel {
        pipeline::run_parallel(&mut log, &mut bank, Some(&mut w), score_from, warn, each)
    } else {
        let out = Some(&mut w);
        pipeline::run(&mut log, &mut bank, out, false, score_from, warn, each)
    };
    bar.finish_and_clear();
    let summary = summary?;
    w.flush()?;
    drop(w);
    let names = bank.names().iter().map(|n| n.to_string()).collect();
    Ok((names, log.summary().clone(), summary))
}
