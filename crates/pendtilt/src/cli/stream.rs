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
use std::path::PathBuf;

use crate::bank::Bank;
use crate::cli::estimate::rig_bank_settings;
use crate::config::RigConfig;
use crate::io::{
    Column, ColumnMap, DegreeColumns, EstimatesWriter, LogReader, LogWarning, ReaderOptions,
    WriterOptions,
};
use crate::pipeline;

/// Options of `pendtilt stream`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The rig file (TOML). Without it the MODEL.md default rig is used, and said so.
    #[arg(long, short = 'p')]
    pub params: Option<PathBuf>,
    /// Other column names, e.g. `phi=enc_angle,gyro=gz`.
    #[arg(long, default_value = "")]
    pub map: ColumnMap,
    /// Angular columns in degrees: alone, every one (phi, gyro, theta); or a list like
    /// `phi,theta`.
    #[arg(long, num_args = 0..=1, default_missing_value = "all")]
    pub deg: Option<DegreeColumns>,
    /// Write the estimates (and theta) in degrees.
    #[arg(long)]
    pub out_deg: bool,
    /// Add a `<name>_flags` column per estimator.
    #[arg(long)]
    pub flags: bool,
    /// Run only these estimators (comma-separated).
    #[arg(long, value_delimiter = ',')]
    pub only: Option<Vec<String>>,
    /// Print nothing but errors on standard error.
    #[arg(long, short = 'q')]
    pub quiet: bool,
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
    let rig = match &args.params {
        Some(p) => RigConfig::load(p)?,
        None => {
            if !args.quiet {
                eprintln!("note: no --params: using the default rig of MODEL.md section 5");
            }
            RigConfig::default()
        }
    };
    let settings = rig_bank_settings(&rig);
    let options = ReaderOptions {
        map: args.map.clone(),
        degrees: args.deg.unwrap_or_default(),
        ..ReaderOptions::default()
    };
    let mut log = LogReader::new(input, "<stdin>", options)?;
    if !args.quiet {
        eprintln!("{}: {}", log.file(), log.columns());
    }
    let mut bank = Bank::new(&settings, pipeline::inputs_of(&log), args.only.as_deref())
        .map_err(anyhow::Error::msg)?;
    if !args.quiet {
        for s in bank.skipped() {
            eprintln!(
                "skipped {}: the log has no {}",
                s.name,
                s.lacking.join(", ")
            );
        }
    }
    anyhow::ensure!(
        !bank.names().is_empty(),
        "{}: no estimator can run on this log's columns",
        log.file()
    );
    let with_theta = log.columns().has(Column::Theta);
    let wopts = WriterOptions {
        flags: args.flags,
        degrees: args.out_deg,
    };
    let quiet = args.quiet;
    let warn = |w: &LogWarning| {
        if !quiet {
            eprintln!("warning: {w}");
        }
    };
    let mut w = EstimatesWriter::new(output, bank.names(), with_theta, wopts)?;
    // The header goes out at once, so that a reader downstream sees the columns before
    // the first sample.
    w.flush()?;
    let summary = pipeline::run(&mut log, &mut bank, Some(&mut w), true, warn, |_, _| {})?;
    if !args.quiet {
        eprintln!("{} rows streamed", summary.rows);
        if log.summary().total_warnings() > 0 {
            eprintln!("{}", log.summary());
        }
    }
    Ok(())
}
