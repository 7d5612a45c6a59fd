//! `pendtilt fit`.

/// Options of `pendtilt fit`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt fit`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt fit is not built yet")
}
