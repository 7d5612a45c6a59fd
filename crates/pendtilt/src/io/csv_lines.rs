//! The one CSV line reader of the crate: the sensor log reader ([`super::log_reader`]) and
//! `pendtilt filter` both read through it.
//!
//! It reads one line at a time (LF or CRLF), skips a UTF-8 byte-order mark, skips blank
//! lines and lines whose first non-blank character is `#` but counts them, so that every
//! line number it gives is the one an editor shows, and splits a line into fields
//! ([`super::split`]: quotes with `"`, whitespace around a field trimmed). A quoted field
//! therefore may not span lines. What a cell means (a number, missing, an error) is the
//! caller's: this module knows only lines and fields.
use std::borrow::Cow;
use std::io::BufRead;

use super::split::{split_fields, SplitError};

/// A line-by-line CSV reader over any [`BufRead`].
#[derive(Debug)]
pub struct CsvLines<R> {
    input: R,
    delimiter: u8,
    buf: Vec<u8>,
    fields: Vec<(usize, usize)>,
    line: u64,
    /// The current line ended with a line feed (not the input's end in the middle of it).
    terminated: bool,
    /// NUL bytes removed so far, the line of the first, and whether they were said
    /// ([`CsvLines::take_nul`]).
    nul: u64,
    nul_line: u64,
    nul_said: u64,
}

impl<R: BufRead> CsvLines<R> {
    /// A reader of `input` with fields separated by `delimiter`.
    pub fn new(input: R, delimiter: u8) -> Self {
        Self {
            input,
            delimiter,
            buf: Vec::with_capacity(256),
            fields: Vec::with_capacity(16),
            line: 0,
            terminated: true,
            nul: 0,
            nul_line: 0,
            nul_said: 0,
        }
    }

    /// Reads the next line that is neither blank nor a comment (line end and BOM removed;
    /// [`CsvLines::bytes`]). `Ok(false)` at the end of the input. An I/O error is on line
    /// [`CsvLines::line`] `+ 1`.
    pub fn next_line(&mut self) -> std::io::Result<bool> {
        loop {
            self.buf.clear();
            self.fields.clear();
            if self.input.read_until(b'\n', &mut self.buf)? == 0 {
                return Ok(false);
            }
            self.line += 1;
            self.terminated = self.buf.last() == Some(&b'\n');
            if self.terminated {
                self.buf.pop();
            }
            if self.buf.last() == Some(&b'\r') {
                self.buf.pop();
            }
            self.strip_nul();
            if self.line == 1 && self.buf.starts_with(b"\xEF\xBB\xBF") {
                self.buf.drain(..3);
            }
            match self.buf.iter().find(|b| !matches!(b, b' ' | b'\t' | b'\r')) {
                None | Some(b'#') => continue,
                Some(_) => return Ok(true),
            }
        }
    }

    /// Removes NUL bytes around the current line: the space an SD-card logger allocated
    /// and never wrote, or a write a power loss cut (a line they end is cut: its last cell
    /// may be cut short). A line of NULs alone is then blank.
    fn strip_nul(&mut self) {
        let len = self.buf.len();
        let Some(start) = self.buf.iter().position(|&b| b != 0) else {
            if len > 0 {
                self.note_nul(len);
                self.buf.clear();
            }
            return;
        };
        let end = self
            .buf
            .iter()
            .rposition(|&b| b != 0)
            .map_or(len, |e| e + 1);
        if start == 0 && end == len {
            return;
        }
        self.note_nul(len - (end - start));
        if end < len {
            self.terminated = false;
        }
        self.buf.truncate(end);
        self.buf.drain(..start);
        if self.buf.last() == Some(&b'\r') {
            self.buf.pop();
        }
    }

    fn note_nul(&mut self, n: usize) {
        if self.nul == 0 {
            self.nul_line = self.line;
        }
        self.nul += n as u64;
    }

    /// NUL bytes removed since the last call: `(line of the first ever, count so far)`, or
    /// `None` when there were none new.
    pub fn take_nul(&mut self) -> Option<(u64, u64)> {
        if self.nul == self.nul_said {
            return None;
        }
        self.nul_said = self.nul;
        Some((self.nul_line, self.nul))
    }

    /// True unless the input ended in the middle of the current line (no line feed after
    /// it: a log cut while being written, the last line of a file without one).
    pub fn terminated(&self) -> bool {
        self.terminated
    }

