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
//! Messages (columns found, skipped estimators, warnings, a read error naming the line and
//! column) go to standard error; standard output carries only the estimates CSV.
use super::options::BankOptions;
use crate::io::{Column, EstimatesWriter, LogReader, LogWarning};
use crate::pipeline;

/// Options of `pendtilt stream`.
#[derive(Debug, clap::Args)]
#[command(after_help = super::help::estimate_after_help())]
pub struct Args {
    /// Rig, column mapping, estimator choice and output form.
    #[command(flatten)]
    pub bank: BankOptions,
}

/// Runs `pendtilt stream` over standard input and output.
pub fn run(args: Args) -> anyhow::Result<()> {
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    run_on(args, stdin.lock(), stdout.lock())
}

/// Runs `pendtilt stream` over any line source and sink (standard input and output in
/// the command): one flushed estimate line per input data line.
pub fn run_on<R: std::io::BufRead, W: std::io::Write>(
    args: Args,
    input: R,
    output: W,
) -> anyhow::Result<()> {
    let opts = &args.bank;
    let rig = opts.rig()?;
    let mut log = LogReader::new(input, "<stdin>", opts.reader_options(&rig))?;
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
        pipeline::DEFAULT_SCORE_FROM,
        warn,
        |_, _| {},
    )?;
    if !opts.quiet {
        eprintln!("{} rows streamed", summary.rows);
        if log.summary().total_warnings() > 0 {
            eprintln!("{}", log.summary());
        }
    }
    Ok(())
}
