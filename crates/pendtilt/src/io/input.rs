//! A log named on the command line: a file, `-` for standard input, or a pipe
//! (`<(zcat log.csv.gz)`, `/dev/stdin`, a FIFO).
//!
//! `estimate` reads its log once, front to back: a pipe is read as it comes
//! ([`LogSource`]), its header peeked at to tell a planar log from a 3-D one without losing
//! a line. `filter` checks the whole file before it filters, so it reads it twice: a pipe
//! is copied to a temporary file first ([`InputLog`], removed when dropped). Messages name
//! the input as the user gave it (`<stdin>` for `-`), never a copy.
use std::fs::File;
use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};

use super::csv_lines::CsvLines;

use super::log_reader::{LogError, LogErrorKind};

/// The name messages give standard input.
pub const STDIN_NAME: &str = "<stdin>";

/// A log to read, by path: the file itself, or a temporary copy of standard input or a
/// pipe.
#[derive(Debug)]
pub struct InputLog {
    path: PathBuf,
    name: String,
    // Removes the copy when dropped.
    _copy: Option<tempfile::TempPath>,
}

/// True for the path `-` (standard input).
pub fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == "-"
}

impl InputLog {
    /// The log at `arg` (`-`: standard input), copied to a temporary file first when it is
    /// standard input or anything else that is not a regular file. A path that does not
    /// exist is kept as it is, for the reader to report.
    ///
    /// # Errors
    /// Reading standard input or the pipe, or writing the copy, failed.
    pub fn open(arg: &Path) -> Result<Self, LogError> {
        let stdin = is_stdin(arg);
        let name = if stdin {
            STDIN_NAME.to_string()
        } else {
            arg.display().to_string()
        };
        let copy = match std::fs::metadata(arg) {
            _ if stdin => true,
            Ok(m) => !m.is_file(),
            Err(_) => false,
        };
        if !copy {
            return Ok(Self {
                path: arg.to_path_buf(),
                name,
                _copy: None,
            });
        }
        let io = |e: std::io::Error| LogError {
            file: name.clone(),
            line: None,
            column: None,
            kind: Box::new(LogErrorKind::Io(e)),
        };
        let mut tmp = tempfile::NamedTempFile::new().map_err(io)?;
        if stdin {
            std::io::copy(&mut std::io::stdin().lock(), &mut tmp).map_err(io)?;
        } else {
            std::io::copy(&mut File::open(arg).map_err(io)?, &mut tmp).map_err(io)?;
        }
        let path = tmp.into_temp_path();
        Ok(Self {
            path: path.to_path_buf(),
            name,
            _copy: Some(path),
        })
    }

    /// Where to read it: the file, or the copy.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The name messages give it: the path as given, or `<stdin>`.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// True when this is a copy of standard input or a pipe.
    pub fn is_copy(&self) -> bool {
        self._copy.is_some()
    }
}

/// A log to read once, front to back: a regular file by its path, or standard input or a
/// pipe as a stream whose header was peeked at ([`peek_header`]), so that it is estimated
/// as it arrives, in constant memory, with nothing copied.
pub enum LogSource {
    /// A regular file (or a path that does not exist, for the reader to report).
    File(PathBuf),
    /// Standard input or a pipe: its header (`None`: it ended before one) and every byte.
    Stream {
        /// The header's fields.
        header: Option<Vec<String>>,
        /// The input from its first byte.
        reader: Peeked<Box<dyn BufRead + Send>>,
    },
}

