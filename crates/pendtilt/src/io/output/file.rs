//! One output file, written beside its target and renamed into place on commit.
use std::fs::{File, Permissions};
use std::io::{self, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use super::interrupt::Pending;
use super::{io_error, is_stdout, OutputError};

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
pub(super) fn resolve_link(path: &Path) -> PathBuf {
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
