//! Log in, estimates out: the streaming loop shared by `estimate`, `stream` and `report`.
use std::io::{BufRead, Write};

use pendtilt_core::Estimate;

use crate::bank::{Bank, Inputs};
use crate::io::{Column, EstimatesWriter, LogError, LogReader, LogWarning};

/// Which sensors a log's columns provide.
pub fn inputs_of<R: BufRead>(log: &LogReader<R>) -> Inputs {
    let c = log.columns();
    Inputs {
        phi: c.has(Column::Phi),
        gyro: c.has(Column::Gyro),
        accel: c.has(Column::Ax) && c.has(Column::Ay),
    }
}

/// Running error statistics of one estimator against the true angle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ErrorStats {
    /// Samples with both a finite estimate and a finite truth.
    pub count: u64,
    /// Samples whose estimate was NaN while the truth was finite.
    pub missing: u64,
    sum_sq: f64,
    /// Largest absolute error [rad].
    pub max_abs: f64,
}

impl ErrorStats {
    /// Adds one sample.
    pub fn add(&mut self, estimate: f64, truth: f64) {
        if !truth.is_finite() {
            return;
        }
        if !estimate.is_finite() {
            self.missing += 1;
            return;
        }
        let e = estimate - truth;
        self.count += 1;
        self.sum_sq += e * e;
        self.max_abs = self.max_abs.max(e.abs());
    }

    /// Root-mean-square error [rad] (NaN without samples).
    pub fn rms(&self) -> f64 {
        if self.count == 0 {
            f64::NAN
        } else {
            (self.sum_sq / self.count as f64).sqrt()
        }
    }
}

/// What one pass over a log produced.
#[derive(Debug, Clone, PartialEq)]
pub struct PassSummary {
    /// Rows read (= rows written).
    pub rows: u64,
    /// Error statistics per estimator, in the bank's order, when the log has `theta`.
    pub errors: Option<Vec<(String, ErrorStats)>>,
}

/// Reads every row of `log`, runs `bank` on it, writes one row per input row to `out`
/// (when given, flushing after each row if `flush_each`), hands each reader warning to
/// `warn`, and accumulates errors against `theta` when the log has it.
pub fn run<R: BufRead, W: Write>(
    log: &mut LogReader<R>,
    bank: &mut Bank,
    mut out: Option<&mut EstimatesWriter<W>>,
    flush_each: bool,
    mut warn: impl FnMut(&LogWarning),
    mut each: impl FnMut(u64, &[Estimate<f64>]),
) -> Result<PassSummary, PassError> {
    let with_theta = log.columns().has(Column::Theta);
    let mut stats = vec![ErrorStats::default(); bank.names().len()];
    let mut est = Vec::with_capacity(bank.names().len());
    let mut rows = 0u64;
    while let Some(rec) = log.next_record()? {
        for w in log.drain_warnings() {
            warn(&w);
        }
        bank.update(&rec.sample, &mut est);
        if let (true, Some(th)) = (with_theta, rec.theta) {
            for (s, e) in stats.iter_mut().zip(&est) {
                s.add(e.theta, th);
            }
        }
        if let Some(w) = out.as_deref_mut() {
            w.write(rec.sample.t, &est, rec.theta)
                .map_err(PassError::Write)?;
            if flush_each {
                w.flush().map_err(PassError::Write)?;
            }
        }
        rows += 1;
        each(rows, &est);
    }
    for w in log.drain_warnings() {
        warn(&w);
    }
    if let Some(w) = out {
        w.flush().map_err(PassError::Write)?;
    }
    Ok(PassSummary {
        rows,
        errors: with_theta.then(|| {
            bank.names()
                .iter()
                .map(|n| n.to_string())
                .zip(stats)
                .collect()
        }),
    })
}

/// Why a pass stopped.
#[derive(Debug, thiserror::Error)]
pub enum PassError {
    /// The log could not be read further.
    #[error(transparent)]
    Read(#[from] LogError),
    /// The output could not be written.
    #[error("cannot write the estimates: {0}")]
    Write(std::io::Error),
}

/// The error table printed by `estimate`: RMS and max error per estimator, in degrees.
pub fn error_table(errors: &[(String, ErrorStats)]) -> String {
    let mut s = String::from("estimator        RMS [deg]   max [deg]   samples  missing\n");
    for (name, e) in errors {
        s.push_str(&format!(
            "{name:<15} {:>10.4} {:>11.4} {:>9} {:>8}\n",
            e.rms().to_degrees(),
            e.max_abs.to_degrees(),
            e.count,
            e.missing
        ));
    }
    s
}
