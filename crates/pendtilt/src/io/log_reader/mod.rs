//! Streaming reader of the sensor log (MODEL.md section 5).
//!
//! One [`LogRecord`] per data row, in file order, never a row dropped; memory does not
//! grow with the log. What is wrong with a file is either an error that stops the read
//! ([`LogError`], naming the file, the line and the column) or, when the row can still be
//! used, a warning ([`LogWarning`]) queued for the caller together with a flagged or
//! missing (NaN) value that the estimators hold through and flag. The library never
//! prints. See `docs/bad-input.md` for the table of cases and outcomes.
//!
//! The format: a header row, then one row per sample, fields separated by `,` (or
//! [`ReaderOptions::delimiter`]), optionally quoted with `"`. Line ends may be LF or CRLF;
//! a UTF-8 byte-order mark is skipped; blank lines and lines whose first non-blank
//! character is `#` are skipped (before and after the header) but still counted, so that
//! every line number is the one an editor shows. Whitespace around a field is ignored.
//! Lines are read and split by [`super::csv_lines`] rather than by the `csv` crate because
//! that crate does not count comment lines in its line numbers; quoted fields therefore
//! may not span lines.
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use pendtilt_core::{Sample, StepGate};

use super::columns::{
    header_unit_warning, shell_word, time_named_suggestion, time_unit_in_name,
    unit_named_suggestion, Column, ColumnMap, ColumnReport, ColumnStatus, DegreeColumns,
    NegatedColumns,
};
use super::csv_lines::CsvLines;
use super::diagnostics::{LogSummary, LogWarning, WarningKind};
use super::plausibility::{AccelUnit, SensorLimits, TimeUnit};
use super::split::unquote;
use crate::sensors::Inputs;
use crate::units::{Finding, UnitCheck};

/// An angle beyond this \[rad\] in a column read as radians looks like degrees (about 200
/// degrees: a pendulum or a tilt never gets there, a degree value of a few tens does).
pub const ANGLE_LOOKS_LIKE_DEGREES: f64 = 3.5;
/// A rate beyond this \[rad/s\] in a gyro column read as rad/s looks like deg/s (2000
/// deg/s is the largest full scale of common MEMS gyros).
pub const RATE_LOOKS_LIKE_DEGREES: f64 = 35.0;

/// Options of the log reader.
#[derive(Debug, Clone, PartialEq)]
pub struct ReaderOptions {
    /// Other header names for the contract columns (`--map`).
    pub map: ColumnMap,
    /// Angular columns given in degrees (`--deg`); converted to radians as read.
    pub degrees: DegreeColumns,
    /// Columns that count the other way (`--negate`); negated as read.
    pub negate: NegatedColumns,
    /// Field separator. Default `,`.
    pub delimiter: u8,
    /// A time step longer than this many nominal steps is reported as a gap. Default 3.
    pub gap_factor: f64,
    /// A time step that differs from the nominal one by more than this fraction of it
    /// (and is not a gap) is counted as jitter. Default 0.5.
    pub jitter_tolerance: f64,
    /// Warnings of one kind queued for the caller before the rest are only counted.
    /// Default 10.
    pub max_reported: usize,
    /// The bounds beyond which a reading is impossible and read as missing (flagged
    /// [`RowIssues::implausible`]). Default: the physical bounds of
    /// [`super::plausibility`].
    pub limits: SensorLimits,
    /// The unit of `t` (`--time-unit`). `None` (default): seconds, and a median step that
    /// no sensor rate explains (a log in ms or us) is an error naming the fix; given, the
    /// time is converted and not checked.
    pub time_unit: Option<TimeUnit>,
    /// The unit of `ax`, `ay` (`--accel-unit`). `None` (default): m/s^2; either way, a log
    /// whose specific force is not gravity's in size is told with the unit that explains
    /// it ([`crate::units::AccelMagnitude`], with the unit check below).
    pub accel_unit: Option<AccelUnit>,
    /// The rig's pendulum natural frequency \[Hz\]: given, the unit check from the physics
    /// ([`crate::units::UnitCheck`]) runs over the whole log, and what it finds (a gyro in
    /// deg/s, ...) is warned about at the end ([`WarningKind::UnitMismatch`], also
    /// [`LogReader::unit_findings`]), for every command that reads a log. Default: the
    /// MODEL.md rig's (2.19 Hz); `None`: not checked.
    pub natural_frequency: Option<f64>,
}

impl ReaderOptions {
    /// The defaults with what the rig tells: its sensors' bounds
    /// ([`ReaderOptions::limits`]) and its pendulum's natural frequency
    /// ([`ReaderOptions::natural_frequency`]).
    pub fn for_rig(rig: &crate::config::RigConfig) -> Self {
        Self {
            limits: SensorLimits::of_rig(rig),
            natural_frequency: Some(rig.params().natural_frequency_hz()),
            ..Self::default()
        }
    }
}

