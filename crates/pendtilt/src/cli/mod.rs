//! Command-line front end: one module per subcommand, each with its `Args` and `run`.
use clap::{Parser, Subcommand};

pub mod batch;
pub mod estimate;
pub mod estimate3d;
pub mod filter;
pub mod fit;
pub mod fit3d;
pub mod help;
pub mod options;
pub mod replay;
pub mod report;
pub mod report3d;
pub mod reproduce;
pub mod rig;
pub mod shell;
pub mod simulate;
pub mod simulate3d;
pub mod stream;
pub mod summary;
pub mod tune;
pub mod tune3d;

/// The version and the commit it was built from (`build.rs`; "unknown" outside a git
/// checkout), for `--version` and bug reports.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("PENDTILT_COMMIT"),
    ")"
);

/// Tilt estimation with a pendulum as the sensor.
#[derive(Debug, Parser)]
#[command(name = "pendtilt", version = VERSION, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// Write the command's summary (its tables, its verdict, what it wrote) to this file
    /// instead of the terminal; warnings, notes and errors stay on standard error. Default:
    /// none (standard output, or standard error when `-o -` puts the data there).
    #[arg(long, global = true, value_name = "FILE")]
    pub summary: Option<std::path::PathBuf>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run every estimator whose inputs are present over a sensor log (CSV).
    Estimate(estimate::Args),
    /// `estimate` on many logs across the cores, with a summary table of each log's
    /// warnings and errors.
    Batch(batch::Args),
    /// Apply the paper's FIR low-pass to columns of any CSV.
    Filter(filter::Args),
    /// Simulate the pendulum rig on a moving, vibrating body and write a sensor log.
    Simulate(simulate::Args),
    /// Fit the pendulum's parameters to a log (output error by default, the paper's Eq 23/29
    /// with --cost inverse; Newton, Eqs 24-28, or Levenberg-Marquardt).
    Fit(fit::Args),
    /// Metrics, figures and an HTML page for a log with a true angle.
    Report(report::Args),
    /// Replay a recorded IMU through a virtual pendulum: the 3-D log a pendulum on that
    /// body would have given (MODEL.md 7.10).
    Replay(replay::Args),
    /// Redo the paper's experiment and figures on built-in simulated data.
    Reproduce(reproduce::Args),
    /// Estimate from log lines on standard input as they arrive.
    Stream(stream::Args),
    /// Tune every estimator's settings from a log (no true angle needed) and write a rig
    /// file that `estimate` reads.
    Tune(tune::Args),
    /// Print a commented rig file with every default (`--template planar` or `3d`).
    Rig(rig::Args),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(shell::CompletionsArgs),
    /// Write the man pages.
    Man(shell::ManArgs),
}

/// Runs one parsed command line; with `--summary FILE` the summary is held and written
/// to FILE when the command ends, whether it succeeded or not.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    let Some(path) = cli.summary else {
        return dispatch(cli.command);
    };
    summary::start(&path, &other_arguments())?;
    let result = dispatch(cli.command);
    let written = summary::finish(&path);
    result.and(written.map(|_| ()))
}

/// The process's arguments but `--summary` and its value.
fn other_arguments() -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    let mut args = std::env::args_os().skip(1);
    while let Some(a) = args.next() {
        if a == "--summary" {
            args.next();
        } else if !a.to_string_lossy().starts_with("--summary=") {
            out.push(a.into());
        }
    }
    out
}

fn dispatch(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Estimate(a) => estimate::run(a),
        Command::Batch(a) => batch::run(a),
        Command::Rig(a) => rig::run(a),
        Command::Filter(a) => filter::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Fit(a) => fit::run(a),
        Command::Report(a) => report::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Reproduce(a) => reproduce::run(a),
        Command::Stream(a) => stream::run(a),
        Command::Tune(a) => tune::run(a),
        Command::Completions(a) => shell::completions(a),
        Command::Man(a) => shell::man(a),
    }
}
