//! Safe output files: no command overwrites one of its inputs, and no failed run leaves a
//! partial file where an earlier good one was.
//!
//! - [`check_distinct`] compares every output path with every input path (and the outputs
//!   with each other) by file identity, device and inode, so a symlink or a hard link to
//!   an input is caught as well as the same name. An output that does not exist yet is
//!   compared by its absolute path.
//! - [`OutputFile`] writes into a temporary file beside the target (same directory, so the
//!   final rename is atomic) and renames it into place only in [`OutputFile::commit`].
//!   Dropped without a commit (an error half way), the temporary file is removed and the
//!   target, if it existed, is untouched. `-` is standard output; an existing target that
//!   is not a regular file (`/dev/null`, a named pipe) is written directly, since renaming
//!   over it would replace the device or pipe.
//! - [`OutputDir`] does the same for a directory of files (`report`, `reproduce`): the
//!   files are written into a staging directory beside the target and moved in one by one
//!   only when the whole run succeeded.
//! - [`not_written`] is the sentence a failed run adds to its error.
//! - [`remove_partial_on_interrupt`] removes the temporary files and staging directories
//!   when the run is interrupted (Ctrl-C, SIGTERM, SIGHUP), which ends it without a drop.
use std::io;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

mod dir;
mod file;
mod interrupt;

pub use dir::OutputDir;
pub use file::{write_atomic, OutputFile};
pub use interrupt::remove_partial_on_interrupt;

/// A file a command reads or writes, with the option that named it (for the messages).
#[derive(Debug, Clone, Copy)]
pub struct NamedPath<'a> {
    /// How the user named it: `LOG`, `--params`, `-o`, ...
    pub option: &'a str,
    /// The path as given.
    pub path: &'a Path,
}

impl<'a> NamedPath<'a> {
    /// `path`, named by `option`.
    pub fn new(option: &'a str, path: &'a Path) -> Self {
        Self { option, path }
    }
}

/// Why an output was refused or could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An output is one of the inputs (or two outputs are one file).
    #[error(
        "{output} is the same file as {other}{how}: writing it would destroy the {what}; \
         choose another output path"
    )]
    SameFile {
        /// The output, as `OPTION PATH`.
        output: String,
        /// The input (or other output) it is, as `OPTION PATH`.
        other: String,
        /// " (a link to it)" when the paths differ.
        how: &'static str,
        /// "input" or "other output".
        what: &'static str,
    },
    /// The output path cannot be used (a directory, no parent directory, ...).
    #[error("{option} {path}: {message}")]
    Unusable {
        /// The output's option.
        option: String,
        /// The output path.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// Reading, writing or renaming failed.
    #[error("{path}: {error}")]
    Io {
        /// The file concerned.
        path: String,
        /// The I/O error (not a `source`: the message holds it, and a chain printed it
        /// twice).
        error: io::Error,
    },
}

fn io_error(path: &Path, error: io::Error) -> OutputError {
    OutputError::Io {
        path: path.display().to_string(),
        error,
    }
}

/// Bytes free to an unprivileged writer on the file system holding `dir`, if known.
#[cfg(unix)]
pub fn free_bytes(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(absolute(dir).as_os_str().as_bytes()).ok()?;
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: `c` is a valid NUL-terminated path and `st` a writable statvfs.
    if unsafe { libc::statvfs(c.as_ptr(), &mut st) } != 0 {
        return None;
    }
    Some((st.f_bavail as u64).saturating_mul(st.f_frsize as u64))
}

/// Bytes free on the file system holding `dir` (not known off unix).
#[cfg(not(unix))]
pub fn free_bytes(_dir: &Path) -> Option<u64> {
    None
}

/// Whether `path` means standard output.
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Whether `path` has no "beside" for the files a command writes next to its output:
/// standard output, or an existing device or pipe, or anything under /dev, whose
/// directory is no place for a user's file (`simulate -o /dev/null` wrote
/// `/dev/null.rig.toml`).
pub fn has_no_beside(path: &Path) -> bool {
    // Under /dev too: `-o /dev/stdout > log.csv` reaches a regular file (helper io13).
    is_stdout(path)
        || std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
        || absolute(path).starts_with("/dev")
}

/// Device and inode of an existing file (following symlinks).
fn identity(path: &Path) -> Option<(u64, u64)> {
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// An absolute form of a path that may not exist yet: its parent resolved, its name kept.
pub fn absolute(path: &Path) -> PathBuf {
    let name = path.file_name();
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match (parent.canonicalize(), name) {
        (Ok(p), Some(n)) => p.join(n),
        _ => std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
    }
}

/// Whether `a` and `b` are one file: same device and inode when both exist, else the same
/// absolute path.
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    match (identity(a), identity(b)) {
        (Some(x), Some(y)) => x == y,
        (None, None) => absolute(a) == absolute(b),
        _ => false,
    }
}

/// Refuses when an output is an input, or two outputs are one file, by file identity
/// (device and inode: symlinks and hard links are caught). `-` (standard input or output)
/// is never compared.
///
/// # Errors
/// [`OutputError::SameFile`] naming both options and paths.
pub fn check_distinct(inputs: &[NamedPath], outputs: &[NamedPath]) -> Result<(), OutputError> {
    let same = |o: &NamedPath, other: &NamedPath, what| {
        if is_stdout(o.path) || is_stdout(other.path) || !same_file(o.path, other.path) {
            return Ok(());
        }
        Err(OutputError::SameFile {
            output: format!("{} {}", o.option, o.path.display()),
            other: format!("{} {}", other.option, other.path.display()),
            how: if o.path == other.path {
                ""
            } else {
                " (a link to it)"
            },
            what,
        })
    };
    for (i, o) in outputs.iter().enumerate() {
        for input in inputs {
            same(o, input, "input")?;
        }
        for other in &outputs[..i] {
            same(o, other, "other output")?;
        }
    }
    Ok(())
}

