//! Command-line front end: one module per subcommand, each with its `Args` and `run`.
use clap::{Parser, Subcommand};

pub mod batch;
pub mod estimate;
pub mod estimate3d;
pub mod filter;
pub mod fit;
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

/// Runs one parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
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
