//! A recorded IMU to replay (MODEL.md 7.10): time, gyro and specific force at the IMU, body
//! axes (FLU), and the truth when the recording has one, as roll and pitch or as a
//! quaternion (world <- body).
//!
//! Two sources: an IMU CSV (the user's own recording; columns by name, other names mapped,
//! units given), and a BROAD trial file (MATLAB v5, as in the dataset's repository:
//! `imu_gyr`, `imu_acc`, `opt_quat`, `sampling_rate`, `movement`).
use std::fmt;
use std::io::BufRead;
use std::path::Path;

use crate::io::csv_lines::{CsvLines, RowError};
use crate::io::mat::MatFile;

/// A recording: one entry per row, SI units, body axes at the IMU (P1).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Recording {
    /// Where it came from, for messages.
    pub origin: String,
    /// t \[s\], strictly increasing.
    pub t: Vec<f64>,
    /// Gyro \[rad/s\] (NaN where a cell was missing).
    pub gyro: Vec<[f64; 3]>,
    /// Specific force \[m/s^2\] (NaN where a cell was missing).
    pub accel: Vec<[f64; 3]>,
    /// True ZYX (roll, pitch) \[rad\] when the recording has a truth (NaN where missing).
    pub truth: Option<Vec<[f64; 2]>>,
    /// Index of the first movement sample, when the recording marks it (BROAD).
    pub movement: Option<usize>,
    /// Which rows are in the movement phase, when the recording marks it (BROAD's
    /// `movement`): the rows its benchmark scores.
    pub moving: Option<Vec<bool>>,
    /// 1-based line of each row in a CSV (empty for other sources).
    pub lines: Vec<u64>,
}

/// ZYX roll and pitch \[rad\] of the quaternion (w, x, y, z), world <- body (MODEL.md
/// 7.1): from the world's up direction in body axes, u = R^T e_z. A quaternion that is
/// not finite or not close to unit length (|q| off 1 by more than 10 %) gives NaN.
pub fn roll_pitch_of_quaternion(q: [f64; 4]) -> [f64; 2] {
    let n2: f64 = q.iter().map(|x| x * x).sum();
    if !(n2.is_finite() && (0.81..=1.21).contains(&n2)) {
        return [f64::NAN; 2];
    }
    let [w, x, y, z] = q.map(|v| v / n2.sqrt());
    let u = [
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    ];
    [u[1].atan2(u[2]), (-u[0]).atan2(u[1].hypot(u[2]))]
}

/// The columns an IMU CSV gives, by their names (MODEL.md 7.6 and 7.10).
pub const IMU_COLUMNS: [&str; 13] = [
    "t", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az", "roll", "pitch", "qw", "qx", "qy", "qz",
];

/// How many of [`IMU_COLUMNS`] (the first ones) are required.
pub const IMU_REQUIRED: usize = 7;

/// How an IMU CSV is read: other names, units.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuOptions {
    /// `NAME=SOURCE` pairs: the header column SOURCE holds [`IMU_COLUMNS`]' NAME.
    pub map: Vec<(String, String)>,
    /// The gyro in deg/s.
    pub gyro_deg: bool,
    /// Roll and pitch in degrees.
    pub angles_deg: bool,
    /// Seconds per unit of `t` (1 for seconds, 1e-3 for ms).
    pub time_scale: f64,
    /// m/s^2 per unit of the accelerometer (1, or 9.80665 for g).
    pub accel_scale: f64,
}

impl Default for ImuOptions {
    fn default() -> Self {
        Self {
            map: Vec::new(),
            gyro_deg: false,
            angles_deg: false,
            time_scale: 1.0,
            accel_scale: 1.0,
        }
    }
}

