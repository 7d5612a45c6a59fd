//! An IMU recording from a CSV file: its header mapped to [`IMU_COLUMNS`], one sample a row.
use std::io::BufRead;

use super::{
    roll_pitch_of_quaternion, ImuOptions, Recording, SourceError, IMU_COLUMNS, IMU_REQUIRED,
};
use crate::io::csv_lines::{CsvLines, RowError};

/// The CSV being read: its lines, its name and its header.
struct CsvSource<'a, R> {
    lines: CsvLines<R>,
    origin: &'a str,
    header: Vec<String>,
    header_line: u64,
}

impl Recording {
    /// An IMU CSV: a header row with [`IMU_COLUMNS`]' names (or mapped ones), one row per
    /// sample. An empty or `nan` cell reads as NaN (replay interpolates across it and keeps
    /// the row); a cell that is not a number, a row with too many fields or a time that does
    /// not increase is an error naming the line and the column.
    pub fn from_csv<R: BufRead>(
        input: R,
        origin: &str,
        options: &ImuOptions,
    ) -> Result<Self, SourceError> {
        let mut src = CsvSource {
            lines: CsvLines::new(input, b','),
            origin,
            header: Vec::new(),
            header_line: 0,
        };
        if !src.next()? {
            return Err(src.err(None, None, "empty: no header".into()));
        }
        src.header_line = src.lines.line();
        src.header = (0..src.lines.field_count())
            .map(|i| {
                (src.lines.field(i))
                    .map(|f| String::from_utf8_lossy(&f).trim().to_string())
                    .unwrap_or_default()
            })
            .collect();
        let pos = src.positions(options)?;
        let has_angles = pos[7].is_some() && pos[8].is_some();
        let has_quat = pos[9..13].iter().all(Option::is_some);
        let mut rec = Recording {
            origin: origin.to_string(),
            truth: (has_angles || has_quat).then(Vec::new),
            ..Recording::default()
        };
        let deg = std::f64::consts::PI / 180.0;
        while src.next()? {
            let line = src.lines.line();
            let v = src.values(&pos, line)?;
            let t = src.time(&rec, &pos, v[0] * options.time_scale, line)?;
            let g = if options.gyro_deg { deg } else { 1.0 };
            rec.t.push(t);
            rec.gyro.push([v[1] * g, v[2] * g, v[3] * g]);
            let s = options.accel_scale;
            rec.accel.push([v[4] * s, v[5] * s, v[6] * s]);
            rec.lines.push(line);
            if let Some(truth) = rec.truth.as_mut() {
                let a = if options.angles_deg { deg } else { 1.0 };
                truth.push(if has_angles {
                    [v[7] * a, v[8] * a]
                } else {
                    roll_pitch_of_quaternion([v[9], v[10], v[11], v[12]])
                });
            }
        }
        if rec.t.is_empty() {
            let line = Some(src.header_line);
            return Err(src.err(line, None, "header only, no data rows".into()));
        }
        Ok(rec)
    }
}