/// The sentence a failed run adds to its error for each output: the file was not written
/// and, when it exists, that the earlier file is unchanged.
pub fn not_written(path: &Path) -> String {
    if is_stdout(path) {
        "the output on standard output (-o -) is incomplete or empty".to_string()
    } else if path.is_dir() {
        format!(
            "nothing was written into {}; the files already there are unchanged",
            path.display()
        )
    } else if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        // A device or pipe has no earlier file: what reached it may be partial.
        format!(
            "{} was written to directly (a device or pipe): what reached it is incomplete",
            path.display()
        )
    } else if path.exists() {
        format!(
            "{} was not written; the earlier file is unchanged",
            path.display()
        )
    } else {
        format!("{} was not written", path.display())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs::Permissions;
    use std::os::unix::fs::PermissionsExt;

    #[test]
    fn hard_link_symlink_and_same_name_are_one_file() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("log.csv");
        std::fs::write(&log, "t\n0\n").unwrap();
        let hard = dir.path().join("hard.csv");
        std::fs::hard_link(&log, &hard).unwrap();
        let soft = dir.path().join("soft.csv");
        std::os::unix::fs::symlink(&log, &soft).unwrap();
        let via_dots = dir.path().join(".").join("log.csv");
        let fresh = dir.path().join("new.csv");
        let inputs = [NamedPath::new("LOG", &log)];
        for o in [&log, &hard, &soft, &via_dots] {
            let e = check_distinct(&inputs, &[NamedPath::new("-o", o)]).unwrap_err();
            let text = e.to_string();
            assert!(text.contains("-o ") && text.contains("LOG "), "{text}");
        }
        check_distinct(&inputs, &[NamedPath::new("-o", &fresh)]).unwrap();
        check_distinct(&inputs, &[NamedPath::new("-o", Path::new("-"))]).unwrap();
        // Two outputs that do not exist yet but are one path.
        let twice = [
            NamedPath::new("-o", &fresh),
            NamedPath::new("--rig-out", &fresh),
        ];
        assert!(check_distinct(&[], &twice).is_err());
    }

    #[test]
    fn a_read_only_output_is_refused_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("kept.csv");
        std::fs::write(&p, "earlier").unwrap();
        std::fs::set_permissions(&p, Permissions::from_mode(0o444)).unwrap();
        let e = OutputFile::create("-o", &p).err().unwrap().to_string();
        assert!(
            e.contains("kept.csv: is read-only, so it is not replaced"),
            "{e}"
        );
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "earlier");
        assert_eq!(
            std::fs::metadata(&p).unwrap().permissions().mode() & 0o777,
            0o444
        );
        let e = write_atomic("-o", &p, b"new").unwrap_err().to_string();
        assert!(e.contains("read-only"), "{e}");
    }

    #[test]
    fn a_directory_output_refuses_standard_output() {
        let e = OutputDir::create("-o", Path::new("-"))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("-o -: this command writes a directory"), "{e}");
        assert!(!Path::new("-").exists());
    }

    #[test]
    fn uncommitted_output_leaves_the_earlier_file_and_no_stray_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.csv");
        std::fs::write(&out, "earlier").unwrap();
        {
            let f = OutputFile::create("-o", &out).unwrap();
            f.write_all(b"partial").unwrap();
        }
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "earlier");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        assert!(not_written(&out).contains("the earlier file is unchanged"));
        write_atomic("-o", &out, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn commit_through_a_symlink_keeps_the_link() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        std::fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomic("-o", &link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
    }

    #[test]
    fn output_dir_moves_nothing_when_a_file_blocks_a_staged_directory() {
        // reproduce with a file `out/scooter` moved claims.json, index.html, report.md and
        // ride3d/ in, then failed on scooter/ (and printed the io error twice).
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("rep");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("sub"), "mine").unwrap();
        let d = OutputDir::create("-o", &target).unwrap();
        std::fs::write(d.staging().join("a.txt"), "x").unwrap();
        std::fs::create_dir(d.staging().join("sub")).unwrap();
        std::fs::write(d.staging().join("sub/b.txt"), "y").unwrap();
        let e = d.commit(&[]).unwrap_err().to_string();
        assert!(
            e.contains("rep/sub is a file, where this command writes the directory")
                && e.contains("nothing was written into"),
            "{e}"
        );
        assert!(!target.join("a.txt").exists());
        assert_eq!(std::fs::read_to_string(target.join("sub")).unwrap(), "mine");
        // A directory where a staged file goes: refused alike.
        let d = OutputDir::create("-o", &target).unwrap();
        std::fs::write(d.staging().join("a.txt"), "x").unwrap();
        std::fs::write(d.staging().join("z.txt"), "x").unwrap();
        std::fs::create_dir(target.join("z.txt")).unwrap();
        let e = d.commit(&[]).unwrap_err().to_string();
        assert!(
            e.contains("z.txt is a directory, where this command writes a file"),
            "{e}"
        );
        assert!(!target.join("a.txt").exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn output_dir_moves_files_in_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("rep");
        {
            let d = OutputDir::create("-o", &target).unwrap();
            std::fs::write(d.staging().join("a.txt"), "x").unwrap();
        }
        assert!(!target.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        let d = OutputDir::create("-o", &target).unwrap();
        std::fs::create_dir(d.staging().join("sub")).unwrap();
        std::fs::write(d.staging().join("sub/b.txt"), "y").unwrap();
        d.commit(&[]).unwrap();
        assert_eq!(
            std::fs::read_to_string(target.join("sub/b.txt")).unwrap(),
            "y"
        );
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
