//! The 3-D branch of `pendtilt estimate` (MODEL.md 7.6): the options of the command into
//! the 3-D pass ([`crate::pipeline::spatial`]), and its rows into the estimates file.
use std::path::Path;

use anyhow::Context;

use super::estimate::Args;
use crate::io::input::{LogSource, STDIN_NAME};
use crate::io::output::{self, NamedPath, OutputFile};
use crate::io::{Estimates3dWriter, Log3dReader};
use crate::pipeline::spatial::{
    columns, pass, pass_on, score_table, setup, Feed, Options3d, Pass, Row, Setup, Sink3d,
};
pub use crate::pipeline::spatial::{is_3d_log, refuse_3d_options};

/// The options of `pendtilt estimate` for the 3-D pass: the log read from `log`, named
/// `name` in messages (else by its path).
pub fn options<'a>(args: &'a Args, log: &'a Path, name: Option<&'a str>) -> Options3d<'a> {
    let b = &args.bank;
    Options3d {
        log,
        log_name: name,
        params: b.params.as_deref(),
        scenario: args.scenario.as_deref(),
        score_from: args.score_from,
        columns: &b.columns,
        only: b.only.as_deref(),
        quiet: b.quiet,
    }
}

/// `pendtilt estimate` on a 3-D log ([`super::estimate::estimate`]).
pub fn estimate(
    args: &Args,
    source: LogSource,
    name: &str,
) -> anyhow::Result<super::estimate::Outcome> {
    let path = match &source {
        LogSource::File(p) => p.clone(),
        LogSource::Stream { .. } => args.log.clone(),
    };
    let opts = options(args, &path, Some(name));
    output::check_distinct(&opts.inputs(), &[NamedPath::new("-o", &args.output)])?;
    let setup = setup(&opts)?;
    let out = OutputFile::create("-o", &args.output)?;
    let result = estimate_into(args, &opts, &setup, source, &out)
        .with_context(|| output::not_written(&args.output))?;
    out.commit()?;
    Ok(super::estimate::Outcome {
        rows: result.rows,
        estimators: result.names.iter().map(|n| n.to_string()).collect(),
        warnings: result.warnings.len() as u64,
        notes: result
            .warnings
            .iter()
            .map(|w| format!("warning: {w}"))
            .collect(),
        table: result.truth.then(|| score_table(&result)),
        scores: if result.truth {
            (result.names.iter().zip(&result.scores))
                .map(|(n, s)| super::estimate::Score {
                    name: n.to_string(),
                    rms: s.rms(),
                    max: s.max(),
                    scored: s.count(),
                })
                .collect()
        } else {
            Vec::new()
        },
    })
}

/// The estimates CSV (header written by [`Sink3d::start`]).
struct FileSink<'a> {
    out: &'a OutputFile,
    options: crate::io::WriterOptions,
    writer: Option<Estimates3dWriter<Box<dyn std::io::Write + Send>>>,
    /// Rows written, for the progress line.
    rows: u64,
    bar: indicatif::ProgressBar,
}

impl Sink3d for FileSink<'_> {
    fn start(
        &mut self,
        names: &[&'static str],
        quaternion: &[bool],
        truth: bool,
    ) -> anyhow::Result<()> {
        self.writer = Some(Estimates3dWriter::new(
            self.out.writer()?,
            columns(names, quaternion),
            truth,
            self.options,
        )?);
        Ok(())
    }

    fn row(&mut self, r: Row) -> anyhow::Result<()> {
        if let Some(w) = &mut self.writer {
            w.write(r.t, r.est, r.quats, r.truth)?;
        }
        self.rows += 1;
        // Every 64k rows: a counter the bar reads, not a draw per row.
        if self.rows % 65_536 == 0 {
            self.bar.set_position(self.rows);
        }
        Ok(())
    }
}

/// Estimates into the (uncommitted) output file, flushed.
fn estimate_into(
    args: &Args,
    opts: &Options3d,
    setup: &Setup,
    source: LogSource,
    out: &OutputFile,
) -> anyhow::Result<Pass> {
    let mut sink = FileSink {
        out,
        options: args.bank.writer_options(),
        writer: None,
        rows: 0,
        bar: super::options::progress(
            opts.log,
            "estimating {spinner} {human_pos} rows, {elapsed}",
            opts.quiet,
        ),
    };
    let q = args.quaternion;
    let result = match source {
        LogSource::File(_) => pass(opts, setup, q, &mut sink),
        // A pipe is read as it comes (the header was peeked at), as a file is read.
        LogSource::Stream { reader, .. } => {
            let name = opts.log_name.unwrap_or(STDIN_NAME);
            let renames = opts.columns.map.spatial();
            Log3dReader::new_mapped(reader, name, renames)
                .map_err(anyhow::Error::from)
                .and_then(|log| pass_on(log, name, opts, setup, q, &mut sink, Feed::File))
        }
    };
    sink.bar.finish_and_clear();
    let result = result?;
    if let Some(mut w) = sink.writer.take() {
        w.flush()?;
    }
    Ok(result)
}
