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
use std::fs::{File, Permissions};
use std::io::{self, Write};
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

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

/// Where an [`OutputFile`] writes until it is committed.
#[derive(Debug)]
enum Sink {
    Stdout,
    /// An existing special file (device, pipe), written in place.
    Direct(File),
    /// A temporary file beside the target, renamed onto it on commit.
    Temp(tempfile::NamedTempFile),
}

/// An output file written to a temporary file beside the target and renamed into place
/// only by [`OutputFile::commit`]; dropped uncommitted, it leaves the target as it was.
#[derive(Debug)]
pub struct OutputFile {
    target: PathBuf,
    sink: Sink,
    /// The temporary file, removed if the run is interrupted ([`remove_partial_on_interrupt`]).
    _pending: Option<Pending>,
}

/// The file `path` names, following a symlink (so that committing replaces the file the
/// link points to, and the link stays); `path` itself when it is not a link or dangles.
fn resolve_link(path: &Path) -> PathBuf {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => path.canonicalize().unwrap_or(path.into()),
        _ => path.to_path_buf(),
    }
}

impl OutputFile {
    /// Starts writing `path` (`-` for standard output), named by `option` in errors.
    /// Nothing appears at `path` before [`OutputFile::commit`].
    ///
    /// # Errors
    /// [`OutputError::Unusable`] for a directory or a missing parent directory, and
    /// [`OutputError::Io`] when the temporary file cannot be created.
    pub fn create(option: &str, path: &Path) -> Result<Self, OutputError> {
        let target = path.to_path_buf();
        if is_stdout(path) {
            return Ok(Self {
                target,
                sink: Sink::Stdout,
                _pending: None,
            });
        }
        let unusable = |message: String| OutputError::Unusable {
            option: option.to_string(),
            path: path.display().to_string(),
            message,
        };
        let dest = resolve_link(path);
        if let Ok(m) = std::fs::metadata(&dest) {
            if m.is_dir() {
                return Err(unusable("is a directory; give a file name".into()));
            }
            // A file its owner made read-only is kept: the rename would replace it anyway.
            if m.is_file() && m.permissions().readonly() {
                return Err(unusable(
                    "is read-only, so it is not replaced; make it writable (chmod u+w) or \
                     choose another path"
                        .into(),
                ));
            }
            if !m.is_file() {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&dest)
                    .map_err(|e| io_error(path, e))?;
                return Ok(Self {
                    target,
                    sink: Sink::Direct(file),
                    _pending: None,
                });
            }
        }
        let dir = match dest.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !dir.is_dir() {
            return Err(unusable(format!(
                "the directory {} does not exist",
                dir.display()
            )));
        }
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        // 0o666 before the umask: the file gets the mode a plain create would give it
        // (tempfile's default, 0o600, would make a shared output private).
        let temp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".partial")
            .permissions(Permissions::from_mode(0o666))
            .tempfile_in(&dir)
            .map_err(|e| {
                unusable(format!(
                    "cannot create a temporary file in {}: {e}",
                    dir.display()
                ))
            })?;
        Ok(Self {
            target: dest,
            _pending: Some(Pending::new(temp.path())),
            sink: Sink::Temp(temp),
        })
    }

    /// The path the output will have after the commit (a symlink resolved).
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// A writer into the output (unbuffered; wrap it or give it to a buffering writer).
    ///
    /// # Errors
    /// When the temporary file's handle cannot be duplicated.
    pub fn writer(&self) -> Result<Box<dyn Write + Send>, OutputError> {
        Ok(match &self.sink {
            Sink::Stdout => Box::new(io::stdout()),
            Sink::Direct(f) => Box::new(f.try_clone().map_err(|e| io_error(&self.target, e))?),
            Sink::Temp(t) => Box::new(
                t.as_file()
                    .try_clone()
                    .map_err(|e| io_error(&self.target, e))?,
            ),
        })
    }

    /// Writes all of `bytes` (for outputs formed in memory, like a TOML file).
    ///
    /// # Errors
    /// An I/O error naming the target.
    pub fn write_all(&self, bytes: &[u8]) -> Result<(), OutputError> {
        let mut w = self.writer()?;
        w.write_all(bytes)
            .and_then(|_| w.flush())
            .map_err(|e| io_error(&self.target, e))
    }

    /// Makes the output visible: syncs the temporary file and renames it onto the target
    /// (atomic: a reader sees the earlier file or the new one, never a mix). Call it only
    /// after every writer into it has been flushed and the whole run succeeded.
    ///
    /// # Errors
    /// An I/O error naming the target; the target is then unchanged.
    pub fn commit(self) -> Result<PathBuf, OutputError> {
        match self.sink {
            Sink::Stdout => io::stdout()
                .flush()
                .map_err(|e| io_error(&self.target, e))?,
            Sink::Direct(mut f) => f.flush().map_err(|e| io_error(&self.target, e))?,
            Sink::Temp(t) => {
                t.as_file()
                    .sync_all()
                    .map_err(|e| io_error(&self.target, e))?;
                t.persist(&self.target)
                    .map_err(|e| io_error(&self.target, e.error))?;
            }
        }
        Ok(self.target)
    }
}

