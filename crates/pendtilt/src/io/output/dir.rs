//! An output directory, staged beside its target and moved in file by file on commit.
use std::path::{Path, PathBuf};

use super::file::resolve_link;
use super::interrupt::{collect_files, Pending};
use super::{absolute, check_distinct, io_error, is_stdout, NamedPath, OutputError};

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
