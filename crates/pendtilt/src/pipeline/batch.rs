//! `pendtilt batch`'s steps: the logs a list of paths and patterns names, where each log's
//! estimates go, each log's own rig and scenario files, the run over the logs one per
//! thread, and the summary tables (CSV and Markdown).
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use rayon::prelude::*;

/// One estimator's error against the truth over the scored rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// The estimator.
    pub name: String,
    /// RMS error \[rad\] (inclination error on a 3-D log, MODEL.md 7.9).
    pub rms: f64,
    /// Largest error \[rad\].
    pub max: f64,
    /// Rows scored (a finite estimate and truth).
    pub scored: u64,
}

/// What `estimate` did with one log, for its own report and for `batch`'s summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Rows read and written (one per input row).
    pub rows: u64,
    /// The estimators run, in column order.
    pub estimators: Vec<String>,
    /// Warnings on the input (each also said on standard error unless quiet).
    pub warnings: u64,
    /// What is said after the run: the warnings' summary (planar) or the warnings (3-D).
    pub notes: Vec<String>,
    /// The error table as printed, when the log has the truth.
    pub table: Option<String>,
    /// Each estimator's error, when the log has the truth.
    pub scores: Vec<Score>,
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

/// The rig and scenario files of `log`: `params` when given; else `NAME.rig.toml` and, for
/// a 3-D log (read with `map`), `NAME.scenario.toml` beside it, each when it exists.
pub fn own_files(
    params: Option<&Path>,
    map: &crate::io::ColumnMap,
    log: &Path,
) -> (Option<PathBuf>, Option<PathBuf>) {
    if let Some(p) = params {
        return (Some(p.to_path_buf()), None);
    }
    let beside = |suffix: &str| {
        let stem = log.file_stem()?.to_string_lossy().into_owned();
        Some(log.with_file_name(format!("{stem}.{suffix}.toml"))).filter(|p| p.is_file())
    };
    let three_d = crate::pipeline::spatial::is_3d_log(log, map);
    (beside("rig"), beside("scenario").filter(|_| three_d))
}

/// Every log named or matched, sorted, once each; logs inside the output folder are left
/// out (a second run would take the first one's estimates for logs).
pub fn expand(patterns: &[String], output: &Path) -> anyhow::Result<Vec<PathBuf>> {
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
pub fn common_folder(logs: &[PathBuf]) -> PathBuf {
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
pub fn output_of(log: &Path, common: &Path, out: &Path) -> PathBuf {
    let rel = log.strip_prefix(common).unwrap_or(log);
    let stem = rel
        .file_stem()
        .map_or_else(|| "log".into(), |s| s.to_string_lossy());
    out.join(rel.with_file_name(format!("{stem}.est.csv")))
}

/// Every log through `estimate`, `jobs` at a time, on a pool of its own: each log's
/// estimates go below `out` ([`output_of`], the folder made first), with the rig and
/// scenario `files` names for it; `estimate(log, output, rig, scenario)` runs one log, and
/// `done` is called after each.
pub fn run_all(
    logs: &[PathBuf],
    out: &Path,
    jobs: usize,
    files: impl Fn(&Path) -> (Option<PathBuf>, Option<PathBuf>) + Sync,
    estimate: impl Fn(&Path, &Path, Option<PathBuf>, Option<PathBuf>) -> anyhow::Result<Outcome> + Sync,
    done: impl Fn() + Sync,
) -> anyhow::Result<Vec<Entry>> {
    let common = common_folder(logs);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .context("cannot start the worker threads")?;
    let one = |log: &Path, output: &Path, rig: Option<PathBuf>, scenario| {
        if let Some(dir) = output.parent() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot make the folder {}", dir.display()))?;
        }
        estimate(log, output, rig, scenario)
    };
    let entries = pool.install(|| {
        logs.par_iter()
            .map(|log| {
                let output = output_of(log, &common, out);
                let (rig, scenario) = files(log);
                let result = one(log, &output, rig.clone(), scenario).map_err(|e| format!("{e:#}"));
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
pub fn scored_names(entries: &[Entry]) -> Vec<String> {
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
pub fn summary_row(e: &Entry, names: &[String]) -> (Vec<String>, String, Option<String>) {
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
