//! `pendtilt rig --template planar|3d`: a rig file with every key at its default and what
//! it means, to edit rather than write from nothing.
use std::io::Write;
use std::path::PathBuf;

use crate::io::output::OutputFile;

/// Which rig file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Kind {
    /// One pendulum axis (MODEL.md 5).
    Planar,
    /// The two-axis Cardan pendulum (MODEL.md 7.6).
    #[value(name = "3d")]
    Spatial,
}

/// Options of `pendtilt rig`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print a commented rig file with every default: planar or 3d.
    #[arg(long, value_name = "KIND")]
    pub template: Kind,
    /// Where to write it. Default: standard output.
    #[arg(long, short = 'o', visible_alias = "out", default_value = "-")]
    pub output: PathBuf,
}

/// The template's text.
pub fn template(kind: Kind) -> String {
    match kind {
        Kind::Planar => crate::config::RigConfig::default().to_toml_string(),
        Kind::Spatial => crate::bank::spatial::rig::template(),
    }
}

/// Runs `pendtilt rig`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let out = OutputFile::create("-o", &args.output)?;
    out.writer()?
        .write_all(template(args.template).as_bytes())?;
    out.commit()?;
    Ok(())
}
