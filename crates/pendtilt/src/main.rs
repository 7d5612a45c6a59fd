//! The `pendtilt` command: estimate, filter, simulate, fit, report, reproduce, stream.
use clap::Parser;

fn main() -> std::process::ExitCode {
    // First, before any thread: an interrupted run leaves no partial output behind.
    if let Err(e) = pendtilt::io::output::remove_partial_on_interrupt() {
        eprintln!("warning: an interrupted run may leave a .partial file behind: {e}");
    }
    let cli = pendtilt::cli::Cli::parse();
    match pendtilt::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::from(1)
        }
    }
}
