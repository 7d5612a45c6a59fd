//! `pendtilt stream`.

/// Options of `pendtilt stream`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt stream`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt stream is not built yet")
}
