//! `pendtilt stream`: estimates from log lines on standard input, as they arrive.
//!
//! The header line comes first; after it, every data line read from standard input is
//! run through the estimator bank at once and its estimate line written to standard
//! output and flushed before the next input line is read. Nothing is read ahead: the log
//! reader takes one line at a time from the (buffered) standard input, and a buffered
//! read returns what the pipe has rather than waiting for a full buffer. So a rig on a
//! serial port can be followed live, for example
//! `socat -u /dev/ttyUSB0,raw,b115200 - | pendtilt stream --params rig.toml --flags`.
//!
//! A 3-D log (MODEL.md 7.6, told by its header) runs through the 3-D estimators the same
//! way, one flushed row per line.
//!
//! A malformed line (a cell that is no number, the wrong number of fields) is skipped and
//! said on standard error with its line; its output row is NaN, flagged `bad_line`, so the
//! rows still match the lines. Only what a live feed cannot recover from stops it: a
//! header that is no log's, a time unit the physics refutes, a failed read or write.
//!
//! Messages (columns found, skipped estimators, warnings, a read error naming the line and
//! column) go to standard error; standard output carries only the estimates CSV.
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};

use super::options::BankOptions;
use crate::io::input::{peek_header, STDIN_NAME};
use crate::io::{Column, Estimates3dWriter, EstimatesWriter, LogReader, LogWarning};
use crate::pipeline;
use crate::pipeline::spatial::{self, Feed, Options3d, Row, Sink3d};

/// Options of `pendtilt stream`.
#[derive(Debug, clap::Args)]
#[command(after_help = super::help::estimate_after_help())]
pub struct Args {
    /// Rig, column mapping, estimator choice and output form.
    #[command(flatten)]
    pub bank: BankOptions,
    /// 3-D logs: add `<name>_qw, _qx, _qy, _qz` (world <- body) for the estimators that
    /// have an attitude quaternion (ekf3d, ukf3d). Default: off.
    #[arg(long)]
    pub quaternion: bool,
    /// 3-D logs: the scenario file `simulate` wrote beside the log (sensor noise figures
    /// for ekf3d/ukf3d, the rig when there is no --params). Default: none.
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
}

/// Runs `pendtilt stream` over standard input and output.
pub fn run(args: Args) -> anyhow::Result<()> {
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    run_on(args, stdin.lock(), stdout.lock())
}

/// Runs `pendtilt stream` over any line source and sink (standard input and output in
/// the command): one flushed estimate line per input data line.
pub fn run_on<R: BufRead, W: Write>(args: Args, input: R, output: W) -> anyhow::Result<()> {
    let (header, input) = peek_header(input)?;
    let map = &args.bank.columns.map;
    let spatial = header.is_some_and(|h| crate::io::is_3d_header(&map.rename_spatial(&h)));
    if spatial || !map.spatial_only().is_empty() {
        return run_3d(&args, input, output);
    }
    spatial::refuse_3d_options(
        &[
            ("--quaternion", args.quaternion),
            ("--scenario", args.scenario.is_some()),
        ],
        Path::new(STDIN_NAME),
    )?;
    let opts = &args.bank;
    let rig = opts.rig()?;
    let mut log = LogReader::new(input, STDIN_NAME, opts.reader_options(&rig))?;
    let mut bank = opts.bank(&rig, &log)?;
    let with_theta = log.columns().has(Column::Theta);
    let wopts = opts.writer_options();
    let warn = |w: &LogWarning| opts.warn(w);
    let mut w = EstimatesWriter::new(output, bank.names(), with_theta, wopts)?;
    // The header goes out at once, so that a reader downstream sees the columns before
    // the first sample.
    w.flush()?;
    let summary = pipeline::run(
        &mut log,
        &mut bank,
        Some(&mut w),
        true,
        None,
        warn,
        |_, _, _| {},
    )?;
    if !opts.quiet {
        super::summary::say_err!("{} rows streamed", summary.rows);
        if log.summary().total_warnings() > 0 {
            eprintln!("{}", log.summary());
        }
    }
    Ok(())
}

/// A 3-D log from a live input: the 3-D estimators, one flushed row per line.
fn run_3d<R: BufRead, W: Write>(args: &Args, input: R, output: W) -> anyhow::Result<()> {
    let b = &args.bank;
    let opts = Options3d {
        log: Path::new("-"),
        log_name: Some(STDIN_NAME),
        params: b.params.as_deref(),
        scenario: args.scenario.as_deref(),
        score_from: None,
        columns: &b.columns,
        only: b.only.as_deref(),
        quiet: b.quiet,
    };
    let setup = spatial::setup(&opts)?;
    let log = crate::io::Log3dReader::new_mapped(input, STDIN_NAME, b.columns.map.spatial())?;
    let mut sink = LiveSink {
        out: Some(output),
        options: b.writer_options(),
        writer: None,
    };
    let pass = spatial::pass_on(
        log,
        STDIN_NAME,
        &opts,
        &setup,
        args.quaternion,
        &mut sink,
        Feed::Live,
    )?;
    if !b.quiet {
        super::summary::say_err!("{} rows streamed", pass.rows);
        for w in &pass.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(())
}

/// The 3-D estimates on a live output: the header at once, then each row flushed.
struct LiveSink<W: Write> {
    out: Option<W>,
    options: crate::io::WriterOptions,
    writer: Option<Estimates3dWriter<W>>,
}

impl<W: Write> Sink3d for LiveSink<W> {
    fn start(
        &mut self,
        names: &[&'static str],
        quaternion: &[bool],
        truth: bool,
    ) -> anyhow::Result<()> {
        let columns = spatial::columns(names, quaternion);
        if let Some(out) = self.out.take() {
            let mut w = Estimates3dWriter::new(out, columns, truth, self.options)?;
            w.flush()?;
            self.writer = Some(w);
        }
        Ok(())
    }

    fn row(&mut self, r: Row) -> anyhow::Result<()> {
        if let Some(w) = &mut self.writer {
            w.write(r.t, r.est, r.quats, r.truth)?;
            w.flush()?;
        }
        Ok(())
    }
}
