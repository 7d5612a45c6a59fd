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

use anyhow::{bail, Context};
use rayon::prelude::*;

use super::estimate::{self, Outcome};
use super::options::BankOptions;

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

/// One log's line of the summary.
#[derive(Debug, Clone)]
pub struct Entry {
    /// The log, as found.
    pub log: PathBuf,
    /// Where its estimates went.
    pub output: PathBuf,
    /// The rig file it was estimated with (None: the MODEL.md rig).
    pub rig: Option<PathBuf>,
    /// What `estimate` found, or why it failed.
    pub result: Result<Outcome, String>,
}

/// The rig and scenario files of `log` when `--params` is not given: `NAME.rig.toml` and,
/// for a 3-D log, `NAME.scenario.toml` beside it, each when it exists.
pub fn own_files(args: &Args, log: &Path) -> (Option<PathBuf>, Option<PathBuf>) {
    if let Some(p) = &args.bank.params {
        return (Some(p.clone()), None);
    }
    let beside = |suffix: &str| {
        let stem = log.file_stem()?.to_string_lossy().into_owned();
        Some(log.with_file_name(format!("{stem}.{suffix}.toml"))).filter(|p| p.is_file())
    };
    let three_d = crate::pipeline::spatial::is_3d_log(log, &args.bank.columns.map);
    (beside("rig"), beside("scenario").filter(|_| three_d))
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

/// Every log named or matched, sorted, once each; logs inside the output folder are left
/// out (a second run would take the first one's estimates for logs).
fn expand(patterns: &[String], output: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut logs = Vec::new();
    for p in patterns {
        if !p.contains(['*', '?', '[']) {
            let path = PathBuf::from(p);
            if !path.is_file() {
                bail!("{p}: no such file");
            }
            logs.push(path);
            continue;
        }
        let before = logs.len();
        for m in glob::glob(p).with_context(|| format!("{p}: not a valid pattern"))? {
            let path = m.with_context(|| format!("{p}: a match could not be read"))?;
            if path.is_file() {
                logs.push(path);
            }
        }
        if logs.len() == before {
            bail!("{p}: no file matches the pattern");
        }
    }
    let out = std::fs::canonicalize(output).ok();
    logs.retain(|l| {
        let inside = out
            .as_ref()
            .is_some_and(|o| std::fs::canonicalize(l).is_ok_and(|l| l.starts_with(o)));
        !inside
    });
    logs.sort();
    logs.dedup();
    if logs.is_empty() {
        bail!("no log to estimate (the files matched are all inside -o)");
    }
    Ok(logs)
}

/// The folder every log is under (for the outputs' paths below `-o`).
fn common_folder(logs: &[PathBuf]) -> PathBuf {
    let mut common: Option<PathBuf> = None;
    for l in logs {
        let dir = l.parent().map(Path::to_path_buf).unwrap_or_default();
        common = Some(match common {
            None => dir,
            Some(c) => c
                .components()
                .zip(dir.components())
                .take_while(|(a, b)| a == b)
                .map(|(a, _)| a)
                .collect(),
        });
    }
    common.unwrap_or_default()
}

/// Where a log's estimates go: its path below `common`, `.est.csv` for its extension.
fn output_of(log: &Path, common: &Path, out: &Path) -> PathBuf {
    let rel = log.strip_prefix(common).unwrap_or(log);
    let stem = rel
        .file_stem()
        .map_or_else(|| "log".into(), |s| s.to_string_lossy());
    out.join(rel.with_file_name(format!("{stem}.est.csv")))
}

/// `estimate` on every log, `jobs` at a time; `done` after each.
pub fn run_all(
    args: &Args,
    logs: &[PathBuf],
    jobs: usize,
    done: impl Fn() + Sync,
) -> anyhow::Result<Vec<Entry>> {
    let common = common_folder(logs);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .context("cannot start the worker threads")?;
    let entries = pool.install(|| {
        logs.par_iter()
            .map(|log| {
                let output = output_of(log, &common, &args.output);
                let (rig, scenario) = own_files(args, log);
                let result =
                    one(args, log, &output, rig.clone(), scenario).map_err(|e| format!("{e:#}"));
                done();
                Entry {
                    log: log.clone(),
                    output,
                    rig,
                    result,
                }
            })
            .collect()
    });
    Ok(entries)
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
    if let Some(dir) = output.parent() {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot make the folder {}", dir.display()))?;
    }
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

/// The summary as CSV (one row per log, an RMS column per estimator in degrees) and as a
/// Markdown table.
pub fn write_summary(entries: &[Entry], csv_path: &Path, md_path: &Path) -> anyhow::Result<()> {
    let names = scored_names(entries);
    let mut csv = csv::Writer::from_path(csv_path)
        .with_context(|| format!("cannot write {}", csv_path.display()))?;
    let mut header = vec![
        "log".to_string(),
        "estimates".into(),
        "rig".into(),
        "status".into(),
        "rows".into(),
        "warnings".into(),
        "error".into(),
    ];
    header.extend(names.iter().map(|n| format!("{n}_rms_deg")));
    csv.write_record(&header)?;
    let mut md = String::from("| log | rig | status | rows | warnings |");
    for n in &names {
        md.push_str(&format!(" {n} RMS [deg] |"));
    }
    md.push_str("\n|---|---|---|---:|---:|");
    md.push_str(&"---:|".repeat(names.len()));
    md.push('\n');
    let mut failures = String::new();
    for e in entries {
        let (row, md_row, failure) = summary_row(e, &names);
        csv.write_record(&row)?;
        md.push_str(&md_row);
        failures.push_str(&failure.unwrap_or_default());
        md.push('\n');
    }
    csv.flush()?;
    if !failures.is_empty() {
        md.push_str(&format!("\nFailed (skipped):\n\n{failures}"));
    }
    std::fs::write(md_path, md).with_context(|| format!("cannot write {}", md_path.display()))?;
    Ok(())
}

/// Every estimator that scored on some log, in order of first appearance.
fn scored_names(entries: &[Entry]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for o in entries.iter().filter_map(|e| e.result.as_ref().ok()) {
        for s in &o.scores {
            if !names.contains(&s.name) {
                names.push(s.name.clone());
            }
        }
    }
    names
}

/// Log `e`'s row of the summary: the CSV record, the Markdown row, and the line of the
/// list of failures when it failed.
fn summary_row(e: &Entry, names: &[String]) -> (Vec<String>, String, Option<String>) {
    let rms = |o: &Outcome, n: &str| {
        o.scores
            .iter()
            .find(|s| s.name == n)
            .map(|s| s.rms.to_degrees())
    };
    let log = e.log.display().to_string();
    let out = e.output.display().to_string();
    let rig = e
        .rig
        .as_ref()
        .map_or("default".into(), |r| r.display().to_string());
    match &e.result {
        Ok(o) => {
            let cells: Vec<String> = names
                .iter()
                .map(|n| rms(o, n).map_or(String::new(), |x| format!("{x}")))
                .collect();
            let mut row = vec![
                log.clone(),
                out,
                rig.clone(),
                "ok".into(),
                o.rows.to_string(),
                o.warnings.to_string(),
                String::new(),
            ];
            row.extend(cells);
            let mut md = format!("| {log} | {rig} | ok | {} | {} |", o.rows, o.warnings);
            for n in names {
                let cell = rms(o, n).map_or("".into(), |x| format!("{x:.4}"));
                md.push_str(&format!(" {cell} |"));
            }
            (row, md, None)
        }
        Err(msg) => {
            let mut row = vec![
                log.clone(),
                String::new(),
                rig.clone(),
                "failed".into(),
                String::new(),
                String::new(),
                msg.clone(),
            ];
            row.extend(names.iter().map(|_| String::new()));
            let mut md = format!("| {log} | {rig} | failed | | |");
            md.push_str(&" |".repeat(names.len()));
            let failure = format!("- `{log}`: {}\n", msg.replace('\n', " "));
            (row, md, Some(failure))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_keep_the_logs_paths_below_their_common_folder() {
        let logs = [
            PathBuf::from("logs/a/ride.csv"),
            PathBuf::from("logs/b/ride.csv"),
            PathBuf::from("logs/c.csv"),
        ];
        let common = common_folder(&logs);
        assert_eq!(common, PathBuf::from("logs"));
        let out = Path::new("out");
        assert_eq!(
            output_of(&logs[0], &common, out),
            PathBuf::from("out/a/ride.est.csv")
        );
        assert_eq!(
            output_of(&logs[1], &common, out),
            PathBuf::from("out/b/ride.est.csv")
        );
        assert_eq!(
            output_of(&logs[2], &common, out),
            PathBuf::from("out/c.est.csv")
        );
    }
}
