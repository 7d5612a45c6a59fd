//! `pendtilt estimate`.

/// Options of `pendtilt estimate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt estimate`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt estimate is not built yet")
}
