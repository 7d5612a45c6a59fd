//! The cells of a row: the field count, the numbers, and what each missing, impossible or
//! degree-looking cell is read as, with its warning or error.
use std::io::BufRead;

use super::{
    not_a_number_hint, CellRef, LogError, LogErrorKind, LogReader, RowIssues,
    ANGLE_LOOKS_LIKE_DEGREES, RATE_LOOKS_LIKE_DEGREES,
};
use crate::io::columns::Column;
use crate::io::diagnostics::WarningKind;

impl<R: BufRead> LogReader<R> {
    /// A row with more (non-empty) fields than the header is an error; one with fewer is
    /// read with the absent cells missing, and a warning.
    #[inline]
    pub(super) fn check_field_count(&mut self, issues: &mut RowIssues) -> Result<(), LogError> {
        let expected = self.header.len();
        let found = self.lines.ranges().len();
        if found > expected {
            let extra_nonempty = self.lines.ranges()[expected..].iter().any(|&(a, b)| b > a);
            if extra_nonempty {
                let line = Some(self.lines.line());
                return Err(self.error(
                    line,
                    None,
                    LogErrorKind::TooManyFields { found, expected },
                ));
            }
        } else if found < expected {
            issues.truncated = true;
            // Cut by the input's end (a log cut while written, `stream` stopped): its last
            // cell may be cut too (`-0.02` of `-0.0215`); it reads as absent, never as a
            // number it was not.
            let cut = if self.lines.terminated() {
                String::new()
            } else {
                let (a, b) = self.lines.ranges()[found - 1];
                let text = String::from_utf8_lossy(&self.lines.bytes()[a..b]).into_owned();
                self.lines.drop_last_field();
                format!(
                    "; the input ends in this line, so its last cell `{text}` (field {found}, \
                     `{}`) may be cut short and reads as missing too",
                    self.header[found - 1]
                )
            };
            self.warn(
                WarningKind::TruncatedRow,
                None,
                None,
                format!(
                    "{found} fields, the header has {expected} (a truncated line?): \
                     the absent cells read as missing{cut}"
                ),
            );
        }
        Ok(())
    }

    /// The used cells of the row as numbers (`None`: absent or not a number). The line is
    /// checked for UTF-8 once, and every field (cut at ASCII delimiters and blanks) is
    /// then valid text too.
    #[inline]
    pub(super) fn parse_used(&self) -> [Option<f64>; 6] {
        let mut parsed = [None; 6];
        let whole = std::str::from_utf8(self.lines.bytes()).ok();
        for column in Column::ALL {
            let Some(&(a, b)) =
                self.positions[column.index()].and_then(|p| self.lines.ranges().get(p))
            else {
                continue;
            };
            let text = match whole {
                Some(w) => w.get(a..b),
                None => std::str::from_utf8(&self.lines.bytes()[a..b]).ok(),
            };
            parsed[column.index()] = text.and_then(|t| t.parse::<f64>().ok());
        }
        parsed
    }

    /// The used cells in SI units (NaN where missing or implausible), and the same before
    /// the plausibility check (an implausible reading as it was).
    #[inline]
    pub(super) fn used_cells(
        &mut self,
        parsed: &[Option<f64>; 6],
        issues: &mut RowIssues,
    ) -> Result<([f64; 6], [f64; 6]), LogError> {
        let mut values = [f64::NAN; 6];
        let mut unchecked = [f64::NAN; 6];
        for column in Column::ALL {
            let Some(pos) = self.positions[column.index()] else {
                continue;
            };
            // The time scale of --time-unit lives in `scale` like the degree factors.
            let value = self.cell(column, pos, parsed[column.index()], issues)?;
            values[column.index()] = value;
            unchecked[column.index()] = if issues.implausible[column.index()] {
                parsed[column.index()].unwrap_or(f64::NAN) * self.scale[column.index()]
            } else {
                value
            };
        }
        Ok((values, unchecked))
    }

    /// When the current line is a header (no field a number, one of them the time
    /// column's name: two logs joined, a logger that restarted into the same file or
    /// stream): what to say about it.
    pub(super) fn header_again(&self) -> Option<String> {
        let n = self.lines.field_count();
        let fields: Vec<String> = (0..n)
            .map(|i| {
                self.lines
                    .field(i)
                    .map(|f| String::from_utf8_lossy(&f).into_owned())
                    .unwrap_or_default()
            })
            .collect();
        let t_name = &self.header[self.positions[Column::T.index()]?];
        let header_like = fields.iter().any(|f| f == t_name)
            && fields
                .iter()
                .all(|f| f.is_empty() || f.trim().parse::<f64>().is_err());
        if !header_like {
            return None;
        }
        Some(if fields == self.header {
            format!("the header again (as on line {})", self.header_line)
        } else {
            format!(
                "a new header ({}; line {} has {})",
                fields.join(", "),
                self.header_line,
                self.header.join(", ")
            )
        })
    }

