//! `pendtilt simulate`.

/// Options of `pendtilt simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt simulate`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt simulate is not built yet")
}
