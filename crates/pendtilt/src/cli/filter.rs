//! `pendtilt filter`.

/// Options of `pendtilt filter`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt filter`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt filter is not built yet")
}
