//! A recorded IMU to replay (MODEL.md 7.10): time, gyro and specific force at the IMU, body
//! axes (FLU), and the truth when the recording has one, as roll and pitch or as a
//! quaternion (world <- body).
//!
//! Two sources: an IMU CSV (the user's own recording; columns by name, other names mapped,
//! units given), and a BROAD trial file (MATLAB v5, as in the dataset's repository:
//! `imu_gyr`, `imu_acc`, `opt_quat`, `sampling_rate`, `movement`).
use std::fmt;
use std::path::Path;

use crate::io::mat::MatFile;

mod csv;

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
