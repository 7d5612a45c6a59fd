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
use super::plausibility::{
    implausible_given_unit, implausible_step, AccelUnit, SensorLimits, TimeUnit,
};
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
            limits: rig.limits(),
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

mod error;
mod header;
pub use error::{
    decimal_comma_hint, not_a_number_hint, CellRef, LogError, LogErrorKind, DECIMAL_COMMA_FIX,
};

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
    /// The previous row's time went back by more than [`TIME_BASE_JUMP`].
    went_back: Option<TimeBack>,
    /// The unit check ([`ReaderOptions::natural_frequency`]) and, at the end, its findings.
    units: Option<UnitCheck>,
    unit_findings: Vec<Finding>,
    finished: bool,
}

/// The error for a time column whose stamps repeat more often than they step: `zero`
/// zero steps and `positive` steps of `dt` \[s\] (0 when none).
fn rounded_time(zero: u64, positive: u64, dt: f64) -> String {
    if positive == 0 {
        return format!(
            "the time never increases ({} rows at one stamp): is `t` the time column \
             (--map t=NAME)?",
            zero + 1
        );
    }
    let run = (zero + positive) as f64 / positive as f64;
    let step = super::plausibility::fmt_sig(dt);
    format!(
        "{zero} of the first {} time steps are zero: each stamp repeats for about {:.0} rows \
         and then steps by {step} s, at about {} rows per second: the time was written \
         rounded (to {step} s) or rows share a stamp; write `t` with more digits, one time \
         per row",
        zero + positive,
        run,
        super::plausibility::fmt_sig(run / dt)
    )
}

/// A time that goes back by more than this \[s\] (the bank's restart gap) and runs on from
/// there is a new time base, an error ([`new_time_base`]); a shorter step back holds the
/// estimators for as long, flagged, as before.
pub const TIME_BASE_JUMP: f64 = crate::sensors::RESTART_GAP;

/// Where the time went back by more than [`TIME_BASE_JUMP`]: the line and the times
/// before and at it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeBack {
    /// The line whose time went back.
    pub line: u64,
    /// The last time before it that the estimators took \[s\].
    pub from: f64,
    /// Its time \[s\].
    pub to: f64,
}

impl TimeBack {
    /// The step back at `line` from `from` to `to`, when it is longer than
    /// [`TIME_BASE_JUMP`].
    pub fn of(line: u64, from: Option<f64>, to: f64) -> Option<Self> {
        let from = from?;
        (from - to > TIME_BASE_JUMP).then_some(Self { line, from, to })
    }

    /// True when `t`, on the row after, runs on from this new time (after it, and still
    /// before `from`, so the estimators would hold until the old time came back).
    pub fn runs_on(&self, t: f64) -> bool {
        t > self.to && t <= self.from
    }
}

