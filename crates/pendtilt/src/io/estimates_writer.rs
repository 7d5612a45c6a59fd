//! Streaming writer of the estimates CSV (MODEL.md section 5).
//!
//! Columns, in this order: `t`; one column per estimator, in the order the caller gives
//! (`accel`, `pendulum`, `alg1`, `alg2`, `alg3`, `kf_accel`, ...); `theta` when the log
//! has a true angle; then, when asked for, one `<name>_flags` column per estimator in the
//! same order, holding [`Flags::names`] (`asin_clamped|initialising`, empty when none).
//! Angles are in radians unless [`WriterOptions::degrees`] is set (`t` stays in seconds).
//! Numbers are written in the shortest form that reads back to the same `f64`; a missing
//! value is `NaN`. One row per call; buffered; [`EstimatesWriter::flush`] pushes the rows
//! out (for live streaming, after every row).
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use pendtilt_core::{Estimate, Flags};

/// Options of the estimates writer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WriterOptions {
    /// Add one `<name>_flags` column per estimator.
    pub flags: bool,
    /// Write the estimates and `theta` in degrees instead of radians.
    pub degrees: bool,
}

/// Streaming CSV writer of estimates.
#[derive(Debug)]
pub struct EstimatesWriter<W: Write> {
    out: BufWriter<W>,
    // The row being formatted: one `write_all` per row.
    line: Vec<u8>,
    names: Vec<String>,
    with_theta: bool,
    options: WriterOptions,
    flag_text: Vec<String>,
    /// The flags each `flag_text` entry renders (re-rendered only on change).
    flag_last: Vec<Flags>,
}

impl EstimatesWriter<File> {
    /// Creates (or truncates) `path` and writes the header.
    pub fn create(
        path: impl AsRef<Path>,
        names: &[impl AsRef<str>],
        with_theta: bool,
        options: WriterOptions,
    ) -> io::Result<Self> {
        let path = path.as_ref();
        let file = File::create(path)
            .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        Self::new(file, names, with_theta, options)
    }
}

fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

impl<W: Write> EstimatesWriter<W> {
    /// Writes the header to `out`: `t`, `names...`, `theta` if `with_theta`, then the flag
    /// columns if asked for. Errors (`InvalidInput`) on an empty, duplicate or reserved
    /// (`t`, `theta`, `*_flags` clash) estimator name.
    pub fn new(
        out: W,
        names: &[impl AsRef<str>],
        with_theta: bool,
        options: WriterOptions,
    ) -> io::Result<Self> {
        let names: Vec<String> = names.iter().map(|n| n.as_ref().to_string()).collect();
        let mut header: Vec<String> = vec!["t".to_string()];
        header.extend(names.iter().cloned());
        if with_theta {
            header.push("theta".to_string());
        }
        if options.flags {
            header.extend(names.iter().map(|n| format!("{n}_flags")));
        }
        if let Some(n) = names.iter().find(|n| n.trim().is_empty()) {
            return Err(invalid(format!("estimator name `{n}` is empty")));
        }
        if let Some(n) = names
            .iter()
            .find(|n| n.contains([',', '"', '\n', '\r']) || n.trim() != n.as_str())
        {
            return Err(invalid(format!(
                "estimator name `{}` has a comma, quote, line break or outer spaces",
                n.escape_debug()
            )));
        }
        for (i, h) in header.iter().enumerate() {
            if header[..i].contains(h) {
                return Err(invalid(format!(
                    "estimates column `{h}` would appear twice (estimator names: {})",
                    names.join(", ")
                )));
            }
        }
        // Every field is a number, a checked name or a flag list (letters, `_`, `|`): none
        // needs quoting, so rows are formatted straight into bytes.
        let mut out = BufWriter::with_capacity(1 << 16, out);
        out.write_all(header.join(",").as_bytes())?;
        out.write_all(b"\n")?;
        Ok(Self {
            out,
            line: Vec::with_capacity(64 * header.len()),
            flag_text: vec![String::new(); names.len()],
            flag_last: vec![Flags::empty(); names.len()],
            names,
            with_theta,
            options,
        })
    }

