//! `pendtilt estimate LOG.csv --params RIG.toml -o OUT.csv`.
use std::path::PathBuf;

use anyhow::Context;

use super::options::BankOptions;
use crate::io::{Column, EstimatesWriter, LogReader};
use crate::pipeline;

/// Options of `pendtilt estimate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sensor log (CSV, MODEL.md section 5).
    pub log: PathBuf,
    /// Where to write the estimates (CSV); `-` for standard output.
    #[arg(long, short = 'o')]
    pub output: PathBuf,
    /// Rig, column mapping, estimator choice and output form.
    #[command(flatten)]
    pub bank: BankOptions,
}

/// Runs `pendtilt estimate`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let opts = &args.bank;
    let rig = opts.rig()?;
    let mut log = LogReader::open(&args.log, opts.reader_options())?;
    let mut bank = opts.bank(&rig, &log)?;
    let with_theta = log.columns().has(Column::Theta);
    let wopts = opts.writer_options();
    let warn = |w: &crate::io::LogWarning| opts.warn(w);
    let summary = if args.output.as_os_str() == "-" {
        let mut w = EstimatesWriter::new(std::io::stdout(), bank.names(), with_theta, wopts)?;
        pipeline::run_parallel(&mut log, &mut bank, Some(&mut w), warn, |_, _| {})?
    } else {
        let mut w = EstimatesWriter::create(&args.output, bank.names(), with_theta, wopts)
            .with_context(|| format!("cannot create {}", args.output.display()))?;
        pipeline::run_parallel(&mut log, &mut bank, Some(&mut w), warn, |_, _| {})?
    };
    if !opts.quiet {
        eprintln!(
            "{} rows -> {} ({} estimators)",
            summary.rows,
            args.output.display(),
            bank.names().len()
        );
        if log.summary().total_warnings() > 0 {
            eprintln!("{}", log.summary());
        }
        if let Some(errors) = &summary.errors {
            println!("{}", pipeline::error_table(errors));
        }
    }
    Ok(())
}