/// What to say when the time went back (`back`) and the row at `t` runs on from there:
/// the estimators, which refuse a time before the last one they took, would hold the rest
/// of the log (every row flagged `bad_time_step`, scored as held) until the old time came
/// back. `file` and `header_line` give the commands that split the log.
pub fn new_time_base(back: &TimeBack, t: f64, file: &str, header_line: u64) -> String {
    let n = back.line;
    let split = if file.starts_with('<') {
        String::new()
    } else {
        format!(
            ": `head -n {} {file} > first.csv; (sed -n {header_line}p {file}; tail -n +{n} \
             {file}) > second.csv`",
            n - 1
        )
    };
    format!(
        "the time went back on line {n} ({} then {} s) and runs on from there ({t} s here): \
         two logs joined, or a logger whose clock restarted? The estimators would hold the \
         estimate of the row before line {n} until the time passed {} s again; split the \
         log at line {n}{split}",
        back.from, back.to, back.from,
    )
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

/// Positive time steps used for the nominal step (their median).
const NOMINAL_DT_SAMPLES: usize = 15;

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
        let inputs = Inputs {
            phi: has(Column::Phi),
            gyro: has(Column::Gyro),
            accel: has(Column::Ax) && has(Column::Ay),
        };
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

    /// A row with more (non-empty) fields than the header is an error; one with fewer is
    /// read with the absent cells missing, and a warning.
    #[inline]
    fn check_field_count(&mut self, issues: &mut RowIssues) -> Result<(), LogError> {
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
    fn parse_used(&self) -> [Option<f64>; 6] {
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
    fn used_cells(
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
    fn header_again(&self) -> Option<String> {
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
    fn cell(
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
            self.summary.missing_cells[column.index()] += 1;
            issues.missing_values = true;
            let h = self.header[pos].clone();
            self.warn(
                WarningKind::EmptyCell,
                Some(column),
                Some(h),
                "empty cell: read as missing".to_string(),
            );
            return Ok(f64::NAN);
        }
        let Some(raw) = parsed else {
            if let Some(what) = self.header_again() {
                let line = Some(self.lines.line());
                return Err(self.error(line, None, LogErrorKind::HeaderAgain { what }));
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
            return Err(self.error(Some(line), Some(cell), kind));
        };
        if !raw.is_finite() {
            self.summary.missing_cells[column.index()] += 1;
            issues.missing_values = true;
            let h = self.header[pos].clone();
            self.warn(
                WarningKind::NonFinite,
                Some(column),
                Some(h),
                format!(
                    "{}: read as missing, the estimators hold and flag this sample",
                    {
                        // `1e400` parses to inf: quote what was written, not `inf`.
                        let text = String::from_utf8_lossy(&self.lines.bytes()[a..b]);
                        let word = text
                            .trim()
                            .trim_start_matches(['+', '-'])
                            .to_ascii_lowercase();
                        // ... and `nan` as `nan`, not `NaN`.
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
                ),
            );
            return Ok(f64::NAN);
        }
        let value = raw * self.scale[column.index()];
        if let Some(reason) = self.options.limits.check(column, value, raw) {
            self.summary.missing_cells[column.index()] += 1;
            issues.missing_values = true;
            issues.implausible[column.index()] = true;
            let h = self.header[pos].clone();
            self.warn(WarningKind::Implausible, Some(column), Some(h), reason);
            return Ok(f64::NAN);
        }
        if self.scale[column.index()].abs() == 1.0 && !self.degree_warned[column.index()] {
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
        Ok(value)
    }

    /// Once the nominal step is known (or at the end of a short log): an error when no
    /// sensor rate explains it, unless `--time-unit` was given.
    fn check_rate(&mut self) -> Result<(), LogError> {
        if self.rate_checked {
            return Ok(());
        }
        let positive = self.first_dts.len() as u64;
        // More repeated stamps than steps: the time is rounded (`%.1f` at 1 kHz repeats
        // each stamp 100 times) or rows share a stamp, whatever its unit. Its steps are
        // those of the rounding, which the rate check would take for a unit (1 s: "in ms?").
        let found = if self.zero_steps > positive && self.zero_steps >= 2 {
            Some(rounded_time(
                self.zero_steps,
                positive,
                self.summary.nominal_dt.unwrap_or(0.0),
            ))
        } else if let Some(u) = self.options.time_unit {
            // A unit given is judged as one found: nominal_dt is in seconds already.
            self.summary
                .nominal_dt
                .and_then(|dt| implausible_given_unit(dt / u.seconds(), u))
        } else {
            let Some(dt) = self.summary.nominal_dt else {
                return Ok(());
            };
            implausible_step(dt)
        };
        self.rate_checked = positive > 0 || found.is_some();
        match found {
            None => Ok(()),
            Some(msg) => {
                let line = Some(self.lines.line());
                let h = self.header[self.positions[Column::T.index()].unwrap_or(0)].clone();
                let cell = CellRef {
                    position: self.positions[Column::T.index()].unwrap_or(0) + 1,
                    header: h,
                };
                Err(self.error(line, Some(cell), LogErrorKind::ImplausibleTimeStep(msg)))
            }
        }
    }

    /// An error when the previous row's time went back by more than [`TIME_BASE_JUMP`]
    /// and this one runs on from it ([`new_time_base`]); notes a step back at this row.
    fn check_time_base(&mut self, t: f64) -> Result<(), LogError> {
        if t.is_nan() {
            return Ok(());
        }
        if let Some(back) = self.went_back.take() {
            if back.runs_on(t) {
                let msg = new_time_base(&back, t, &self.file, self.header_line);
                let pos = self.positions[Column::T.index()].unwrap_or(0);
                let cell = CellRef {
                    position: pos + 1,
                    header: self.header[pos].clone(),
                };
                let line = Some(self.lines.line());
                return Err(self.error(line, Some(cell), LogErrorKind::NewTimeBase(msg)));
            }
        }
        self.went_back = TimeBack::of(self.lines.line(), self.gate.last(), t);
        Ok(())
    }

    fn check_time(&mut self, t: f64, issues: &mut RowIssues) {
        if t.is_nan() {
            issues.bad_time = true;
            let h = self.header[self.positions[Column::T.index()].unwrap_or(0)].clone();
            self.warn(
                WarningKind::TimeMissing,
                Some(Column::T),
                Some(h),
                "no time: the sample is kept and the estimators flag bad_time_step".to_string(),
            );
            return;
        }
        if self.summary.first_t.is_none() {
            self.summary.first_t = Some(t);
        }
        self.summary.last_t = Some(t);
        let Some(prev) = self.last_t.replace(t) else {
            return;
        };
        let dt = t - prev;
        if dt <= 0.0 {
            issues.bad_time = true;
            if dt == 0.0 && !self.rate_checked {
                self.zero_steps += 1;
            }
            let what = if dt == 0.0 { "repeated" } else { "goes back" };
            // The gate holds the latest time taken: every row until the time passes it
            // again is held, not only this one.
            let held = match self.gate.last() {
                Some(last) if dt < 0.0 => format!(
                    "this sample and every one until the time passes {last} s again are kept, \
                     the estimators holding their estimate, flagged bad_time_step"
                ),
                _ => "the sample is kept and the estimators flag bad_time_step".to_string(),
            };
            self.warn(
                WarningKind::TimeNotIncreasing,
                Some(Column::T),
                None,
                format!("time {what} ({prev} then {t}): {held}"),
            );
            return;
        }
        self.summary.max_dt = Some(self.summary.max_dt.map_or(dt, |m| m.max(dt)));
        self.summary.min_dt = Some(self.summary.min_dt.map_or(dt, |m| m.min(dt)));
        if self.first_dts.len() < NOMINAL_DT_SAMPLES {
            self.first_dts.push(dt);
            if self.first_dts.len() >= 3 {
                let mut sorted = self.first_dts.clone();
                sorted.sort_by(f64::total_cmp);
                self.summary.nominal_dt = Some(sorted[sorted.len() / 2]);
            }
        }
        let Some(nominal) = self.summary.nominal_dt else {
            return;
        };
        if dt > self.options.gap_factor * nominal {
            issues.time_gap = true;
            self.warn(
                WarningKind::TimeGap,
                Some(Column::T),
                None,
                format!(
                    "gap in time: {prev} to {t} s, {:.1} times the nominal step {} s",
                    dt / nominal,
                    seconds(nominal)
                ),
            );
        } else if (dt - nominal).abs() > self.options.jitter_tolerance * nominal {
            self.warn(
                WarningKind::TimeJitter,
                Some(Column::T),
                None,
                format!(
                    "time step {} s against a nominal {} s (jitter)",
                    seconds(dt),
                    seconds(nominal)
                ),
            );
        }
    }
}

/// A time step \[s\] as a reader writes it: to the nanosecond, without the rounding noise
/// of a difference of two stamps (`0.0010000000000000009` is `0.001`).
fn seconds(x: f64) -> String {
    format!("{}", (x * 1e9).round() / 1e9)
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