    /// The estimator names, in column order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Writes one row: the time, one estimate per name (same order), and the true angle
    /// (written only when the writer was made `with_theta`; `None` writes `NaN`). Errors
    /// (`InvalidInput`) when `estimates` does not have one entry per name.
    pub fn write(
        &mut self,
        t: f64,
        estimates: &[Estimate<f64>],
        theta: Option<f64>,
    ) -> io::Result<()> {
        if estimates.len() != self.names.len() {
            return Err(invalid(format!(
                "{} estimates for {} estimator columns",
                estimates.len(),
                self.names.len()
            )));
        }
        let scale = if self.options.degrees {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        if self.options.flags {
            for ((text, last), e) in self
                .flag_text
                .iter_mut()
                .zip(self.flag_last.iter_mut())
                .zip(estimates)
            {
                if *last != e.flags {
                    *last = e.flags;
                    text.clear();
                    write_flags(text, e.flags);
                }
            }
        }
        self.line.clear();
        let mut number = zmij::Buffer::new();
        push_number(&mut self.line, &mut number, t);
        for e in estimates {
            self.line.push(b',');
            push_number(&mut self.line, &mut number, e.theta * scale);
        }
        if self.with_theta {
            self.line.push(b',');
            let th = theta.unwrap_or(f64::NAN);
            push_number(&mut self.line, &mut number, th * scale);
        }
        if self.options.flags {
            for f in &self.flag_text {
                self.line.push(b',');
                self.line.extend_from_slice(f.as_bytes());
            }
        }
        self.line.push(b'\n');
        self.out.write_all(&self.line)
    }

    /// Pushes the buffered rows to the underlying writer and flushes it.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    /// Flushes and returns the underlying writer.
    pub fn into_inner(self) -> io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

fn write_flags(text: &mut String, flags: Flags) {
    use std::fmt::Write as _;
    // Writing to a String cannot fail.
    let _ = write!(text, "{}", flags.names());
}

/// Appends `x` in the shortest form that reads back to the same `f64` (`NaN`, `inf` and
/// `-inf` for the others, as the log reader accepts them).
#[inline]
fn push_number(line: &mut Vec<u8>, buf: &mut zmij::Buffer, x: f64) {
    if x.is_finite() {
        line.extend_from_slice(buf.format_finite(x).as_bytes());
    } else if x.is_nan() {
        line.extend_from_slice(b"NaN");
    } else if x > 0.0 {
        line.extend_from_slice(b"inf");
    } else {
        line.extend_from_slice(b"-inf");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn est(theta: f64, flags: Flags) -> Estimate<f64> {
        Estimate { theta, flags }
    }

    #[test]
    fn header_rows_flags_and_degrees() {
        let mut w = EstimatesWriter::new(
            Vec::new(),
            &["accel", "alg2"],
            true,
            WriterOptions {
                flags: true,
                degrees: true,
            },
        )
        .unwrap();
        w.write(
            0.25,
            &[
                est(0.0, Flags::ASIN_CLAMPED),
                est(0.0, Flags::SAMPLE_MISSING | Flags::INITIALISING),
            ],
            None,
        )
        .unwrap();
        w.write(
            0.5,
            &[
                est(std::f64::consts::PI / 2.0, Flags::empty()),
                est(f64::NAN, Flags::SAMPLE_MISSING | Flags::INITIALISING),
            ],
            Some(std::f64::consts::PI),
        )
        .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "t,accel,alg2,theta,accel_flags,alg2_flags");
        assert_eq!(
            lines[1],
            "0.25,0.0,0.0,NaN,asin_clamped,initialising|sample_missing"
        );
        assert_eq!(lines[2], "0.5,90.0,NaN,180.0,,initialising|sample_missing");
        assert_eq!(lines.len(), 3);
    }

    #[test]
    fn radians_round_trip_exactly_and_no_theta_column() {
        let x = 0.123_456_789_012_345_67_f64;
        let mut w =
            EstimatesWriter::new(Vec::new(), &["pendulum"], false, WriterOptions::default())
                .unwrap();
        w.write(1e-3, &[est(x, Flags::ASIN_CLAMPED)], Some(1.0))
            .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("t,pendulum"));
        let row: Vec<f64> = lines
            .next()
            .unwrap()
            .split(',')
            .map(|c| c.parse().unwrap())
            .collect();
        assert_eq!(row, vec![1e-3, x]);
    }

    #[test]
    fn rejects_bad_names_and_counts() {
        let opts = WriterOptions::default();
        assert!(EstimatesWriter::new(Vec::new(), &["alg1", "alg1"], false, opts).is_err());
        assert!(EstimatesWriter::new(Vec::new(), &["theta"], true, opts).is_err());
        assert!(EstimatesWriter::new(Vec::new(), &["t"], false, opts).is_err());
        assert!(EstimatesWriter::new(Vec::new(), &[""], false, opts).is_err());
        assert!(EstimatesWriter::new(Vec::new(), &["a,b"], false, opts).is_err());
        assert!(EstimatesWriter::new(Vec::new(), &[" a"], false, opts).is_err());
        let mut w = EstimatesWriter::new(Vec::new(), &["alg1"], false, opts).unwrap();
        let e = w.write(0.0, &[], None).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
    }
}
