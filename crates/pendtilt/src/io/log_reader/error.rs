//! Why a log could not be read, and where: the file, the line and the cell.

/// A cell position for error messages: its 1-based field number and header name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CellRef {
    /// 1-based field number in the row.
    pub position: usize,
    /// The header name of that field.
    pub header: String,
}

/// The command [`decimal_comma_hint`] gives: each quoted field that is a number with a
/// decimal comma, `"-0,5"` or `"1,5e-3"`, becomes `-0.5`, `1.5e-3`; other fields (a quoted
/// header `"t","phi"`, `"0"`) are left as they are, which the reader takes.
pub const DECIMAL_COMMA_FIX: &str = r#"sed -E 's/(^|,)"([-+]?[0-9]*),([0-9]*([eE][-+]?[0-9]+)?)"/\1\2.\3/g' log.csv > log_points.csv"#;

/// What to do about a cell `text` that is a number written with a decimal comma (`0,5`;
/// a comma-separated log can hold one only quoted, `"0,5"`): the sentence to append to
/// the error, with a command that converts the log ([`DECIMAL_COMMA_FIX`]); empty for
/// any other text.
pub fn decimal_comma_hint(text: &str) -> String {
    let t = text.trim();
    let comma_number = t.matches(',').count() == 1 && t.replace(',', ".").parse::<f64>().is_ok();
    if !comma_number {
        return String::new();
    }
    format!(
        ": a number with a decimal comma (quoted, \"{t}\"), and the log must use decimal \
         points: convert it with `{DECIMAL_COMMA_FIX}`"
    )
}

/// Why a log could not be read.
#[derive(Debug, thiserror::Error)]
pub enum LogErrorKind {
    /// The file could not be opened or read.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// No header: the file is empty (or holds only blank and comment lines).
    #[error("the file is empty: no header row")]
    Empty,
    /// A header and no data row.
    #[error("header only, no data rows")]
    NoData,
    /// A line that is not UTF-8 text.
    #[error("not UTF-8 text")]
    InvalidUtf8,
    /// The file starts with a UTF-16 byte-order mark.
    #[error("the file is UTF-16 text; save it as UTF-8 (or ASCII)")]
    Utf16,
    /// A quoted field not closed on its line.
    #[error("a quoted field is not closed on its line")]
    UnterminatedQuote,
    /// No time column.
    #[error("no `t` column (the header has: {header}){hint}")]
    MissingTime {
        /// The header names, comma-separated.
        header: String,
        /// A suggestion: `--map t=...` or another delimiter.
        hint: String,
    },
    /// A used column appears twice in the header.
    #[error("duplicate column: `{name}` is also field {first}; which one is meant is unclear")]
    DuplicateColumn {
        /// The header name.
        name: String,
        /// 1-based field number of its first appearance.
        first: usize,
    },
    /// `--map` names a header column that is not there.
    #[error("--map {column}={source_name}: no column `{source_name}` in the header (the header has: {header})")]
    MappedSourceMissing {
        /// The contract column (planar or 3-D).
        column: String,
        /// The header name asked for.
        source_name: String,
        /// The header names, comma-separated.
        header: String,
    },
    /// A cell that is not a number (nor empty, `nan` or `inf`).
    #[error("not a number: `{text}`{hint}")]
    NotANumber {
        /// The cell text.
        text: String,
        /// What it may be and what to do (`not_a_number_hint`), or empty.
        hint: String,
    },
    /// A data line that is a header (the same or another).
    #[error("{what}: two logs joined, or a logger that restarted into the same file or stream? remove this line, or split the log here")]
    HeaderAgain {
        /// Which header, and the first one's line.
        what: String,
    },
    /// The time went back by more than the restart gap and ran on from there: two logs
    /// joined, or a clock restarted (`log_reader::new_time_base`).
    #[error("{0}")]
    NewTimeBase(String),
    /// The time steps are not those of a sensor log in seconds (a log in ms or us).
    #[error("{0}")]
    ImplausibleTimeStep(String),
    /// A row with more non-empty fields than the header.
    #[error("{found} fields, the header has {expected}")]
    TooManyFields {
        /// Fields in the row.
        found: usize,
        /// Fields in the header.
        expected: usize,
    },
    /// A 3-D header (complete or not) given to the planar reader.
    #[error("{what}; to read its roll axis as a planar log, give --map phi=phi_x,gyro=gyro_x,ax=ay,ay=az,theta=roll (MODEL.md 7.4: planar x, y = 3-D y, z) (the header has: {header})")]
    NotPlanar {
        /// What the header is and what is missing.
        what: String,
        /// The header names, comma-separated.
        header: String,
    },
    /// Required columns of a 3-D log (MODEL.md 7.6) absent from the header.
    #[error("not a 3-D log: no {missing} column (the header has: {header}; a 3-D log needs t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az)")]
    MissingColumns {
        /// The missing names, comma-separated and quoted.
        missing: String,
        /// The header names, comma-separated.
        header: String,
    },
}

