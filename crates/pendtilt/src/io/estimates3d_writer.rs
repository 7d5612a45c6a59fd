//! Streaming writer of the 3-D estimates CSV (MODEL.md 7.6).
//!
//! Columns, in this order: `t`; per estimator `<name>_roll`, `<name>_pitch` and, when asked
//! for and the estimator has one, its quaternion `<name>_qw, _qx, _qy, _qz` (world <- body);
//! `roll`, `pitch` when the log has the truth; then, when asked for, one `<name>_flags`
//! column per estimator ([`Flags::names`], empty when none). Angles in radians unless
//! [`WriterOptions::degrees`] (the quaternion is unitless). Numbers in the shortest form
//! that reads back to the same `f64`; a missing value is `NaN`.
use std::io::{self, BufWriter, Write};

use pendtilt_core::spatial::Attitude;
use pendtilt_core::Flags;

use super::WriterOptions;

/// One estimator's columns.
#[derive(Debug, Clone)]
pub struct Column3d {
    /// The estimator's name.
    pub name: String,
    /// Whether its quaternion columns are written.
    pub quaternion: bool,
}

/// Streaming CSV writer of 3-D estimates.
#[derive(Debug)]
pub struct Estimates3dWriter<W: Write> {
    out: BufWriter<W>,
    line: String,
    columns: Vec<Column3d>,
    with_truth: bool,
    options: WriterOptions,
}

impl<W: Write> Estimates3dWriter<W> {
    /// Writes the header to `out`.
    pub fn new(
        out: W,
        columns: Vec<Column3d>,
        with_truth: bool,
        options: WriterOptions,
    ) -> io::Result<Self> {
        let mut header = vec!["t".to_string()];
        for c in &columns {
            header.push(format!("{}_roll", c.name));
            header.push(format!("{}_pitch", c.name));
            if c.quaternion {
                header.extend(["qw", "qx", "qy", "qz"].map(|q| format!("{}_{q}", c.name)));
            }
        }
        if with_truth {
            header.extend(["roll".to_string(), "pitch".to_string()]);
        }
        if options.flags {
            header.extend(columns.iter().map(|c| format!("{}_flags", c.name)));
        }
        let mut out = BufWriter::with_capacity(1 << 16, out);
        writeln!(out, "{}", header.join(","))?;
        Ok(Self {
            out,
            line: String::new(),
            columns,
            with_truth,
            options,
        })
    }

    /// Writes one row: `est` and `quat` have one entry per column (a `None` quaternion
    /// writes `NaN`); `truth` is written when the writer was made with it.
    pub fn write(
        &mut self,
        t: f64,
        est: &[Attitude<f64>],
        quat: &[Option<[f64; 4]>],
        truth: (f64, f64),
    ) -> io::Result<()> {
        if est.len() != self.columns.len() || quat.len() != self.columns.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} estimates for {} columns", est.len(), self.columns.len()),
            ));
        }
        let scale = if self.options.degrees {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        self.line.clear();
        let mut buf = zmij::Buffer::new();
        push(&mut self.line, &mut buf, t);
        for ((c, e), q) in self.columns.iter().zip(est).zip(quat) {
            self.line.push(',');
            push(&mut self.line, &mut buf, e.roll * scale);
            self.line.push(',');
            push(&mut self.line, &mut buf, e.pitch * scale);
            if c.quaternion {
                for x in q.unwrap_or([f64::NAN; 4]) {
                    self.line.push(',');
                    push(&mut self.line, &mut buf, x);
                }
            }
        }
        if self.with_truth {
            for x in [truth.0, truth.1] {
                self.line.push(',');
                push(&mut self.line, &mut buf, x * scale);
            }
        }
        if self.options.flags {
            for e in est {
                self.line.push(',');
                push_flags(&mut self.line, e.flags);
            }
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())
    }

    /// Pushes the buffered rows out and flushes.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

fn push_flags(line: &mut String, flags: Flags) {
    use std::fmt::Write as _;
    // Writing to a String cannot fail.
    let _ = write!(line, "{}", flags.names());
}

fn push(line: &mut String, buf: &mut zmij::Buffer, x: f64) {
    if x.is_finite() {
        line.push_str(buf.format_finite(x));
    } else if x.is_nan() {
        line.push_str("NaN");
    } else if x > 0.0 {
        line.push_str("inf");
    } else {
        line.push_str("-inf");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_rows_quaternion_truth_flags_and_degrees() {
        let cols = vec![
            Column3d {
                name: "pendulum3d".into(),
                quaternion: false,
            },
            Column3d {
                name: "ekf3d".into(),
                quaternion: true,
            },
        ];
        let opts = WriterOptions {
            flags: true,
            degrees: true,
        };
        let mut out = Vec::new();
        {
            let mut w = Estimates3dWriter::new(&mut out, cols, true, opts).unwrap();
            let a = Attitude {
                roll: std::f64::consts::PI,
                pitch: -std::f64::consts::FRAC_PI_2,
                flags: Flags::empty(),
            };
            let b = Attitude {
                flags: Flags::SAMPLE_MISSING,
                ..a
            };
            w.write(
                0.5,
                &[a, b],
                &[None, Some([1.0, 0.0, 0.0, 0.0])],
                (0.0, f64::NAN),
            )
            .unwrap();
            w.write(0.6, &[a, b], &[None, None], (0.0, 0.0)).unwrap();
            w.flush().unwrap();
        }
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "t,pendulum3d_roll,pendulum3d_pitch,ekf3d_roll,ekf3d_pitch,ekf3d_qw,ekf3d_qx,\
             ekf3d_qy,ekf3d_qz,roll,pitch,pendulum3d_flags,ekf3d_flags"
        );
        assert_eq!(
            lines[1],
            format!(
                "0.5,180.0,-90.0,180.0,-90.0,1.0,0.0,0.0,0.0,0.0,NaN,,{}",
                Flags::SAMPLE_MISSING.names()
            )
        );
        assert!(lines[2].starts_with("0.6,180.0,-90.0,180.0,-90.0,NaN,NaN,NaN,NaN,0.0,0.0,"));
    }
}