impl<R: BufRead> CsvSource<'_, R> {
    /// The error at `line` and `column` (1-based position and name).
    fn err(
        &self,
        line: Option<u64>,
        column: Option<(usize, String)>,
        message: String,
    ) -> SourceError {
        SourceError {
            file: self.origin.to_string(),
            line,
            column,
            message,
        }
    }

    /// Reads the next row; false at the end.
    fn next(&mut self) -> Result<bool, SourceError> {
        match self.lines.next_row() {
            Ok(r) => Ok(r.is_some()),
            Err(RowError::Io(e)) => Err(self.err(
                Some(self.lines.line() + 1),
                None,
                format!("cannot read: {e}"),
            )),
            Err(RowError::UnterminatedQuote(i)) => Err(self.err(
                Some(self.lines.line()),
                Some((i + 1, String::new())),
                "unterminated quote".into(),
            )),
        }
    }

    /// The field of each of [`IMU_COLUMNS`] under `options.map`; an error for a mapping to
    /// no column and for a required column missing.
    fn positions(&self, options: &ImuOptions) -> Result<[Option<usize>; 13], SourceError> {
        let header = &self.header;
        for (name, _) in &options.map {
            if !IMU_COLUMNS.contains(&name.as_str()) {
                return Err(self.err(
                    None,
                    None,
                    format!(
                        "--map {name}=...: `{name}` is not an IMU column (they are: {})",
                        IMU_COLUMNS.join(", ")
                    ),
                ));
            }
        }
        let mut pos = [None; 13];
        for (k, name) in IMU_COLUMNS.iter().enumerate() {
            let source = options
                .map
                .iter()
                .find(|(n, _)| n == name)
                .map_or(*name, |(_, s)| s.as_str());
            pos[k] = header.iter().position(|h| h == source);
            if pos[k].is_none() && source != *name {
                return Err(self.err(
                    Some(self.header_line),
                    None,
                    format!(
                        "--map {name}={source}: no column `{source}` in the header (it has: {})",
                        header.join(", ")
                    ),
                ));
            }
        }
        let missing: Vec<&str> = (0..IMU_REQUIRED)
            .filter(|&k| pos[k].is_none())
            .map(|k| IMU_COLUMNS[k])
            .collect();
        if !missing.is_empty() {
            return Err(self.err(
                Some(self.header_line),
                None,
                format!(
                    "no {} column (the header has: {}); an IMU recording needs t, gyro_x, gyro_y, gyro_z, ax, ay, az, and may have roll, pitch or qw, qx, qy, qz; other names: --map gyro_x=gx,...",
                    missing.iter().map(|m| format!("`{m}`")).collect::<Vec<_>>().join(", "),
                    header.join(", ")
                ),
            ));
        }
        Ok(pos)
    }

    /// The row's cells at `pos` as numbers (NaN where empty or not finite); an error for
    /// too many fields or a cell that is not a number.
    fn values(&self, pos: &[Option<usize>; 13], line: u64) -> Result<[f64; 13], SourceError> {
        let lines = &self.lines;
        let (found, expected) = (lines.field_count(), self.header.len());
        if found > expected
            && (expected..found).any(|i| lines.raw(i).is_some_and(|f| !f.is_empty()))
        {
            return Err(self.err(
                Some(line),
                None,
                format!("{found} fields, the header has {expected}"),
            ));
        }
        let mut v = [f64::NAN; 13];
        for (k, p) in pos.iter().enumerate() {
            let Some(p) = *p else { continue };
            let Some(raw) = lines.field(p) else { continue };
            let text = String::from_utf8_lossy(&raw).trim().to_string();
            if text.is_empty() {
                continue;
            }
            match text.parse::<f64>() {
                Ok(x) => v[k] = if x.is_finite() { x } else { f64::NAN },
                Err(_) => {
                    return Err(self.err(
                        Some(line),
                        Some((p + 1, self.header[p].clone())),
                        format!("not a number: `{text}`"),
                    ));
                }
            }
        }
        Ok(v)
    }

    /// The row's time `t` \[s\]; an error when it is missing or does not increase.
    fn time(
        &self,
        rec: &Recording,
        pos: &[Option<usize>; 13],
        t: f64,
        line: u64,
    ) -> Result<f64, SourceError> {
        let column = || pos[0].map(|p| (p + 1, self.header[p].clone()));
        if !t.is_finite() {
            return Err(self.err(
                Some(line),
                column(),
                "no time: a replay needs every row's `t`".into(),
            ));
        }
        if let Some(&prev) = rec.t.last() {
            if t <= prev {
                return Err(self.err(
                    Some(line),
                    column(),
                    format!("t = {t} s does not increase (the row before has {prev} s): a replay needs a time that increases"),
                ));
            }
        }
        Ok(t)
    }
}
