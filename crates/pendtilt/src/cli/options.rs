//! What `estimate` and `stream` share: the rig, how the log is read, which estimators run,
//! how the estimates are written, and the notices about all of that.
use std::io::BufRead;
use std::path::PathBuf;

use crate::bank::planar::{Bank, BankSettings};
use crate::config::RigConfig;
use crate::io::{LogReader, LogWarning, ReaderOptions, WriterOptions};
use crate::pipeline;
pub use crate::pipeline::LogColumns;

/// Options common to the commands that run the estimator bank over a log.
#[derive(Debug, Clone, clap::Args)]
pub struct BankOptions {
    /// The rig file (TOML). Without it the MODEL.md default rig is used, and said so.
    #[arg(long, short = 'p')]
    pub params: Option<PathBuf>,
    /// How the log's columns are named and in which units.
    #[command(flatten)]
    pub columns: LogColumns,
    /// Write the estimates (and theta) in degrees. Default: rad.
    #[arg(long)]
    pub out_deg: bool,
    /// Add a `<name>_flags` column per estimator.
    #[arg(long)]
    pub flags: bool,
    /// Run only these estimators (comma-separated; the names are listed below). Default:
    /// every estimator whose columns are in the log.
    #[arg(long, value_delimiter = ',')]
    pub only: Option<Vec<String>>,
    /// Print nothing but errors on standard error.
    #[arg(long, short = 'q')]
    pub quiet: bool,
}

/// Loads the rig file at `path` and prints its doubtful values ([`RigConfig::doubts`]) as
/// warnings naming the file, unless `quiet`.
pub fn load_rig(path: &std::path::Path, quiet: bool) -> anyhow::Result<RigConfig> {
    let rig = RigConfig::load(path)?;
    if !quiet {
        for d in rig.doubts() {
            eprintln!("warning: {}: {d}", path.display());
        }
    }
    Ok(rig)
}

impl BankOptions {
    /// The rig file, or the default rig with a notice.
    pub fn rig(&self) -> anyhow::Result<RigConfig> {
        Ok(match &self.params {
            Some(p) => load_rig(p, self.quiet)?,
            None => {
                self.notice("note: no --params: using the default rig of MODEL.md section 5");
                RigConfig::default()
            }
        })
    }

    /// How the log is read ([`LogColumns::reader_options`]).
    pub fn reader_options(&self, rig: &RigConfig) -> ReaderOptions {
        self.columns.reader_options(rig)
    }

    /// How the estimates are written (`--flags`, `--out-deg`).
    pub fn writer_options(&self) -> WriterOptions {
        WriterOptions {
            flags: self.flags,
            degrees: self.out_deg,
        }
    }

    /// The bank for `log`'s columns: reports the columns and the skipped estimators, and
    /// errors when nothing can run ([`bank_for`], its notices on standard error).
    pub fn bank<R: BufRead>(&self, rig: &RigConfig, log: &LogReader<R>) -> anyhow::Result<Bank> {
        bank_for(rig, log, self.only.as_deref(), |n| self.notice(&n))
    }

    /// Prints a reader warning unless quiet.
    pub fn warn(&self, w: &LogWarning) {
        self.notice(&format!("warning: {w}"));
    }

    /// Prints `text` on standard error unless quiet.
    pub fn notice(&self, text: &str) {
        if !self.quiet {
            eprintln!("{text}");
        }
    }
}

/// The bank settings a rig file gives: every table of it.
pub fn rig_bank_settings(rig: &RigConfig) -> BankSettings {
    BankSettings::from_rig(rig.clone())
}

/// Logs smaller than this \[bytes\] are read in well under 2 s (10 MB is about 100,000
/// rows, 0.15 s through `estimate`): no progress line for them.
pub const PROGRESS_BYTES: u64 = 10_000_000;

/// A progress line on standard error for work over the file at `input`: `what`, a spinner,
/// `{human_pos}` in the template counts what [`indicatif::ProgressBar::set_position`] says,
/// and the time taken. Hidden when quiet, for a file under [`PROGRESS_BYTES`], or when
/// standard error is not a terminal (a pipe, a file, CI).
pub fn progress(input: &std::path::Path, template: &str, quiet: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    let big = std::fs::metadata(input).is_ok_and(|m| m.len() > PROGRESS_BYTES);
    if quiet || !big || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::stderr());
    b.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    b.enable_steady_tick(std::time::Duration::from_millis(200));
    b
}

/// A progress bar on standard error over `total` steps, drawn with `template`
/// (indicatif's keys: `{bar:40}`, `{pos}`, `{len}`, `{eta}`...). Hidden when quiet or when
/// standard error is not a terminal (a pipe, a file, CI).
pub fn bar(total: u64, template: &str, quiet: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::with_draw_target(
        Some(total),
        indicatif::ProgressDrawTarget::stderr(),
    );
    b.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    b
}

/// The bank for `log`'s columns with `rig`'s settings and `--only`: each notice (the
/// columns found, an estimator pulled in, one skipped and why) handed to `say`; an error
/// when nothing can run. What `estimate`, `stream` and the Python package say alike.
pub fn bank_for<R: BufRead>(
    rig: &RigConfig,
    log: &LogReader<R>,
    only: Option<&[String]>,
    mut say: impl FnMut(String),
) -> anyhow::Result<Bank> {
    say(format!("{}: {}", log.file(), log.columns()));
    let bank = Bank::new(&rig_bank_settings(rig), pipeline::inputs_of(log), only)
        .map_err(anyhow::Error::msg)?;
    for (name, reader) in bank.pulled_in() {
        say(format!(
            "note: {reader} reads {name}: {name} runs too (its column is written)"
        ));
    }
    for s in bank.skipped() {
        say(format!(
            "skipped {}: the log has no {}",
            s.name,
            s.lacking.join(", ")
        ));
    }
    anyhow::ensure!(
        !bank.names().is_empty(),
        "{}: no estimator can run on this log's columns",
        log.file()
    );
    Ok(bank)
}