/// Writes `bytes` to `path` through an [`OutputFile`]: all of it, or nothing.
///
/// # Errors
/// As [`OutputFile::create`], [`OutputFile::write_all`] and [`OutputFile::commit`].
pub fn write_atomic(option: &str, path: &Path, bytes: &[u8]) -> Result<PathBuf, OutputError> {
    let out = OutputFile::create(option, path)?;
    out.write_all(bytes)?;
    out.commit()
}

/// An output directory written in a staging directory beside it and moved in file by file
/// by [`OutputDir::commit`] only when the whole run succeeded; dropped uncommitted, the
/// staging directory is removed and the target is as it was.
#[derive(Debug)]
pub struct OutputDir {
    option: String,
    target: PathBuf,
    staging: tempfile::TempDir,
    /// The staging directory, removed if the run is interrupted.
    _pending: Pending,
}

impl OutputDir {
    /// Prepares to write into the directory `path` (created on commit if need be).
    ///
    /// # Errors
    /// [`OutputError::Unusable`] when `path` is an existing file or its parent directory
    /// cannot hold the staging directory.
    pub fn create(option: &str, path: &Path) -> Result<Self, OutputError> {
        let unusable = |message: String| OutputError::Unusable {
            option: option.to_string(),
            path: path.display().to_string(),
            message,
        };
        if is_stdout(path) {
            return Err(unusable(
                "this command writes a directory of files, which standard output cannot \
                 take; give a directory"
                    .into(),
            ));
        }
        match std::fs::metadata(path) {
            Ok(m) if !m.is_dir() => {
                let what = if m.is_file() {
                    "a file"
                } else {
                    "a device or pipe"
                };
                return Err(unusable(format!(
                    "is {what}, not a directory: this command writes a directory of files"
                )));
            }
            _ => {}
        }
        let parent = absolute(path)
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        std::fs::create_dir_all(&parent).map_err(|e| {
            unusable(format!(
                "cannot create the directory {}: {e}",
                parent.display()
            ))
        })?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let staging = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".partial")
            .tempdir_in(&parent)
            .map_err(|e| {
                unusable(format!(
                    "cannot create a staging directory in {}: {e}",
                    parent.display()
                ))
            })?;
        Ok(Self {
            option: option.to_string(),
            target: path.to_path_buf(),
            _pending: Pending::new(staging.path()),
            staging,
        })
    }

    /// Where the command writes its files until the commit.
    pub fn staging(&self) -> &Path {
        self.staging.path()
    }

    /// The directory the files go to on commit.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Where a path inside the staging directory ends up after the commit.
    pub fn final_path(&self, staged: &Path) -> PathBuf {
        match staged.strip_prefix(self.staging.path()) {
            Ok(rel) => self.target.join(rel),
            Err(_) => staged.to_path_buf(),
        }
    }

    /// Moves every staged file into the target (creating it and its subdirectories), after
    /// checking that none of them is one of `inputs` ([`check_distinct`]). Files of the
    /// target that the run did not write are left alone.
    ///
    /// # Errors
    /// [`OutputError::SameFile`] or [`OutputError::Unusable`] (a file where a staged
    /// directory goes, or a directory where a staged file goes: then nothing was moved),
    /// or an I/O error.
    pub fn commit(self, inputs: &[NamedPath]) -> Result<PathBuf, OutputError> {
        let mut files = Vec::new();
        collect_files(self.staging.path(), &mut files)
            .map_err(|e| io_error(self.staging.path(), e))?;
        let finals: Vec<PathBuf> = files.iter().map(|f| self.final_path(f)).collect();
        let named: Vec<NamedPath> = finals
            .iter()
            .map(|p| NamedPath::new(&self.option, p))
            .collect();
        check_distinct(inputs, &named)?;
        // Every move must be possible before the first: a file where a staged directory
        // goes (`reproduce -o out` with a file `out/scooter`) moved half the run in.
        for to in &finals {
            let blocked = to
                .ancestors()
                .skip(1)
                .take_while(|a| a.starts_with(&self.target))
                .find(|a| std::fs::metadata(a).is_ok_and(|m| !m.is_dir()));
            let message = match blocked {
                Some(file) => format!(
                    "{} is a file, where this command writes the directory {}: move it away \
                     or give another directory; nothing was written into {}",
                    file.display(),
                    file.display(),
                    self.target.display()
                ),
                None if std::fs::metadata(to).is_ok_and(|m| m.is_dir()) => format!(
                    "{} is a directory, where this command writes a file of that name: move \
                     it away or give another directory; nothing was written into {}",
                    to.display(),
                    self.target.display()
                ),
                None => continue,
            };
            return Err(OutputError::Unusable {
                option: self.option.clone(),
                path: self.target.display().to_string(),
                message,
            });
        }
        for (from, to) in files.iter().zip(&finals) {
            if let Some(dir) = to.parent() {
                std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
            }
            std::fs::rename(from, resolve_link(to)).map_err(|e| io_error(to, e))?;
        }
        Ok(self.target)
    }
}