/// Why a recording cannot be read. Displays as `imu.csv:7: column 3 (`gyro_y`): not a
/// number: `abc``.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceError {
    /// The file.
    pub file: String,
    /// 1-based line, when the error has one.
    pub line: Option<u64>,
    /// 1-based column and its header name, when the error has one.
    pub column: Option<(usize, String)>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SourceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        if let Some((c, name)) = &self.column {
            write!(f, ": column {c} (`{name}`)")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SourceError {}

impl Recording {
    /// Reads a recording from `path`: a MATLAB v5 file is read as a BROAD trial, anything
    /// else as an IMU CSV with `options`.
    pub fn open(path: impl AsRef<Path>, options: &ImuOptions) -> Result<Self, SourceError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let err = |message: String| SourceError {
            file: name.clone(),
            line: None,
            column: None,
            message,
        };
        let bytes = std::fs::read(path).map_err(|e| err(format!("cannot read: {e}")))?;
        if MatFile::is_mat_v5(&bytes) || bytes.starts_with(b"MATLAB") {
            let mat = MatFile::from_bytes(&bytes, &name).map_err(|e| SourceError {
                file: name.clone(),
                line: None,
                column: None,
                message: strip_origin(&e.to_string(), &name),
            })?;
            return Self::from_broad(&mat, &name);
        }
        Self::from_csv(bytes.as_slice(), &name, options)
    }

    /// A BROAD trial (Laidig et al., *Data* 6(7), 2021): `imu_gyr` \[rad/s\], `imu_acc`
    /// \[m/s^2\], `opt_quat` (w, x, y, z; ENU <- IMU), `sampling_rate` \[Hz\] and
    /// `movement` (1 in the movement phase). The rows are at t_k = k / rate.
    pub fn from_broad(mat: &MatFile, origin: &str) -> Result<Self, SourceError> {
        let err = |message: String| SourceError {
            file: origin.to_string(),
            line: None,
            column: None,
            message,
        };
        let get = |name: &str, cols: usize| {
            let a = mat.get(name).ok_or_else(|| {
                err(format!(
                    "no `{name}` variable: not a BROAD trial (it has: {})",
                    mat.names().collect::<Vec<_>>().join(", ")
                ))
            })?;
            if a.cols() != cols {
                return Err(err(format!(
                    "`{name}` has {} columns, a BROAD trial's has {cols}",
                    a.cols()
                )));
            }
            Ok(a)
        };
        let (gyr, acc) = (get("imu_gyr", 3)?, get("imu_acc", 3)?);
        let rate = get("sampling_rate", 1)?;
        let fs = rate.data.first().copied().unwrap_or(f64::NAN);
        if !(fs.is_finite() && fs > 0.0) {
            return Err(err(format!("`sampling_rate` must be > 0 Hz, got {fs}")));
        }
        let n = gyr.rows();
        if acc.rows() != n {
            return Err(err(format!(
                "`imu_gyr` has {n} rows, `imu_acc` {}",
                acc.rows()
            )));
        }
        let row3 = |a: &crate::io::mat::MatArray, k| [a.get(k, 0), a.get(k, 1), a.get(k, 2)];
        let truth = match mat.get("opt_quat") {
            Some(q) if q.cols() == 4 && q.rows() == n => Some(
                (0..n)
                    .map(|k| {
                        roll_pitch_of_quaternion([
                            q.get(k, 0),
                            q.get(k, 1),
                            q.get(k, 2),
                            q.get(k, 3),
                        ])
                    })
                    .collect(),
            ),
            _ => None,
        };
        let moving: Option<Vec<bool>> = mat
            .get("movement")
            .filter(|m| m.rows() == n)
            .map(|m| m.column(0).iter().map(|&v| v != 0.0).collect());
        let movement = moving.as_ref().and_then(|m| m.iter().position(|&v| v));
        Ok(Self {
            origin: origin.to_string(),
            t: (0..n).map(|k| k as f64 / fs).collect(),
            gyro: (0..n).map(|k| row3(gyr, k)).collect(),
            accel: (0..n).map(|k| row3(acc, k)).collect(),
            truth,
            movement,
            moving,
            lines: Vec::new(),
        })
    }

    /// An IMU CSV: a header row with [`IMU_COLUMNS`]' names (or mapped ones), one row per
    /// sample. An empty or `nan` cell reads as NaN (replay interpolates across it and keeps
    /// the row); a cell that is not a number, a row with too many fields or a time that does
    /// not increase is an error naming the line and the column.
    pub fn from_csv<R: BufRead>(
        input: R,
        origin: &str,
        options: &ImuOptions,
    ) -> Result<Self, SourceError> {
        let mut lines = CsvLines::new(input, b',');
        let err =
            |line: Option<u64>, column: Option<(usize, String)>, message: String| SourceError {
                file: origin.to_string(),
                line,
                column,
                message,
            };
        let next = |lines: &mut CsvLines<R>| -> Result<bool, SourceError> {
            match lines.next_row() {
                Ok(r) => Ok(r.is_some()),
                Err(RowError::Io(e)) => Err(err(
                    Some(lines.line() + 1),
                    None,
                    format!("cannot read: {e}"),
                )),
                Err(RowError::UnterminatedQuote(i)) => Err(err(
                    Some(lines.line()),
                    Some((i + 1, String::new())),
                    "unterminated quote".into(),
                )),
            }
        };
        if !next(&mut lines)? {
            return Err(err(None, None, "empty: no header".into()));
        }
        let header_line = lines.line();
        let header: Vec<String> = (0..lines.field_count())
            .map(|i| {
                lines
                    .field(i)
                    .map(|f| String::from_utf8_lossy(&f).trim().to_string())
                    .unwrap_or_default()
            })
            .collect();
        for (name, _) in &options.map {
            if !IMU_COLUMNS.contains(&name.as_str()) {
                return Err(err(
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
                return Err(err(
                    Some(header_line),
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
            return Err(err(
                Some(header_line),
                None,
                format!(
                    "no {} column (the header has: {}); an IMU recording needs t, gyro_x, gyro_y, gyro_z, ax, ay, az, and may have roll, pitch or qw, qx, qy, qz; other names: --map gyro_x=gx,...",
                    missing.iter().map(|m| format!("`{m}`")).collect::<Vec<_>>().join(", "),
                    header.join(", ")
                ),
            ));
        }
        let has_angles = pos[7].is_some() && pos[8].is_some();
        let has_quat = pos[9..13].iter().all(Option::is_some);
        let mut rec = Recording {
            origin: origin.to_string(),
            truth: (has_angles || has_quat).then(Vec::new),
            ..Recording::default()
        };
        let deg = std::f64::consts::PI / 180.0;
        while next(&mut lines)? {
            let line = lines.line();
            let (found, expected) = (lines.field_count(), header.len());
            if found > expected
                && (expected..found).any(|i| lines.raw(i).is_some_and(|f| !f.is_empty()))
            {
                return Err(err(
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
                        return Err(err(
                            Some(line),
                            Some((p + 1, header[p].clone())),
                            format!("not a number: `{text}`"),
                        ));
                    }
                }
            }
            let t = v[0] * options.time_scale;
            if !t.is_finite() {
                return Err(err(
                    Some(line),
                    pos[0].map(|p| (p + 1, header[p].clone())),
                    "no time: a replay needs every row's `t`".into(),
                ));
            }
            if let Some(&prev) = rec.t.last() {
                if t <= prev {
                    return Err(err(
                        Some(line),
                        pos[0].map(|p| (p + 1, header[p].clone())),
                        format!("t = {t} s does not increase (the row before has {prev} s): a replay needs a time that increases"),
                    ));
                }
            }
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
            return Err(err(
                Some(header_line),
                None,
                "header only, no data rows".into(),
            ));
        }
        Ok(rec)
    }
}

/// A MAT error's message without its leading `origin: ` (the source error adds its own).
fn strip_origin(message: &str, origin: &str) -> String {
    message
        .strip_prefix(origin)
        .and_then(|m| m.strip_prefix(": "))
        .unwrap_or(message)
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternions_give_the_zyx_roll_and_pitch() {
        // Rz(yaw) Ry(pitch) Rx(roll) as a quaternion: qz * qy * qx.
        let (r, p, y) = (0.3f64, -0.4f64, 1.2f64);
        let (cr, sr) = ((r / 2.0).cos(), (r / 2.0).sin());
        let (cp, sp) = ((p / 2.0).cos(), (p / 2.0).sin());
        let (cy, sy) = ((y / 2.0).cos(), (y / 2.0).sin());
        let q = [
            cy * cp * cr + sy * sp * sr,
            cy * cp * sr - sy * sp * cr,
            cy * sp * cr + sy * cp * sr,
            sy * cp * cr - cy * sp * sr,
        ];
        let [rr, pp] = roll_pitch_of_quaternion(q);
        assert!(
            (rr - r).abs() < 1e-12 && (pp - p).abs() < 1e-12,
            "{rr} {pp}"
        );
        assert!(roll_pitch_of_quaternion([f64::NAN, 0.0, 0.0, 0.0])[0].is_nan());
        assert!(roll_pitch_of_quaternion([0.0; 4])[0].is_nan());
    }

    #[test]
    fn an_imu_csv_reads_with_its_units_and_names() {
        let text = "time,gx,gyro_y,gyro_z,ax,ay,az,roll,pitch\n\
                    0,57.29577951308232,0,0,0,0,1,10,0\n\
                    10,0,,0,0,0,1,0,-5\n";
        let o = ImuOptions {
            map: vec![("t".into(), "time".into()), ("gyro_x".into(), "gx".into())],
            gyro_deg: true,
            angles_deg: true,
            time_scale: 1e-3,
            accel_scale: 9.80665,
        };
        let r = Recording::from_csv(text.as_bytes(), "imu.csv", &o).unwrap();
        assert_eq!(r.t, vec![0.0, 0.01]);
        assert!((r.gyro[0][0] - 1.0).abs() < 1e-15 && r.gyro[1][1].is_nan());
        assert_eq!(r.accel[0][2], 9.80665);
        let truth = r.truth.unwrap();
        assert!((truth[0][0] - 10f64.to_radians()).abs() < 1e-15);
        assert_eq!(r.lines, vec![2, 3]);
    }

    #[test]
    fn bad_imu_csvs_are_named_with_line_and_column() {
        let o = ImuOptions::default();
        let head = "t,gyro_x,gyro_y,gyro_z,ax,ay,az";
        let e = Recording::from_csv(
            format!("{head}\n0,0,0,0,0,0,9.8\n0.01,0,abc,0,0,0,9.8\n").as_bytes(),
            "imu.csv",
            &o,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(e, "imu.csv:3: column 3 (`gyro_y`): not a number: `abc`");
        let e = Recording::from_csv("t,gyro_x,ax\n0,0,0\n".as_bytes(), "imu.csv", &o)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("imu.csv:1: no `gyro_y`, `gyro_z`, `ay`, `az` column"),
            "{e}"
        );
        let e = Recording::from_csv(
            format!("{head}\n0,0,0,0,0,0,9.8\n0,0,0,0,0,0,9.8\n").as_bytes(),
            "imu.csv",
            &o,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("imu.csv:3: column 1 (`t`): t = 0 s does not increase"),
            "{e}"
        );
        let e = Recording::from_csv(
            format!("{head}\n0,0,0,0,0,0,9.8,1\n").as_bytes(),
            "imu.csv",
            &o,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(e, "imu.csv:2: 8 fields, the header has 7");
        let o = ImuOptions {
            map: vec![("gyro_x".into(), "gx".into())],
            ..ImuOptions::default()
        };
        let e = Recording::from_csv(format!("{head}\n").as_bytes(), "imu.csv", &o)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--map gyro_x=gx: no column `gx`"), "{e}");
    }
}
