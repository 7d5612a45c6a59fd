//! The `pendtilt` command: estimate, filter, simulate, fit, report, reproduce, stream.
use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = pendtilt::cli::Cli::parse();
    match pendtilt::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::from(1)
        }
    }
}
