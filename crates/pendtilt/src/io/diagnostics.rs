//! What the log reader noticed without stopping: warnings (each with its line) and a
//! summary with counts. The library never prints; the caller drains and shows them.
use std::fmt;

use super::columns::Column;

/// The kinds of warning the log reader gives. Each row that raises one is still returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WarningKind {
    /// A row with fewer fields than the header (for example a truncated last line): the
    /// missing cells read as missing (NaN).
    TruncatedRow,
    /// An empty cell in a used column: read as missing (NaN).
    EmptyCell,
    /// A `nan` or `inf` cell in a used column: read as missing (NaN), the estimators flag it.
    NonFinite,
    /// The time cell is missing or not finite: the estimators flag `bad_time_step`.
    TimeMissing,
    /// Time repeated or went backwards: the estimators flag `bad_time_step`.
    TimeNotIncreasing,
    /// A time step much longer than the nominal one (a gap in the log).
    TimeGap,
    /// A time step that differs from the nominal one by more than the jitter tolerance.
    TimeJitter,
    /// An angle (or rate) column read as radians holds values that look like degrees.
    LooksLikeDegrees,
    /// Two header columns share a name that no contract column uses.
    DuplicateIgnoredColumn,
    /// A reading beyond its sensor's full scale, or physically impossible: read as
    /// missing, the row flagged `implausible`.
    Implausible,
    /// Every estimator reading a sensor was restarted after a long gap in it.
    Restarted,
    /// A column's scale disagrees with the physics (the gyro against the encoder's
    /// derivative, the encoder against the accelerometer): degrees read as radians.
    UnitMismatch,
    /// A run of identical readings well above the sensor's noise: a clip at a full scale
    /// the rig does not give; the readings at its level are flagged `saturated`.
    Clipped,
    /// NUL bytes in the file (a logger's preallocated space, or a write a power loss cut):
    /// removed; a line of them alone is blank, a line they end is cut (`TruncatedRow`).
    NulBytes,
    /// A malformed line of a live stream (`pendtilt stream`): skipped, its output row NaN
    /// and flagged `bad_line`.
    BadLine,
}

impl WarningKind {
    /// Every kind, in a fixed order (the order of [`LogSummary::warning_counts`]).
    pub const ALL: [WarningKind; 15] = [
        WarningKind::TruncatedRow,
        WarningKind::EmptyCell,
        WarningKind::NonFinite,
        WarningKind::TimeMissing,
        WarningKind::TimeNotIncreasing,
        WarningKind::TimeGap,
        WarningKind::TimeJitter,
        WarningKind::LooksLikeDegrees,
        WarningKind::DuplicateIgnoredColumn,
        WarningKind::Implausible,
        WarningKind::Restarted,
        WarningKind::UnitMismatch,
        WarningKind::Clipped,
        WarningKind::NulBytes,
        WarningKind::BadLine,
    ];

    /// A short snake_case name, for summaries.
    pub fn name(self) -> &'static str {
        match self {
            WarningKind::TruncatedRow => "truncated_row",
            WarningKind::EmptyCell => "empty_cell",
            WarningKind::NonFinite => "non_finite",
            WarningKind::TimeMissing => "time_missing",
            WarningKind::TimeNotIncreasing => "time_not_increasing",
            WarningKind::TimeGap => "time_gap",
            WarningKind::TimeJitter => "time_jitter",
            WarningKind::LooksLikeDegrees => "looks_like_degrees",
            WarningKind::DuplicateIgnoredColumn => "duplicate_ignored_column",
            WarningKind::Implausible => "implausible",
            WarningKind::Restarted => "restarted",
            WarningKind::UnitMismatch => "unit_mismatch",
            WarningKind::Clipped => "clipped",
            WarningKind::NulBytes => "nul_bytes",
            WarningKind::BadLine => "bad_line",
        }
    }

    pub(crate) fn index(self) -> usize {
        self as usize
    }
}

/// One warning: where (file, line, column) and what.
#[derive(Debug, Clone, PartialEq)]
pub struct LogWarning {
    /// The file (or origin name) of the log.
    pub file: String,
    /// 1-based line in the file (comment and blank lines counted); 0 for a finding about
    /// the whole log.
    pub line: u64,
    /// The contract column concerned, if any.
    pub column: Option<Column>,
    /// The header name of that column (differs from the contract name under `--map`).
    pub header: Option<String>,
    /// The kind, for counting and tests.
    pub kind: WarningKind,
    /// A sentence saying what was seen and what it means (or what to do).
    pub message: String,
}

impl fmt::Display for LogWarning {
    /// `log.csv:17: column `phi`: ...`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line > 0 {
            write!(f, "{}:{}: ", self.file, self.line)?;
        } else {
            write!(f, "{}: ", self.file)?;
        }
        match (&self.column, &self.header) {
            (Some(c), Some(h)) if h != c.name() => write!(f, "column `{h}` ({c}): ")?,
            (Some(c), _) => write!(f, "column `{c}`: ")?,
            (None, Some(h)) => write!(f, "column `{h}`: ")?,
            (None, None) => {}
        }
        f.write_str(&self.message)
    }
}

/// Running totals over the rows read so far.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LogSummary {
    /// Data rows returned.
    pub rows: u64,
    /// Time of the first row with a finite time \[s\].
    pub first_t: Option<f64>,
    /// Time of the last row with a finite time \[s\].
    pub last_t: Option<f64>,
    /// The nominal time step: the median of the first positive steps \[s\].
    pub nominal_dt: Option<f64>,
    /// The smallest positive time step seen \[s\].
    pub min_dt: Option<f64>,
    /// The largest time step seen \[s\].
    pub max_dt: Option<f64>,
    /// Per contract column ([`Column::ALL`] order): cells read as missing (empty, nan,
    /// inf, or absent from a truncated row).
    pub missing_cells: [u64; 6],
    /// Per [`WarningKind::ALL`] kind: how many times it occurred.
    pub warning_counts: [u64; WarningKind::ALL.len()],
    /// Warnings counted but not queued, because their kind had already been reported
    /// `max_reported` times.
    pub warnings_not_listed: u64,
}

impl LogSummary {
    /// How many times a kind of warning occurred.
    pub fn count(&self, kind: WarningKind) -> u64 {
        self.warning_counts[kind.index()]
    }

    /// Cells of `column` read as missing.
    pub fn missing(&self, column: Column) -> u64 {
        self.missing_cells[column.index()]
    }

    /// Total warnings of every kind.
    pub fn total_warnings(&self) -> u64 {
        self.warning_counts.iter().sum()
    }
}

impl fmt::Display for LogSummary {
    /// `12000 rows, t 0 .. 11.999 s, dt 0.001 s; warnings: time_gap 2, non_finite 5`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} rows", self.rows)?;
        if let (Some(a), Some(b)) = (self.first_t, self.last_t) {
            write!(f, ", t {a} .. {b} s")?;
        }
        if let Some(dt) = self.nominal_dt {
            write!(f, ", dt {dt} s")?;
        }
        let kinds: Vec<String> = WarningKind::ALL
            .into_iter()
            .filter(|k| self.count(*k) > 0)
            .map(|k| format!("{} {}", k.name(), self.count(k)))
            .collect();
        if !kinds.is_empty() {
            write!(f, "; warnings: {}", kinds.join(", "))?;
        }
        Ok(())
    }
}