    /// One used cell (`parsed`: its number, `None` if it is not one): a finite value in SI
    /// units, or NaN (with a warning) when it is missing; an error when it is not a number.
    pub(super) fn cell(
        &mut self,
        column: Column,
        pos: usize,
        parsed: Option<f64>,
        issues: &mut RowIssues,
    ) -> Result<f64, LogError> {
        let Some(&(a, b)) = self.lines.ranges().get(pos) else {
            // Absent from a truncated row (already warned about).
            self.summary.missing_cells[column.index()] += 1;
            issues.missing_values = true;
            return Ok(f64::NAN);
        };
        if a == b {
            let why = "empty cell: read as missing".to_string();
            return Ok(self.missing(column, pos, issues, WarningKind::EmptyCell, why));
        }
        let Some(raw) = parsed else {
            return Err(self.not_a_number(pos, (a, b)));
        };
        if !raw.is_finite() {
            let why = format!(
                "{}: read as missing, the estimators hold and flag this sample",
                self.non_finite((a, b), raw)
            );
            return Ok(self.missing(column, pos, issues, WarningKind::NonFinite, why));
        }
        let value = raw * self.scale[column.index()];
        if let Some(reason) = self.options.limits.check(column, value, raw) {
            issues.implausible[column.index()] = true;
            return Ok(self.missing(column, pos, issues, WarningKind::Implausible, reason));
        }
        if self.scale[column.index()].abs() == 1.0 && !self.degree_warned[column.index()] {
            self.degrees_warning(column, pos, raw);
        }
        Ok(value)
    }

    /// NaN for the cell of `column` at field `pos`, counted as missing and warned about as
    /// `kind`, `why`.
    fn missing(
        &mut self,
        column: Column,
        pos: usize,
        issues: &mut RowIssues,
        kind: WarningKind,
        why: String,
    ) -> f64 {
        self.summary.missing_cells[column.index()] += 1;
        issues.missing_values = true;
        let h = self.header[pos].clone();
        self.warn(kind, Some(column), Some(h), why);
        f64::NAN
    }

    /// The error for the cell at field `pos` (bytes `a..b` of the line), not a number: a
    /// header again, or the text with a hint.
    fn not_a_number(&mut self, pos: usize, (a, b): (usize, usize)) -> LogError {
        if let Some(what) = self.header_again() {
            let line = Some(self.lines.line());
            return self.error(line, None, LogErrorKind::HeaderAgain { what });
        }
        let text = String::from_utf8_lossy(&self.lines.bytes()[a..b]).into_owned();
        let cell = CellRef {
            position: pos + 1,
            header: self.header[pos].clone(),
        };
        let line = self.lines.line();
        let hint = not_a_number_hint(
            &text,
            self.summary.rows == 0,
            self.lines.all_text(),
            line,
            &self.file,
        );
        let kind = LogErrorKind::NotANumber { text, hint };
        self.error(Some(line), Some(cell), kind)
    }

    /// A non-finite cell (bytes `a..b`, read as `raw`) as written: `1e400` parses to inf,
    /// so what was written is quoted, not `inf`; and `nan` as `nan`, not `NaN`.
    fn non_finite(&self, (a, b): (usize, usize), raw: f64) -> String {
        let text = String::from_utf8_lossy(&self.lines.bytes()[a..b]);
        let word = text
            .trim()
            .trim_start_matches(['+', '-'])
            .to_ascii_lowercase();
        let shown: String = text.trim().chars().take(40).collect();
        let more = if text.trim().chars().count() > 40 {
            "..."
        } else {
            ""
        };
        if raw.is_nan() || ["inf", "infinity"].contains(&word.as_str()) {
            format!("`{shown}{more}`")
        } else {
            format!("`{shown}{more}` is beyond the largest number, 1.8e308 ({raw})")
        }
    }

    /// Warns, once per column, of a reading `raw` in radians that looks like degrees.
    fn degrees_warning(&mut self, column: Column, pos: usize, raw: f64) {
        let limit = match column {
            Column::Phi | Column::Theta => ANGLE_LOOKS_LIKE_DEGREES,
            Column::Gyro => RATE_LOOKS_LIKE_DEGREES,
            _ => f64::INFINITY,
        };
        if raw.abs() > limit {
            self.degree_warned[column.index()] = true;
            let h = self.header[pos].clone();
            let unit = column.unit();
            self.warn(
                WarningKind::LooksLikeDegrees,
                Some(column),
                Some(h),
                format!(
                    "{raw} is beyond {limit} {unit}: the column looks like degrees; \
                     if it is, read it with --deg {column}"
                ),
            );
        }
    }
}
