//! The input CSV of `pendtilt filter`, row by row through the log reader's line reader,
//! with every problem reported as `FILE:LINE: what`, naming the column.
use anyhow::{bail, Context, Result};
use csv::ByteRecord;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use crate::io::csv_lines::{CsvLines, RowError};

/// The input as CSV lines (the log reader's: [`crate::io::csv_lines`]).
pub(super) type Lines = CsvLines<BufReader<File>>;

/// The file at `path`, named `name` in messages.
pub(super) fn open_reader(path: &Path, name: &Path) -> Result<Lines> {
    let file = File::open(path).with_context(|| format!("cannot open {}", name.display()))?;
    Ok(CsvLines::new(BufReader::with_capacity(1 << 16, file), b','))
}

/// The header's names (lossily decoded, trimmed, unquoted).
pub(super) fn read_header(path: &Path, rdr: &mut Lines) -> Result<Vec<String>> {
    if !next_row(path, rdr, &[])? {
        bail!("{}: empty file: expected a header row", path.display());
    }
    Ok((0..rdr.field_count())
        .map(|i| String::from_utf8_lossy(&rdr.field(i).unwrap_or_default()).into_owned())
        .collect())
}

/// Reads the next data row into `rec` (fields trimmed and unquoted): its line, `None` at
/// the end of the file.
pub(super) fn read_record(
    path: &Path,
    rdr: &mut Lines,
    names: &[String],
    rec: &mut ByteRecord,
) -> Result<Option<u64>> {
    if !next_row(path, rdr, names)? {
        return Ok(None);
    }
    rec.clear();
    for i in 0..rdr.field_count() {
        rec.push_field(&rdr.field(i).unwrap_or_default());
    }
    Ok(Some(rdr.line()))
}

/// Reads and splits the next line; an error as `FILE:LINE: what` when it cannot be read or
/// split, or when its field count is not the header's (`names`, empty for the header).
pub(super) fn next_row(path: &Path, rdr: &mut Lines, names: &[String]) -> Result<bool> {
    let file = path.display();
    match rdr.next_row() {
        Ok(None) => Ok(false),
        Ok(Some(())) => {
            let (len, expected) = (rdr.field_count(), names.len());
            if expected > 0 && len != expected {
                bail!(
                    "{file}:{}: row has {len} fields but the header has {expected}",
                    rdr.line()
                );
            }
            Ok(true)
        }
        Err(RowError::Io(e)) => bail!("{file}:{}: cannot read: {e}", rdr.line() + 1),
        Err(RowError::UnterminatedQuote(i)) => bail!(
            "{file}:{}: column '{}' (field {}): a quoted field is not closed on its line",
            rdr.line(),
            names.get(i).map_or("?", String::as_str),
            i + 1
        ),
    }
}

/// Parses one cell of a filtered (or time) column. Empty means missing (NaN); anything else
/// that is not a number is an error naming file, line and column.
pub(super) fn parse_cell(
    path: &Path,
    line: u64,
    names: &[String],
    i: usize,
    field: Option<&[u8]>,
) -> Result<f64> {
    let name = names.get(i).map_or("?", String::as_str);
    let Some(field) = field else {
        bail!(
            "{}:{line}: column '{name}' (field {}) is missing from this row",
            path.display(),
            i + 1
        );
    };
    let text = String::from_utf8_lossy(field);
    let s = text.trim();
    if s.is_empty() {
        return Ok(f64::NAN);
    }
    s.parse::<f64>().map_err(|_| {
        anyhow::anyhow!(
            "{}:{line}: column '{name}' (field {}): '{s}' is not a number{}",
            path.display(),
            i + 1,
            crate::io::decimal_comma_hint(s)
        )
    })
}

/// The index of the header field named `name`: an error listing the columns if there is
/// none, and an error if there are several (the choice would be a guess).
pub(super) fn find_column(path: &Path, names: &[String], name: &str, what: &str) -> Result<usize> {
    let hits: Vec<usize> = (0..names.len()).filter(|&i| names[i] == name).collect();
    match hits.as_slice() {
        [i] => Ok(*i),
        [] => bail!(
            "{}:1: no {what} column '{name}' in the header; the columns are: {}",
            path.display(),
            names.join(", ")
        ),
        many => bail!(
            "{}:1: the {what} column '{name}' appears {} times in the header (fields {})",
            path.display(),
            many.len(),
            many.iter()
                .map(|i| (i + 1).to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}