/// The temporary files and staging directories of the outputs being written, for
/// [`remove_partial_on_interrupt`]: their drop (or commit) removes them on a normal end,
/// but a signal ends the process without running it.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// One entry of [`PENDING`], taken out when dropped.
#[derive(Debug)]
struct Pending(PathBuf);

impl Pending {
    fn new(path: &Path) -> Self {
        let path = absolute(path);
        PENDING
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(path.clone());
        Self(path)
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = pending.iter().position(|p| *p == self.0) {
            pending.swap_remove(i);
        }
    }
}

/// Removes every partial output (the `.NAME.XXXXXX.partial` files and staging directories
/// beside the targets) when the process gets SIGINT (Ctrl-C), SIGTERM or SIGHUP, then ends
/// it with status 128 + the signal's number, saying so on standard error. Without it an
/// interrupted run left them behind, hidden, as large as the run had got (2.7 GB after 20
/// s of `simulate --duration 1e7`). For the `pendtilt` binary: call it first thing in
/// `main`, before any thread starts; the signals are then blocked in every thread and
/// taken by one that waits for them (so the removal is ordinary code, not a signal
/// handler's). A no-op off Unix.
///
/// # Errors
/// When the signal mask cannot be set or the thread cannot start.
pub fn remove_partial_on_interrupt() -> io::Result<()> {
    #[cfg(unix)]
    {
        // SAFETY: sigset_t is plain data, initialised by sigemptyset before any use; the
        // calls only read and write the set and this thread's mask.
        let set = unsafe {
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                libc::sigaddset(&mut set, sig);
            }
            let rc = libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
            if rc != 0 {
                return Err(io::Error::from_raw_os_error(rc));
            }
            set
        };
        std::thread::Builder::new()
            .name("interrupt".into())
            .spawn(move || loop {
                let mut sig: libc::c_int = 0;
                // SAFETY: `set` is an initialised signal set, `sig` a valid out pointer.
                if unsafe { libc::sigwait(&set, &mut sig) } != 0 {
                    continue;
                }
                let paths = PENDING.lock().unwrap_or_else(|e| e.into_inner()).clone();
                for p in &paths {
                    let _ = if p.is_dir() {
                        std::fs::remove_dir_all(p)
                    } else {
                        std::fs::remove_file(p)
                    };
                }
                let removed = if paths.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; the partial output was removed, nothing was written ({})",
                        paths
                            .iter()
                            .map(|p| p.display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                };
                eprintln!("\ninterrupted (signal {sig}){removed}");
                std::process::exit(128 + sig);
            })?;
    }
    Ok(())
}

/// Every file under `dir`, recursively.
fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            collect_files(&path, out)?;
        } else {
            out.push(path);
        }
    }
    out.sort();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