impl LogSource {
    /// The log at `arg` (`-`: standard input).
    ///
    /// # Errors
    /// Opening the pipe or reading up to its header failed (named as given).
    pub fn open(arg: &Path) -> Result<(Self, String), LogError> {
        let stdin = is_stdin(arg);
        let name = if stdin {
            STDIN_NAME.to_string()
        } else {
            arg.display().to_string()
        };
        let regular = !stdin && std::fs::metadata(arg).map_or(true, |m| m.is_file());
        if regular {
            return Ok((Self::File(arg.to_path_buf()), name));
        }
        let io = |e: std::io::Error| LogError {
            file: name.clone(),
            line: None,
            column: None,
            kind: Box::new(LogErrorKind::Io(e)),
        };
        let input: Box<dyn BufRead + Send> = if stdin {
            Box::new(std::io::BufReader::with_capacity(1 << 16, std::io::stdin()))
        } else {
            let f = File::open(arg).map_err(io)?;
            Box::new(std::io::BufReader::with_capacity(1 << 16, f))
        };
        let (header, reader) = peek_header(input).map_err(io)?;
        Ok((Self::Stream { header, reader }, name))
    }
}

/// A live input after [`peek_header`]: the lines read to find the header, then the rest.
pub type Peeked<R> = std::io::Chain<std::io::Cursor<Vec<u8>>, R>;

/// Reads `input` up to its header line (blank and `#` comment lines before it skipped,
/// as the log readers skip them) and returns the header's fields and a reader that gives
/// every byte again from the start: a live stream can be told planar or 3-D by its header
/// without losing a line. `None` for an input that ends before a header.
///
/// # Errors
/// Reading `input` failed.
pub fn peek_header<R: BufRead>(mut input: R) -> std::io::Result<(Option<Vec<String>>, Peeked<R>)> {
    let mut seen = Vec::new();
    let header = loop {
        let start = seen.len();
        if input.read_until(b'\n', &mut seen)? == 0 {
            break None;
        }
        // The readers' own line reader, on this line alone (a byte-order mark, quotes).
        let mut line = CsvLines::new(&seen[start..], b',');
        if let Ok(Some(())) = line.next_row() {
            break Some(
                (0..line.field_count())
                    .filter_map(|i| line.field(i))
                    .map(|f| String::from_utf8_lossy(&f).into_owned())
                    .collect(),
            );
        }
    };
    Ok((header, std::io::Cursor::new(seen).chain(input)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_is_peeked_and_every_byte_given_again() {
        let text = "\u{feff}# a comment\n\n t , phi_x,\"phi_y\"\n0,1,2\n1,2,3\n";
        let (header, mut rest) = peek_header(text.as_bytes()).unwrap();
        assert_eq!(header.unwrap(), ["t", "phi_x", "phi_y"]);
        let mut again = String::new();
        rest.read_to_string(&mut again).unwrap();
        assert_eq!(again, text);
        let (none, _) = peek_header("# only a comment\n".as_bytes()).unwrap();
        assert!(none.is_none());
    }

    #[test]
    fn a_regular_file_is_read_in_place_and_a_pipe_is_copied() {
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join("log.csv");
        std::fs::write(&f, "t,phi\n0,1\n").unwrap();
        let log = InputLog::open(&f).unwrap();
        assert_eq!(log.path(), f);
        assert!(!log.is_copy());
        assert_eq!(log.name(), f.display().to_string());

        // A path that does not exist is left for the reader to name.
        let missing = d.path().join("nope.csv");
        let log = InputLog::open(&missing).unwrap();
        assert_eq!(log.path(), missing);

        #[cfg(unix)]
        {
            // A FIFO: copied once, then readable as often as needed, named as given.
            let fifo = d.path().join("fifo");
            let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
            // SAFETY: a valid NUL-terminated path.
            assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
            let writer = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::write(fifo, "t,phi\n0,2\n").unwrap())
            };
            let log = InputLog::open(&fifo).unwrap();
            writer.join().unwrap();
            assert!(log.is_copy());
            assert_eq!(log.name(), fifo.display().to_string());
            for _ in 0..2 {
                assert_eq!(std::fs::read_to_string(log.path()).unwrap(), "t,phi\n0,2\n");
            }
            let copy = log.path().to_path_buf();
            drop(log);
            assert!(!copy.exists(), "the copy is removed with the InputLog");
        }
    }
}
