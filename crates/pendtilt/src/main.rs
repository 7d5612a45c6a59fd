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
        // The reader of a pipe stopped early (`pendtilt ... -o - | head`): nothing is
        // wrong with this run, so it ends quietly, as ripgrep and cat do.
        Err(e) if broken_pipe(&e) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::from(1)
        }
    }
}

/// Whether `e` comes from writing into a pipe whose reader has gone.
fn broken_pipe(e: &anyhow::Error) -> bool {
    let pipe = |io: &std::io::Error| io.kind() == std::io::ErrorKind::BrokenPipe;
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>().is_some_and(pipe)
            || c.downcast_ref::<csv::Error>()
                .is_some_and(|e| match e.kind() {
                    csv::ErrorKind::Io(io) => pipe(io),
                    _ => false,
                })
    })
}
