//! Where a command's summary goes: its tables, its verdict and what it wrote.
//!
//! By default a summary is printed on standard output, or on standard error when standard
//! output carries the data (`-o -`) or when the command has always said it there (progress
//! of a run, what was written). With `--summary FILE` every summary line goes to FILE
//! instead, written whole when the command ends, and the terminal keeps only warnings,
//! notes and errors.
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{bail, Context};

use crate::io::output;

/// The summary held for `--summary FILE`; None prints it at once.
static HELD: Mutex<Option<String>> = Mutex::new(None);

/// Holds the summary for a file, or prints it; true when it was held.
fn hold(text: &str) -> bool {
    let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
    match held.as_mut() {
        Some(s) => {
            s.push_str(text);
            s.push('\n');
            true
        }
        None => false,
    }
}

/// A summary (a table, a verdict): on standard output, or on standard error when
/// standard output carries the data (`-o -`), so that a pipe gets only the data; in the
/// `--summary` file when there is one.
pub fn print(data_on_stdout: bool, text: &str) {
    if hold(text) {
        return;
    }
    if data_on_stdout {
        eprintln!("{text}");
    } else {
        println!("{text}");
    }
}

/// A summary line said on standard error (what a run did), or held for the `--summary`
/// file.
pub fn eprint(text: &str) {
    if !hold(text) {
        eprintln!("{text}");
    }
}

/// Starts holding the summary for `path`, after checking that it is none of the
/// command's files: no other argument (`args`, the command line without the summary's own
/// value) may name it, whether it exists or not.
pub fn start(path: &Path, args: &[PathBuf]) -> anyhow::Result<()> {
    if output::is_stdout(path) {
        bail!(
            "--summary takes a file: standard output is the data's with -o -, and the summary \
             goes to standard error then without --summary"
        );
    }
    if let Some(a) = args
        .iter()
        .find(|a| a.as_path() == path || output::same_file(a, path))
    {
        bail!(
            "--summary {} is also the argument {} of the command: the summary would replace \
             that file; give another",
            path.display(),
            a.display()
        );
    }
    *HELD.lock().unwrap_or_else(|e| e.into_inner()) = Some(String::new());
    Ok(())
}

/// Writes the held summary to `path` (atomically: a reader never sees half of it), also
/// when the command failed, so that a batch's table of failures is kept.
pub fn finish(path: &Path) -> anyhow::Result<PathBuf> {
    let text = HELD
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take()
        .unwrap_or_default();
    output::write_atomic("--summary", path, text.as_bytes())
        .with_context(|| format!("cannot write the summary to {}", path.display()))
}

/// [`print`] with `format!` arguments, on standard output (or in the `--summary` file).
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::cli::summary::print(false, &format!($($arg)*))
    };
}
pub(crate) use say;

/// [`eprint`] with `format!` arguments.
macro_rules! say_err {
    ($($arg:tt)*) => {
        $crate::cli::summary::eprint(&format!($($arg)*))
    };
}
pub(crate) use say_err;
