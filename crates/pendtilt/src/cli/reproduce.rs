//! `pendtilt reproduce`.

/// Options of `pendtilt reproduce`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `pendtilt reproduce`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("pendtilt reproduce is not built yet")
}