impl Default for ReaderOptions {
    fn default() -> Self {
        Self {
            map: ColumnMap::new(),
            degrees: DegreeColumns::none(),
            negate: NegatedColumns::none(),
            delimiter: b',',
            gap_factor: 3.0,
            jitter_tolerance: 0.5,
            max_reported: 10,
            limits: SensorLimits::default(),
            time_unit: None,
            accel_unit: None,
            natural_frequency: Some(
                crate::config::RigConfig::default()
                    .params()
                    .natural_frequency_hz(),
            ),
        }
    }
}

/// What is wrong with a row, beyond the NaN values it carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RowIssues {
    /// The row had fewer fields than the header; the absent cells are missing (NaN).
    pub truncated: bool,
    /// At least one used cell was empty, `nan` or `inf` (now NaN in the sample).
    pub missing_values: bool,
    /// The time is missing, or not later than the previous row's: the estimators flag
    /// `bad_time_step` on this sample.
    pub bad_time: bool,
    /// The time step before this row is a gap (longer than `gap_factor` nominal steps).
    pub time_gap: bool,
    /// Per contract column ([`Column::ALL`] order): the cell held an impossible reading
    /// (beyond the sensor's full scale, or physically impossible), now NaN.
    pub implausible: [bool; 6],
}

impl RowIssues {
    /// True when nothing was wrong.
    pub fn is_clean(&self) -> bool {
        *self == Self::default()
    }

    /// True when `column`'s cell held an impossible reading (now NaN).
    pub fn is_implausible(&self, column: Column) -> bool {
        self.implausible[column.index()]
    }
}

/// One data row of the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogRecord {
    /// 1-based line in the file (comment and blank lines counted).
    pub line: u64,
    /// The time stamp \[s\] (NaN when the cell is missing or not finite).
    pub t: f64,
    /// The sensors in SI units, `dt` from the reader's [`StepGate`]; a missing or non-finite cell, or a column the log does not
    /// have, is NaN.
    pub sample: Sample<f64>,
    /// The true tilt \[rad\]: `None` when the log has no `theta` column, `Some(NaN)` when
    /// this row's cell is missing.
    pub theta: Option<f64>,
    /// The sensors as read, before the plausibility check: equal to `sample` except where
    /// a cell was implausible ([`RowIssues::implausible`]), which `sample` has as NaN. For
    /// checks of the log as a whole (units), never for the estimators.
    pub unchecked: Sample<f64>,
    /// What was wrong with the row.
    pub issues: RowIssues,
}

mod cells;
mod error;
mod header;
mod time;
pub use error::{
    decimal_comma_hint, not_a_number_hint, CellRef, LogError, LogErrorKind, DECIMAL_COMMA_FIX,
};
use time::NOMINAL_DT_SAMPLES;
pub use time::{new_time_base, TimeBack};

/// Streaming sensor-log reader over any [`BufRead`].
///
/// [`LogReader::new`] reads the header (and the lines before it) and resolves the
/// columns; each [`LogReader::next_record`] (or iterator step) reads one data row. After
/// an error the reader is finished. Warnings queue up, at most
/// [`ReaderOptions::max_reported`] per kind (the rest are counted in
/// [`LogReader::summary`]); take them with [`LogReader::drain_warnings`].
#[derive(Debug)]
pub struct LogReader<R> {
    lines: CsvLines<R>,
    file: String,
    options: ReaderOptions,
    header: Vec<String>,
    /// Field position of each contract column.
    positions: [Option<usize>; 6],
    /// Factor to SI of each contract column (pi/180 for degrees).
    scale: [f64; 6],
    report: ColumnReport,
    summary: LogSummary,
    // Stamps into steps, once for every estimator.
    gate: StepGate<f64>,
    pending: Vec<LogWarning>,
    reported: [usize; WarningKind::ALL.len()],
    degree_warned: [bool; 6],
    last_t: Option<f64>,
    first_dts: Vec<f64>,
    /// Zero time steps (a repeated stamp) before the rate check.
    zero_steps: u64,
    /// The header's line (after comment and blank lines).
    header_line: u64,
    /// The time step has been checked against plausible rates.
    rate_checked: bool,
    /// The previous row's time went back by more than [`TIME_BASE_JUMP`](time::TIME_BASE_JUMP).
    went_back: Option<TimeBack>,
    /// The unit check ([`ReaderOptions::natural_frequency`]) and, at the end, its findings.
    units: Option<UnitCheck>,
    unit_findings: Vec<Finding>,
    finished: bool,
}

