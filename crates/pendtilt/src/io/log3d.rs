//! The 3-D sensor log reader (MODEL.md 7.6): t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax,
//! ay, az required; speed, roll, pitch optional; other columns ignored. Reads through the one
//! CSV line reader ([`super::csv_lines`]) with the planar reader's error type and quality: an
//! error names the file, the line and the column (`log.csv:7: column 4 (`gyro_x`): not a
//! number: `abc``); an empty or `nan` cell, or one absent from a short row, reads as NaN and
//! flags its row; a time that does not increase flags its row. Every data row gives a record.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use super::csv_lines::CsvLines;
use super::log_reader::{
    new_time_base, not_a_number_hint, CellRef, LogError, LogErrorKind, TimeBack,
};
use crate::sensors::{Sensor, SENSORS};

/// The columns of a 3-D log after the sensors' (MODEL.md 7.6), all optional: the speed
/// and the truth.
const LOG3D_TAIL: [&str; 3] = ["speed", "roll", "pitch"];

/// How many columns a 3-D log can have: the time, the sensors', [`LOG3D_TAIL`].
const LOG3D_COUNT: usize = {
    let mut n = 1 + LOG3D_TAIL.len();
    let mut i = 0;
    while i < SENSORS.len() {
        n += SENSORS[i].spatial_columns.len();
        i += 1;
    }
    n
};

/// The columns of a 3-D log (MODEL.md 7.6): `t`, then each sensor's of the table
/// ([`SENSORS`], the required ones first), then `speed`, `roll` and `pitch`.
pub const LOG3D_COLUMNS: [&str; LOG3D_COUNT] = {
    let mut all = ["t"; LOG3D_COUNT];
    let mut k = 1;
    let mut i = 0;
    while i < SENSORS.len() {
        let columns = SENSORS[i].spatial_columns;
        let mut j = 0;
        while j < columns.len() {
            all[k] = columns[j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    let mut j = 0;
    while j < LOG3D_TAIL.len() {
        all[k] = LOG3D_TAIL[j];
        k += 1;
        j += 1;
    }
    all
};

/// How many of [`LOG3D_COLUMNS`] (the first ones) a 3-D log must have: the time and the
/// required sensors' (which the table lists first).
pub const LOG3D_REQUIRED: usize = {
    let mut n = 1;
    let mut i = 0;
    while i < SENSORS.len() {
        if SENSORS[i].spatial_required {
            assert!(
                i == 0 || SENSORS[i - 1].spatial_required,
                "required sensors first"
            );
            n += SENSORS[i].spatial_columns.len();
        }
        i += 1;
    }
    n
};

/// True when a header has every required 3-D column (how `estimate` can tell a 3-D log).
pub fn is_3d_header<S: AsRef<str>>(header: &[S]) -> bool {
    LOG3D_COLUMNS[..LOG3D_REQUIRED]
        .iter()
        .all(|c| header.iter().any(|h| h.as_ref() == *c))
}

/// What was wrong with a row (its values are still given).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Row3dIssues {
    /// A required cell was empty, `nan`, infinite or absent (read as NaN).
    pub missing: bool,
    /// t is not greater than the previous row's.
    pub time_not_increasing: bool,
}

/// One data row of a 3-D log, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Log3dRecord {
    /// 1-based line in the file (comment and blank lines counted).
    pub line: u64,
    /// t \[s\].
    pub t: f64,
    /// Encoders (phi_x, phi_y) \[rad\].
    pub phi: [f64; 2],
    /// Gyro, body axes \[rad/s\].
    pub gyro: [f64; 3],
    /// Accelerometer, body axes \[m/s^2\].
    pub accel: [f64; 3],
    /// Forward speed \[m/s\]: `None` when the log has no `speed` column.
    pub speed: Option<f64>,
    /// True roll \[rad\]: `None` when the log has no `roll` column.
    pub roll: Option<f64>,
    /// True pitch \[rad\]: `None` when the log has no `pitch` column.
    pub pitch: Option<f64>,
    /// What was wrong with the row.
    pub issues: Row3dIssues,
}

impl Log3dRecord {
    /// The readings of `sensor`, one per axis (its columns' order in the table).
    pub fn reading(&self, sensor: Sensor) -> &[f64] {
        match sensor {
            Sensor::Encoder => &self.phi,
            Sensor::Gyro => &self.gyro,
            Sensor::Accel => &self.accel,
        }
    }

    fn reading_mut(&mut self, sensor: Sensor) -> &mut [f64] {
        match sensor {
            Sensor::Encoder => &mut self.phi,
            Sensor::Gyro => &mut self.gyro,
            Sensor::Accel => &mut self.accel,
        }
    }
}

/// Streaming 3-D log reader over any [`BufRead`]; after an error it is finished.
#[derive(Debug)]
pub struct Log3dReader<R> {
    lines: CsvLines<R>,
    file: String,
    header: Vec<String>,
    /// Field position of each of [`LOG3D_COLUMNS`].
    positions: [Option<usize>; LOG3D_COUNT],
    last_t: Option<f64>,
    /// The latest time so far (the one the estimators' step gates hold).
    max_t: Option<f64>,
    /// The previous row's time went back by more than the restart gap.
    went_back: Option<TimeBack>,
    /// The header's line.
    header_line: u64,
    rows: u64,
    finished: bool,
}

impl Log3dReader<BufReader<File>> {
    /// Opens a log file; errors name it as given.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, LogError> {
        let path = path.as_ref();
        Self::open_as(path, &path.display().to_string(), &[])
    }

    /// Opens the log file at `path`; errors name it `name` (the path the user gave, or
    /// `<stdin>`: [`super::input::InputLog`]).
    /// `renames`: `--map`'s 3-D entries ([`Self::new_mapped`]).
    pub fn open_as(
        path: &Path,
        name: &str,
        renames: &[(String, String)],
    ) -> Result<Self, LogError> {
        let file = File::open(path).map_err(|e| LogError {
            file: name.to_string(),
            line: None,
            column: None,
            kind: Box::new(LogErrorKind::Io(e)),
        })?;
        Self::new_mapped(BufReader::with_capacity(1 << 16, file), name, renames)
    }
}