    /// Forgets the current line's last field (a cell the input's end may have cut short
    /// reads as absent).
    pub fn drop_last_field(&mut self) {
        self.fields.pop();
    }

    /// Splits the current line into fields. `Err(i)`: field `i` (0-based) opens a quote
    /// that the line does not close.
    pub fn split(&mut self) -> Result<(), usize> {
        split_fields(&self.buf, self.delimiter, &mut self.fields)
            .map_err(|SplitError::UnterminatedQuote(i)| i)
    }

    /// [`CsvLines::next_line`] then [`CsvLines::split`]: `Ok(None)` at the end of the input.
    pub fn next_row(&mut self) -> Result<Option<()>, RowError> {
        if !self.next_line().map_err(RowError::Io)? {
            return Ok(None);
        }
        self.split().map_err(RowError::UnterminatedQuote)?;
        Ok(Some(()))
    }

    /// The 1-based number of the current line (blank and comment lines counted).
    pub fn line(&self) -> u64 {
        self.line
    }

    /// The current line's bytes, without its line end.
    pub fn bytes(&self) -> &[u8] {
        &self.buf
    }

    /// The fields of the current line as byte ranges of [`CsvLines::bytes`] (a quoted
    /// field's range is its content, doubled quotes still doubled).
    pub fn ranges(&self) -> &[(usize, usize)] {
        &self.fields
    }

    /// Number of fields on the current line.
    pub fn field_count(&self) -> usize {
        self.fields.len()
    }

    /// Field `i`'s bytes as written between the delimiters (trimmed, quotes removed,
    /// doubled quotes still doubled); `None` past the last field.
    pub fn raw(&self, i: usize) -> Option<&[u8]> {
        self.fields.get(i).map(|&(a, b)| &self.buf[a..b])
    }

    /// True when no field of the current line is a number (empty fields aside): a header
    /// or a units line, not data.
    pub fn all_text(&self) -> bool {
        (0..self.field_count()).all(|i| {
            self.raw(i).is_none_or(|f| {
                f.is_empty()
                    || std::str::from_utf8(f)
                        .ok()
                        .and_then(|t| t.parse::<f64>().ok())
                        .is_none()
            })
        })
    }

    /// Field `i`'s content: as [`CsvLines::raw`] with doubled quotes undone.
    pub fn field(&self, i: usize) -> Option<Cow<'_, [u8]>> {
        let raw = self.raw(i)?;
        Some(if raw.windows(2).any(|w| w == b"\"\"") {
            let mut v = Vec::with_capacity(raw.len());
            let mut k = 0;
            while k < raw.len() {
                v.push(raw[k]);
                k += if raw[k] == b'"' && raw.get(k + 1) == Some(&b'"') {
                    2
                } else {
                    1
                };
            }
            Cow::Owned(v)
        } else {
            Cow::Borrowed(raw)
        })
    }
}

/// Why [`CsvLines::next_row`] could not give a row.
#[derive(Debug, thiserror::Error)]
pub enum RowError {
    /// The input could not be read (on the line after [`CsvLines::line`]).
    #[error("cannot read: {0}")]
    Io(std::io::Error),
    /// Field `.0` (0-based) opens a quote that its line does not close.
    #[error("a quoted field is not closed on its line")]
    UnterminatedQuote(usize),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_skipped_lines_and_unquotes() {
        let text = "\u{feff}t,x\r\n\n# note\n  \n1, \"a \"\"b\"\"\" \n2,c\n";
        let mut r = CsvLines::new(text.as_bytes(), b',');
        assert!(r.next_row().unwrap().is_some());
        assert_eq!((r.line(), r.field_count()), (1, 2));
        assert_eq!(r.raw(0), Some(&b"t"[..]));
        assert!(r.next_row().unwrap().is_some());
        assert_eq!(r.line(), 5);
        assert_eq!(r.field(1).as_deref(), Some(&b"a \"b\""[..]));
        assert!(r.next_row().unwrap().is_some());
        assert_eq!((r.line(), r.field(1).as_deref()), (6, Some(&b"c"[..])));
        assert!(r.next_row().unwrap().is_none());
    }

    #[test]
    fn unclosed_quote_names_its_field() {
        let mut r = CsvLines::new(&b"a,\"b\n"[..], b',');
        assert!(matches!(r.next_row(), Err(RowError::UnterminatedQuote(1))));
    }
}