/// What to say about `n` NUL bytes removed, the first on `line` (never the bytes: they
/// would garble a terminal).
pub fn nul_message(line: u64, n: u64) -> String {
    format!(
        "{n} NUL byte(s) from line {line} on (space a logger allocated and never wrote, or a \
         write a power loss cut): removed, a line of them alone read as blank, a line they \
         end as cut (its last cell may be cut short)"
    )
}

impl LogReader<BufReader<File>> {
    /// Opens a log file; errors (and warnings) name it as given.
    pub fn open(path: impl AsRef<Path>, options: ReaderOptions) -> Result<Self, LogError> {
        let path = path.as_ref();
        Self::open_as(path, &path.display().to_string(), options)
    }

    /// Opens the log file at `path`; errors and warnings name it `name` (the path the user
    /// gave, or `<stdin>` for a copy of standard input: [`super::input::InputLog`]).
    pub fn open_as(path: &Path, name: &str, options: ReaderOptions) -> Result<Self, LogError> {
        let file = File::open(path).map_err(|e| LogError {
            file: name.to_string(),
            line: None,
            column: None,
            kind: Box::new(LogErrorKind::Io(e)),
        })?;
        Self::new(BufReader::with_capacity(1 << 16, file), name, options)
    }
}

impl<R: BufRead> LogReader<R> {
    /// Reads the header from `input`; `origin` names the source in messages.
    pub fn new(input: R, origin: &str, options: ReaderOptions) -> Result<Self, LogError> {
        let mut reader = Self {
            lines: CsvLines::new(input, options.delimiter),
            file: origin.to_string(),
            options,
            header: Vec::new(),
            positions: [None; 6],
            scale: [1.0; 6],
            report: ColumnReport {
                columns: Vec::new(),
                ignored: Vec::new(),
            },
            summary: LogSummary::default(),
            gate: StepGate::new(),
            pending: Vec::new(),
            reported: [0; WarningKind::ALL.len()],
            degree_warned: [false; 6],
            last_t: None,
            first_dts: Vec::with_capacity(NOMINAL_DT_SAMPLES),
            zero_steps: 0,
            header_line: 1,
            rate_checked: false,
            went_back: None,
            units: None,
            unit_findings: Vec::new(),
            finished: false,
        };
        reader.read_header()?;
        let has = |c: Column| reader.positions[c.index()].is_some();
        let inputs = Inputs::from_fn(|s| Column::provides(s, has));
        reader.units = reader.options.natural_frequency.map(|f_n| {
            UnitCheck::with_natural_frequency(f_n, inputs)
                .with_accel_unit(reader.options.accel_unit)
        });
        Ok(reader)
    }

    /// The name used for the source in messages.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// Which contract columns were found (and how), missing, or ignored.
    pub fn columns(&self) -> &ColumnReport {
        &self.report
    }

    /// The header names, in file order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// Counts over the rows read so far.
    pub fn summary(&self) -> &LogSummary {
        &self.summary
    }

    /// The unit check's findings, once the log has been read to its end (empty before, and
    /// without [`ReaderOptions::natural_frequency`]).
    pub fn unit_findings(&self) -> &[Finding] {
        &self.unit_findings
    }