/// Reads a whole 3-D log file.
pub fn read_log3d(path: impl AsRef<Path>) -> Result<Vec<Log3dRecord>, LogError> {
    Log3dReader::open(path)?.collect()
}

impl<R: BufRead> Log3dReader<R> {
    /// Reads the header from `input`; `origin` names the source in messages.
    pub fn new(input: R, origin: &str) -> Result<Self, LogError> {
        Self::new_mapped(input, origin, &[])
    }

    /// [`Self::new`] with the header's columns `(column, source)` renamed (`--map`): the
    /// header field `source` is read as the 3-D column `column`; a source the header does
    /// not have is an error.
    pub fn new_mapped(
        input: R,
        origin: &str,
        renames: &[(String, String)],
    ) -> Result<Self, LogError> {
        let mut r = Self {
            lines: CsvLines::new(input, b','),
            file: origin.to_string(),
            header: Vec::new(),
            positions: [None; LOG3D_COUNT],
            last_t: None,
            max_t: None,
            went_back: None,
            header_line: 1,
            rows: 0,
            finished: false,
        };
        r.read_header(renames)?;
        Ok(r)
    }

    /// The header names, in file order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// The header's 1-based line in the file (comment lines may come before it).
    pub fn header_line(&self) -> u64 {
        self.header_line
    }

    /// NUL bytes removed from the lines so far (`csv_lines`): the line of the first and
    /// the count, for a warning ([`super::nul_message`]).
    pub fn take_nul(&mut self) -> Option<(u64, u64)> {
        self.lines.take_nul()
    }