/// A log reading error: the file, the line and the column where it is, and why.
///
/// Displays as `log.csv:5: column 3 (`phi`): not a number: `abc``.
#[derive(Debug, thiserror::Error)]
#[error("{file}{}{}: {kind}", line_part(*.line), column_part(.column))]
pub struct LogError {
    /// The file (or origin name).
    pub file: String,
    /// 1-based line, when the error is on a line.
    pub line: Option<u64>,
    /// The cell's field, when the error is in one.
    pub column: Option<CellRef>,
    /// What is wrong (boxed to keep `Result<_, LogError>` small).
    pub kind: Box<LogErrorKind>,
}

impl LogError {
    /// What is wrong, with the cell, without the file and line (for a message that names
    /// them itself): "column 3 (`gyro`): not a number: `abc`".
    pub fn what(&self) -> String {
        match &self.column {
            Some(c) => format!("column {} (`{}`): {}", c.position, c.header, self.kind),
            None => self.kind.to_string(),
        }
    }

    /// Whether the error is in one line alone, which a reader may skip and go on after
    /// (a cell that is no number, a wrong number of fields, an unclosed quote, bytes that
    /// are not UTF-8): what a live feed's glitch looks like. The others (the header, the
    /// time base, the rate, the file itself) concern the whole log.
    pub fn is_one_line(&self) -> bool {
        matches!(
            *self.kind,
            LogErrorKind::NotANumber { .. }
                | LogErrorKind::TooManyFields { .. }
                | LogErrorKind::UnterminatedQuote
                | LogErrorKind::InvalidUtf8
        ) && self.line.is_some()
    }
}

fn line_part(line: Option<u64>) -> String {
    line.map(|l| format!(":{l}")).unwrap_or_default()
}

fn column_part(column: &Option<CellRef>) -> String {
    column
        .as_ref()
        .map(|c| format!(": column {} (`{}`)", c.position, c.header))
        .unwrap_or_default()
}

/// Texts loggers and tools write for a missing reading (compared without case).
const MISSING_MARKERS: [&str; 12] = [
    "na", "n/a", "#n/a", "null", "none", "nil", "-", "--", "?", "missing", "nodata", "n.a.",
];

/// What a cell `text` that is not a number may be, said after the error: a units line
/// under the header (`first_row`: the first data row, `all_text`: none of its cells is a
/// number; `line`, `file` for the command that comments it out), or a marker of a missing
/// reading, or a number with a decimal comma ([`decimal_comma_hint`]). Empty when none.
pub fn not_a_number_hint(
    text: &str,
    first_row: bool,
    all_text: bool,
    line: u64,
    file: &str,
) -> String {
    // A number written with a decimal comma is that, whatever the rest of the row.
    let comma = decimal_comma_hint(text);
    if !comma.is_empty() {
        return comma;
    }
    if first_row && all_text {
        let fix = if file.starts_with('<') {
            String::new()
        } else {
            format!(" (`sed -i '{line}s/^/#/' {file}`)")
        };
        return format!(
            "; the first row under the header is text: a units line? make it a comment \
             with `#`{fix} or delete it"
        );
    }
    if MISSING_MARKERS
        .iter()
        .any(|m| text.trim().eq_ignore_ascii_case(m))
    {
        return format!(
            "; if `{text}` marks a missing reading, leave the cell empty (or write nan): \
             an empty cell reads as missing, and the estimators hold and flag the sample"
        );
    }
    String::new()
}
