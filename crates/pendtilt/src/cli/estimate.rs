//! `pendtilt estimate LOG.csv --params RIG.toml -o OUT.csv`.
use std::path::PathBuf;

use anyhow::Context;

use crate::bank::{Bank, BankSettings};
use crate::config::RigConfig;
use crate::io::{
    ColumnMap, DegreeColumns, EstimatesWriter, LogReader, ReaderOptions, WriterOptions,
};
use crate::pipeline;

/// Options of `pendtilt estimate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sensor log (CSV, MODEL.md section 5).
    pub log: PathBuf,
    /// The rig file (TOML). Without it the MODEL.md default rig is used, and said so.
    #[arg(long, short = 'p')]
    pub params: Option<PathBuf>,
    /// Where to write the estimates (CSV); `-` for standard output.
    #[arg(long, short = 'o')]
    pub output: PathBuf,
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
    /// Print nothing but errors.
    #[arg(long, short = 'q')]
    pub quiet: bool,
}

/// Runs `pendtilt estimate`.
pub fn run(args: Args) -> anyhow::Result<()> {
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
    let mut log = LogReader::open(&args.log, options)?;
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
    let with_theta = log.columns().has(crate::io::Column::Theta);
    let wopts = WriterOptions {
        flags: args.flags,
        degrees: args.out_deg,
    };
    let quiet = args.quiet;
    let warn = |w: &crate::io::LogWarning| {
        if !quiet {
            eprintln!("warning: {w}");
        }
    };
    let summary = if args.output.as_os_str() == "-" {
        let mut w =
            EstimatesWriter::new(std::io::stdout().lock(), bank.names(), with_theta, wopts)?;
        pipeline::run(&mut log, &mut bank, Some(&mut w), false, warn, |_, _| {})?
    } else {
        let mut w = EstimatesWriter::create(&args.output, bank.names(), with_theta, wopts)
            .with_context(|| format!("cannot create {}", args.output.display()))?;
        pipeline::run(&mut log, &mut bank, Some(&mut w), false, warn, |_, _| {})?
    };
    if !args.quiet {
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

/// The bank settings a rig file gives: every table of it.
pub fn rig_bank_settings(rig: &RigConfig) -> BankSettings {
    BankSettings {
        params: rig.params(),
        accel: rig.accel_settings(),
        alg1: rig.alg1_settings(),
        alg2: rig.alg2_settings(),
        alg3: rig.alg3_settings(),
        kalman: rig.kalman_settings(),
        gravity: rig
            .physical()
            .map_or(pendtilt_core::params::STANDARD_GRAVITY, |p| p.gravity),
        peers: crate::peers::PeerSettings::default(),
    }
}