    /// Whether the log has the column `name` (one of [`LOG3D_COLUMNS`]).
    pub fn has(&self, name: &str) -> bool {
        LOG3D_COLUMNS
            .iter()
            .position(|c| *c == name)
            .is_some_and(|i| self.positions[i].is_some())
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

    fn read_row(&mut self) -> Result<bool, LogError> {
        match self.lines.next_row() {
            Ok(Some(())) => Ok(true),
            Ok(None) => Ok(false),
            Err(super::csv_lines::RowError::Io(e)) => {
                let line = Some(self.lines.line() + 1);
                Err(self.error(line, None, LogErrorKind::Io(e)))
            }
            Err(super::csv_lines::RowError::UnterminatedQuote(i)) => {
                let column = Some(self.cell_ref(i));
                let line = Some(self.lines.line());
                Err(self.error(line, column, LogErrorKind::UnterminatedQuote))
            }
        }
    }

    fn cell_ref(&self, i: usize) -> CellRef {
        CellRef {
            position: i + 1,
            header: self.header.get(i).cloned().unwrap_or_default(),
        }
    }

    /// The header: names, each column's position, the required ones present, no used name
    /// twice.
    fn read_header(&mut self, renames: &[(String, String)]) -> Result<(), LogError> {
        if !self.read_row()? {
            return Err(self.error(None, None, LogErrorKind::Empty));
        }
        let line = Some(self.lines.line());
        self.header_line = self.lines.line();
        let mut header = Vec::with_capacity(self.lines.field_count());
        for i in 0..self.lines.field_count() {
            let Some(name) = self
                .lines
                .field(i)
                .and_then(|f| String::from_utf8(f.into_owned()).ok())
            else {
                return Err(self.error(line, None, LogErrorKind::InvalidUtf8));
            };
            header.push(name);
        }
        for (column, source) in renames {
            let Some(i) = header.iter().position(|h| h == source) else {
                let kind = LogErrorKind::MappedSourceMissing {
                    column: column.clone(),
                    source_name: source.clone(),
                    header: header.join(", "),
                };
                return Err(self.error(line, None, kind));
            };
            header[i] = column.clone();
        }
        self.header = header;
        for (k, name) in LOG3D_COLUMNS.iter().enumerate() {
            let mut found = self.header.iter().enumerate().filter(|(_, h)| h == name);
            self.positions[k] = found.next().map(|(i, _)| i);
            if let (Some(first), Some((dup, _))) = (self.positions[k], found.next()) {
                let column = Some(self.cell_ref(dup));
                let kind = LogErrorKind::DuplicateColumn {
                    name: name.to_string(),
                    first: first + 1,
                };
                return Err(self.error(line, column, kind));
            }
        }
        let missing: Vec<String> = (0..LOG3D_REQUIRED)
            .filter(|&k| self.positions[k].is_none())
            .map(|k| format!("`{}`", LOG3D_COLUMNS[k]))
            .collect();
        if !missing.is_empty() {
            let required = &LOG3D_COLUMNS[..LOG3D_REQUIRED];
            let units =
                super::unit_named_3d_hint(required, &self.header, &self.file, self.header_line)
                    .map(|h| format!("; {h}"))
                    .unwrap_or_default();
            let kind = LogErrorKind::MissingColumns {
                missing: missing.join(", "),
                header: format!("{}{units}", self.header.join(", ")),
            };
            return Err(self.error(line, None, kind));
        }
        Ok(())
    }

    /// Column `k`'s value on the current row: NaN when empty, non-finite or absent; an error
    /// when it is not a number.
    fn value(&mut self, k: usize, missing: &mut bool) -> Result<f64, LogError> {
        let Some(pos) = self.positions[k] else {
            return Ok(f64::NAN);
        };
        let Some(raw) = self.lines.field(pos) else {
            *missing = true;
            return Ok(f64::NAN);
        };
        if raw.is_empty() {
            *missing = true;
            return Ok(f64::NAN);
        }
        match std::str::from_utf8(&raw)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
        {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => {
                *missing = true;
                Ok(f64::NAN)
            }
            None => {
                let text = String::from_utf8_lossy(&raw).into_owned();
                let line = self.lines.line();
                let column = Some(self.cell_ref(pos));
                let (first, all_text) = (self.rows == 0, self.lines.all_text());
                let hint = not_a_number_hint(&text, first, all_text, line, &self.file);
                let kind = LogErrorKind::NotANumber { text, hint };
                Err(self.error(Some(line), column, kind))
            }
        }
    }

    /// An error when the previous row's time went back by more than the restart gap and
    /// this one (`t`, finite) runs on from it; notes a step back at this row.
    fn check_time_base(&mut self, t: f64) -> Result<(), LogError> {
        if let Some(back) = self.went_back.take() {
            if back.runs_on(t) {
                let msg = new_time_base(&back, t, &self.file, self.header_line);
                let (line, column) = (Some(self.lines.line()), self.positions[0]);
                let column = column.map(|p| self.cell_ref(p));
                return Err(self.error(line, column, LogErrorKind::NewTimeBase(msg)));
            }
        }
        self.went_back = TimeBack::of(self.lines.line(), self.max_t, t);
        Ok(())
    }

    /// After an error on one line ([`LogError::is_one_line`]: a cell that is no number,
    /// the wrong number of fields, an unclosed quote), reading goes on from the next line,
    /// for a live stream that must not stop on one glitch. After any other error the
    /// reader stays finished.
    pub fn resume_after(&mut self, e: &LogError) {
        if e.is_one_line() {
            self.finished = false;
        }
    }

    /// Reads the next data row; `Ok(None)` at the end (an error if there was no data row).
    /// After an error the reader is finished (unless [`Self::resume_after`]).
    pub fn next_record(&mut self) -> Result<Option<Log3dRecord>, LogError> {
        if self.finished {
            return Ok(None);
        }
        if !self.read_row()? {
            self.finished = true;
            if self.rows == 0 {
                let line = Some(self.lines.line().max(1));
                return Err(self.error(line, None, LogErrorKind::NoData));
            }
            return Ok(None);
        }
        let (found, expected) = (self.lines.field_count(), self.header.len());
        if found > expected
            && (expected..found).any(|i| self.lines.raw(i).is_some_and(|f| !f.is_empty()))
        {
            let line = Some(self.lines.line());
            return Err(self.error(line, None, LogErrorKind::TooManyFields { found, expected }));
        }
        // A short row the input's end cut: its last cell may be cut short too (`-0.02` of
        // `-0.0215`), so it reads as absent (NaN, the row flagged) like the cells after it.
        if found < expected && !self.lines.terminated() {
            self.lines.drop_last_field();
        }
        let mut missing = false;
        let mut v = [f64::NAN; LOG3D_COUNT];
        for (k, x) in v.iter_mut().enumerate() {
            let mut m = false;
            *x = self.value(k, &mut m)?;
            missing |= m && k < LOG3D_REQUIRED;
        }
        let time_not_increasing = self.last_t.is_some_and(|p| v[0] <= p || v[0].is_nan());
        if v[0].is_finite() {
            self.check_time_base(v[0])?;
            self.last_t = Some(v[0]);
            self.max_t = Some(self.max_t.map_or(v[0], |m| m.max(v[0])));
        }
        self.rows += 1;
        let optional = |k: usize| self.positions[k].map(|_| v[k]);
        let tail = LOG3D_COUNT - LOG3D_TAIL.len();
        let mut record = Log3dRecord {
            line: self.lines.line(),
            t: v[0],
            phi: [f64::NAN; 2],
            gyro: [f64::NAN; 3],
            accel: [f64::NAN; 3],
            speed: optional(tail),
            roll: optional(tail + 1),
            pitch: optional(tail + 2),
            issues: Row3dIssues {
                missing,
                time_not_increasing,
            },
        };
        let mut k = 1;
        for sensor in Sensor::ALL {
            for x in record.reading_mut(sensor) {
                *x = v[k];
                k += 1;
            }
        }
        Ok(Some(record))
    }
}

impl<R: BufRead> Iterator for Log3dReader<R> {
    type Item = Result<Log3dRecord, LogError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_record().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az";

