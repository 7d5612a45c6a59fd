//! Columns of numbers as the lines of a CSV log, made as the reader asks for them.
//!
//! The log reader ([`pendtilt::io::LogReader`]) reads any [`BufRead`]: given this one, it
//! reads a table of NumPy columns exactly as it reads the same table from a file, with
//! every check, unit, warning and message of the command. Each number is written in the
//! shortest form that reads back to the same `f64` (NaN as `NaN`), so the values the
//! estimators get are the columns' own, bit for bit. A block of rows is formatted at a
//! time; memory does not grow with the table.
use std::io::{BufRead, Read};

/// Rows formatted per refill of the buffer.
const BLOCK_ROWS: usize = 512;

/// A table of equally long columns read as CSV text: the header, then one line per row.
pub struct ColumnsSource<'a> {
    columns: Vec<&'a [f64]>,
    rows: usize,
    next_row: usize,
    buf: Vec<u8>,
    pos: usize,
}

impl<'a> ColumnsSource<'a> {
    /// The table with these column `names` (the header) and `columns` (one per name, all
    /// of one length).
    pub fn new(names: &[String], columns: Vec<&'a [f64]>) -> Self {
        let rows = columns.first().map_or(0, |c| c.len());
        let mut buf = Vec::with_capacity(1 << 16);
        for (i, n) in names.iter().enumerate() {
            if i > 0 {
                buf.push(b',');
            }
            if n.contains([',', '"', '\n', '\r']) {
                buf.push(b'"');
                buf.extend_from_slice(n.replace('"', "\"\"").as_bytes());
                buf.push(b'"');
            } else {
                buf.extend_from_slice(n.as_bytes());
            }
        }
        buf.push(b'\n');
        Self {
            columns,
            rows,
            next_row: 0,
            buf,
            pos: 0,
        }
    }

    fn refill(&mut self) {
        self.buf.clear();
        self.pos = 0;
        let end = (self.next_row + BLOCK_ROWS).min(self.rows);
        let mut number = zmij::Buffer::new();
        for r in self.next_row..end {
            for (i, c) in self.columns.iter().enumerate() {
                if i > 0 {
                    self.buf.push(b',');
                }
                push_number(&mut self.buf, &mut number, c[r]);
            }
            self.buf.push(b'\n');
        }
        self.next_row = end;
    }
}

/// `x` in the shortest form that reads back to the same `f64`; `NaN`, `inf`, `-inf`.
pub fn push_number(line: &mut Vec<u8>, buf: &mut zmij::Buffer, x: f64) {
    if x.is_finite() {
        line.extend_from_slice(buf.format_finite(x).as_bytes());
    } else if x.is_nan() {
        line.extend_from_slice(b"NaN");
    } else if x > 0.0 {
        line.extend_from_slice(b"inf");
    } else {
        line.extend_from_slice(b"-inf");
    }
}

impl Read for ColumnsSource<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(out.len());
        out[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for ColumnsSource<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.pos >= self.buf.len() && self.next_row < self.rows {
            self.refill();
        }
        Ok(&self.buf[self.pos..])
    }

    fn consume(&mut self, amt: usize) {
        self.pos = (self.pos + amt).min(self.buf.len());
    }
}
