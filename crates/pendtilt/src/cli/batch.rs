//! `pendtilt batch 'logs/**/*.csv' --params RIG -o OUTDIR`: `estimate` on many logs, one
//! log per core.
//!
//! Each log's estimates are what `pendtilt estimate` writes for it, byte for byte, in
//! `OUTDIR/<its path under the logs' common folder, .est.csv>`. A log that cannot be read is
//! reported and skipped; the others finish. `OUTDIR/summary.csv` and `OUTDIR/summary.md`
//! list every log: its rows, warnings, error (if it failed) and, where it has the truth,
//! each estimator's RMS error. The exit status is 1 when any log failed.
//!
//! Without `--params` each log is estimated with its own rig: the `NAME.rig.toml` beside
//! `NAME.csv` (as `simulate` writes it, and for a 3-D log its `NAME.scenario.toml` too), or
//! the MODEL.md rig when there is none; the summary names the rig of each log.
//!
//! Each log runs on one thread (the sequential pass, [`crate::pipeline::run`]), so the
//! logs spread over the cores (rayon) rather than each log's reading, estimating and
//! writing (as `estimate` does for one log).
use std::path::{Path, PathBuf};

use super::estimate::{self, Outcome};
use super::options::BankOptions;
use crate::pipeline::batch::{self, expand, write_summary, Entry};
use anyhow::{bail, Context};

/// Options of `pendtilt batch`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The logs: paths or patterns (`'logs/**/*.csv'`; quote a pattern so that pendtilt,
    /// not the shell, expands it, as `**` needs). Planar and 3-D logs may be mixed.
    #[arg(required = true, value_name = "LOG_OR_PATTERN")]
    pub logs: Vec<String>,
    /// The folder for the estimates (one `.est.csv` per log, under its path below the
    /// logs' common folder) and the summary tables; made when missing.
    #[arg(long, short = 'o', visible_alias = "out")]
    pub output: PathBuf,
    /// Rig, column mapping, estimator choice and output form, as for `estimate`. Without
    /// --params, each log's own NAME.rig.toml beside it (and a 3-D log's
    /// NAME.scenario.toml), else the default rig.
    #[command(flatten)]
    pub bank: BankOptions,
    /// Score the error against the truth from this long after each log's first row (s).
    /// Default: as `estimate`, 5 s (the whole log when it lasts less than 10 s).
    #[arg(long, value_name = "SECONDS")]
    pub score_from: Option<f64>,
    /// Logs estimated at once. Default: one per core.
    #[arg(long, short = 'j', value_name = "N")]
    pub jobs: Option<usize>,
}

/// The rig and scenario files of `log` when `--params` is not given (see
/// [`batch::own_files`]).
pub fn own_files(args: &Args, log: &Path) -> (Option<PathBuf>, Option<PathBuf>) {
    batch::own_files(args.bank.params.as_deref(), &args.bank.columns.map, log)
}

/// Runs `pendtilt batch`.
pub fn run(args: Args) -> anyhow::Result<()> {
    if crate::io::output::is_stdout(&args.output) {
        bail!("-o -: batch writes a folder (an estimates file per log and the summary); name one");
    }
    let logs = expand(&args.logs, &args.output)?;
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot make the folder -o {}", args.output.display()))?;
    let jobs = match args.jobs {
        Some(0) => bail!("--jobs 0: at least one log at a time"),
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let bar = super::options::bar(
        logs.len() as u64,
        "estimating {bar:40} {pos}/{len} logs, {elapsed}, eta {eta}",
        args.bank.quiet,
    );
    let entries = run_all(&args, &logs, jobs, || bar.inc(1))?;
    bar.finish_and_clear();
    let summary_csv = args.output.join("summary.csv");
    let summary_md = args.output.join("summary.md");
    write_summary(&entries, &summary_csv, &summary_md)?;
    let failed: Vec<&Entry> = entries.iter().filter(|e| e.result.is_err()).collect();
    if !args.bank.quiet {
        let rows: u64 = entries
            .iter()
            .filter_map(|e| e.result.as_ref().ok())
            .map(|o| o.rows)
            .sum();
        super::summary::eprint(&format!(
            "{} logs, {rows} rows -> {} ({} failed); summary: {}, {}",
            entries.len(),
            args.output.display(),
            failed.len(),
            summary_csv.display(),
            summary_md.display()
        ));
    }
    for e in &failed {
        if let Err(msg) = &e.result {
            eprintln!("error: {}: {msg}", e.log.display());
        }
    }
    if !failed.is_empty() {
        bail!(
            "{} of {} logs failed (skipped; the others were estimated)",
            failed.len(),
            entries.len()
        );
    }
    Ok(())
}

/// `estimate` on every log, `jobs` at a time; `done` after each.
pub fn run_all(
    args: &Args,
    logs: &[PathBuf],
    jobs: usize,
    done: impl Fn() + Sync,
) -> anyhow::Result<Vec<Entry>> {
    let files = |log: &Path| own_files(args, log);
    let one = |log: &Path, output: &Path, rig, scenario| one(args, log, output, rig, scenario);
    batch::run_all(logs, &args.output, jobs, files, one, done)
}

/// One log through `estimate` with `rig` and `scenario`, quietly (its warnings are counted
/// in the summary).
fn one(
    args: &Args,
    log: &Path,
    output: &Path,
    rig: Option<PathBuf>,
    scenario: Option<PathBuf>,
) -> anyhow::Result<Outcome> {
    let mut bank = args.bank.clone();
    bank.quiet = true;
    bank.params = rig;
    let a = estimate::Args {
        log: log.to_path_buf(),
        output: output.to_path_buf(),
        bank,
        quaternion: false,
        scenario,
        score_from: args.score_from,
    };
    estimate::estimate_with(&a, false)
}