    fn read(text: &str) -> Result<Vec<Log3dRecord>, LogError> {
        Log3dReader::new(text.as_bytes(), "log.csv")?.collect()
    }

    /// The table gives MODEL.md 7.6's columns, in its order.
    #[test]
    fn the_columns_are_the_contracts() {
        let contract = [
            "t", "phi_x", "phi_y", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az", "speed", "roll",
            "pitch",
        ];
        assert_eq!(LOG3D_COLUMNS, contract);
        assert_eq!(LOG3D_REQUIRED, 9);
    }

    #[test]
    fn reads_required_and_optional_columns() {
        let text = format!(
            "{HEAD},roll,extra\n0,1,2,3,4,5,6,7,8,0.5,x\n# c\n0.001,1,2,3,4,5,6,7,9.5,,y\n"
        );
        let r = read(&text).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].accel, [6.0, 7.0, 8.0]);
        assert_eq!((r[0].roll, r[0].speed, r[0].pitch), (Some(0.5), None, None));
        assert_eq!(r[1].line, 4);
        assert!(r[1].roll.unwrap().is_nan());
        assert!(!r[1].issues.missing, "roll is optional");
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let text = format!("{HEAD}\n0,1,2,3,4,5,6,7,8\n0.001,1,2,abc,4,5,6,7,8\n");
        let e = read(&text).unwrap_err().to_string();
        assert_eq!(e, "log.csv:3: column 4 (`gyro_x`): not a number: `abc`");
        let e = read("t,phi_x,gyro_x\n0,1,2\n").unwrap_err().to_string();
        assert!(
            e.starts_with("log.csv:1: not a 3-D log: no `phi_y`, `gyro_y`"),
            "{e}"
        );
        let e = read(&format!("{HEAD},ax\n")).unwrap_err().to_string();
        assert!(
            e.contains("column 10 (`ax`): duplicate column: `ax` is also field 7"),
            "{e}"
        );
        let e = read(&format!("{HEAD}\n")).unwrap_err().to_string();
        assert_eq!(e, "log.csv:1: header only, no data rows");
        let e = read(&format!("{HEAD}\n0,1,2,3,4,5,6,7,8,9\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(e, "log.csv:2: 10 fields, the header has 9");
    }

    #[test]
    fn missing_cells_and_time_flag_their_row() {
        let text = format!("{HEAD}\n0,1,2,3,4,5,6,7,8\n0,1,,3,4,5,6,7,nan\n-1,1,2,3\n");
        let r = read(&text).unwrap();
        assert_eq!(r.len(), 3);
        assert!(!r[0].issues.missing && !r[0].issues.time_not_increasing);
        assert!(r[1].issues.missing && r[1].issues.time_not_increasing);
        assert!(r[1].phi[1].is_nan() && r[1].accel[2].is_nan());
        assert!(r[2].issues.missing && r[2].accel[0].is_nan());
        assert!(is_3d_header(&HEAD.split(',').collect::<Vec<_>>()));
        assert!(!is_3d_header(&["t", "phi", "gyro", "ax", "ay"]));
    }
}
