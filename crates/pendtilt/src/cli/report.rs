//! `pendtilt report`.

/// Options of `pendtilt report`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt report`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt report is not built yet")
}