    /// Takes the warnings queued since the last call, oldest first.
    pub fn drain_warnings(&mut self) -> std::vec::Drain<'_, LogWarning> {
        self.pending.drain(..)
    }

    fn error(
        &mut self,
        line: Option<u64>,
        column: Option<CellRef>,
        kind: LogErrorKind,
    ) -> LogError {
        self.finished = true;
        LogError {
            file: self.file.clone(),
            line,
            column,
            kind: Box::new(kind),
        }
    }

    fn warn(
        &mut self,
        kind: WarningKind,
        column: Option<Column>,
        header: Option<String>,
        message: String,
    ) {
        self.summary.warning_counts[kind.index()] += 1;
        if self.reported[kind.index()] < self.options.max_reported {
            self.reported[kind.index()] += 1;
            self.pending.push(LogWarning {
                file: self.file.clone(),
                line: self.lines.line(),
                column,
                header,
                kind,
                message,
            });
        } else {
            self.summary.warnings_not_listed += 1;
        }
    }

    /// Reads the next line that is neither blank nor a comment ([`CsvLines::next_line`]).
    /// `Ok(false)` at the end of the input.
    fn next_line(&mut self) -> Result<bool, LogError> {
        let more = self.lines.next_line().map_err(|e| {
            let line = Some(self.lines.line() + 1);
            self.error(line, None, LogErrorKind::Io(e))
        })?;
        if let Some((line, n)) = self.lines.take_nul() {
            self.warn(WarningKind::NulBytes, None, None, nul_message(line, n));
        }
        Ok(more)
    }

    fn split(&mut self) -> Result<(), LogError> {
        self.lines.split().map_err(|i| {
            let column = Some(CellRef {
                position: i + 1,
                header: self.header.get(i).cloned().unwrap_or_default(),
            });
            let line = Some(self.lines.line());
            self.error(line, column, LogErrorKind::UnterminatedQuote)
        })
    }

    /// Goes on after an error in one line alone ([`LogError::is_one_line`]: the line was
    /// read and left behind), for a live stream that must survive a glitch; the next
    /// [`Self::next_record`] reads the line after it.
    pub fn resume_after(&mut self, e: &LogError) {
        if e.is_one_line() {
            self.finished = false;
        }
    }

    /// Reads the next data row. `Ok(None)` at the end of the log; after an error the
    /// reader is finished and returns `Ok(None)` (unless [`Self::resume_after`]).
    pub fn next_record(&mut self) -> Result<Option<LogRecord>, LogError> {
        if self.finished {
            return Ok(None);
        }
        if !self.next_line()? {
            if self.summary.rows == 0 {
                let line = Some(self.lines.line().max(1));
                return Err(self.error(line, None, LogErrorKind::NoData));
            }
            // A short log: its few steps are checked at its end.
            self.check_rate()?;
            self.finished = true;
            self.tell_units();
            return Ok(None);
        }
        self.split()?;
        let mut issues = RowIssues::default();
        self.check_field_count(&mut issues)?;
        let parsed = self.parse_used();
        let (values, unchecked) = self.used_cells(&parsed, &mut issues)?;

        self.check_time_base(values[Column::T.index()])?;
        self.check_time(values[Column::T.index()], &mut issues);
        if self.first_dts.len() == NOMINAL_DT_SAMPLES {
            self.check_rate()?;
        }
        self.summary.rows += 1;
        let t = values[Column::T.index()];
        let sample = Sample {
            dt: self.gate.step(t),
            phi: values[Column::Phi.index()],
            gyro: values[Column::Gyro.index()],
            ax: values[Column::Ax.index()],
            ay: values[Column::Ay.index()],
        };
        let theta = self.positions[Column::Theta.index()].map(|_| values[Column::Theta.index()]);
        let unchecked = Sample {
            dt: sample.dt,
            phi: unchecked[Column::Phi.index()],
            gyro: unchecked[Column::Gyro.index()],
            ax: unchecked[Column::Ax.index()],
            ay: unchecked[Column::Ay.index()],
        };
        if let Some(u) = &mut self.units {
            u.add(&unchecked, theta);
        }
        Ok(Some(LogRecord {
            line: self.lines.line(),
            t,
            sample,
            theta,
            issues,
            unchecked,
        }))
    }

    /// The unit check's findings, kept and warned about once, at the end of the log (no
    /// line: they are about the whole log).
    fn tell_units(&mut self) {
        let Some(u) = self.units.take() else {
            return;
        };
        self.unit_findings = u.findings();
        for f in &self.unit_findings {
            self.summary.warning_counts[WarningKind::UnitMismatch.index()] += 1;
            self.pending.push(LogWarning {
                file: self.file.clone(),
                line: 0,
                column: None,
                header: None,
                kind: WarningKind::UnitMismatch,
                message: f.message.clone(),
            });
        }
    }
}

impl<R: BufRead> Iterator for LogReader<R> {
    type Item = Result<LogRecord, LogError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_record().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reader(text: &str) -> LogReader<&[u8]> {
        LogReader::new(text.as_bytes(), "x.csv", ReaderOptions::default()).unwrap()
    }

    #[test]
    fn reads_plain_rows_with_line_numbers() {
        let mut r = reader("t,phi\n0,0.1\n# note\n\n0.001,0.2\n");
        let a = r.next_record().unwrap().unwrap();
        assert_eq!((a.line, a.t, a.sample.phi), (2, 0.0, 0.1));
        assert!(a.sample.gyro.is_nan() && a.theta.is_none());
        let b = r.next_record().unwrap().unwrap();
        assert_eq!((b.line, b.t, b.sample.phi), (5, 0.001, 0.2));
        assert!(r.next_record().unwrap().is_none());
        assert!(r.next_record().unwrap().is_none());
        assert_eq!(r.summary().rows, 2);
    }

    #[test]
    fn nominal_dt_is_a_median() {
        let mut text = String::from("t\n");
        for k in 0..20 {
            text.push_str(&format!("{}\n", k as f64 * 0.01));
        }
        let mut r = reader(&text);
        while r.next_record().unwrap().is_some() {}
        let dt = r.summary().nominal_dt.unwrap();
        assert!((dt - 0.01).abs() < 1e-12, "{dt}");
        assert_eq!(r.summary().count(WarningKind::TimeGap), 0);
    }
}
