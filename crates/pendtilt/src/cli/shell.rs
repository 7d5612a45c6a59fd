//! `pendtilt completions SHELL` and `pendtilt man`: what a shell and `man` need to know
//! of the command line, generated from the same definition that parses it (clap_complete,
//! clap_mangen), so they never fall behind it.
use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use clap::CommandFactory;
use clap_complete::Shell;

use super::Cli;

/// Print a shell completion script.
#[derive(Debug, clap::Args)]
#[command(after_help = "Install, for example:\n  \
    bash: pendtilt completions bash > ~/.local/share/bash-completion/completions/pendtilt\n  \
    zsh:  pendtilt completions zsh > ~/.zfunc/_pendtilt  (with ~/.zfunc on $fpath)\n  \
    fish: pendtilt completions fish > ~/.config/fish/completions/pendtilt.fish")]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// Write the man pages: pendtilt(1) and one per subcommand (pendtilt-estimate(1), ...).
#[derive(Debug, clap::Args)]
#[command(after_help = "View one without installing: pendtilt man -o man && man -l man/pendtilt.1")]
pub struct ManArgs {
    /// Directory to write the pages into (created if missing). Default: pendtilt(1) alone
    /// on standard output.
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
}

/// Writes the completion script for `args.shell` to standard output.
pub fn completions(args: CompletionsArgs) -> anyhow::Result<()> {
    let mut cmd = Cli::command();
    let mut out = std::io::stdout().lock();
    clap_complete::generate(args.shell, &mut cmd, "pendtilt", &mut out);
    out.flush().context("writing the completion script")?;
    Ok(())
}

/// Writes pendtilt(1) to standard output, or every page into `args.output`.
pub fn man(args: ManArgs) -> anyhow::Result<()> {
    let cmd = Cli::command();
    match args.output {
        None => {
            let mut out = std::io::stdout().lock();
            clap_mangen::Man::new(cmd)
                .render(&mut out)
                .context("writing the man page")?;
            out.flush().context("writing the man page")?;
        }
        Some(dir) if crate::io::output::is_stdout(&dir) => anyhow::bail!(
            "-o -: -o names a directory for every page; leave -o out for pendtilt(1) alone on \
             standard output"
        ),
        Some(dir) => {
            std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
            clap_mangen::generate_to(cmd, &dir)
                .with_context(|| format!("writing the man pages into {}", dir.display()))?;
            super::summary::say_err!("man pages written to {}", dir.display());
        }
    }
    Ok(())
}
