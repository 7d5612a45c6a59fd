//! Log in, estimates out: the pass over a log shared by `estimate`, `stream`, `report` and
//! `batch`, planar ([`planar`]: [`run`], [`run_parallel`]) and 3-D ([`spatial`]:
//! [`spatial::pass`], [`spatial::pass_on`]), with what both score by ([`Window`],
//! [`Scorer`]) and how a log's columns are read ([`LogColumns`]).
use std::io::BufRead;

use crate::io::{Column, LogReader};
use crate::sensors::Inputs;
use crate::units::Finding;

pub mod batch;

mod clips;
pub(crate) use clips::ClipFinder;

mod columns;
pub use columns::LogColumns;

pub mod planar;
pub use planar::{run, run_parallel, PassError};

pub mod spatial;

mod window;
pub use window::{duration, Scorer, Window, DEFAULT_SCORE_FROM, SHORT_LOG};

/// Which sensors a log's columns provide.
pub fn inputs_of<R: BufRead>(log: &LogReader<R>) -> Inputs {
    let c = log.columns();
    Inputs::from_fn(|s| Column::provides(s, |col| c.has(col)))
}

/// Running error statistics of one estimator against the true angle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ErrorStats {
    /// Samples with both a finite estimate and a finite truth.
    pub count: u64,
    /// Samples whose estimate was NaN while the truth was finite.
    pub missing: u64,
    sum_sq: f64,
    /// Largest absolute error \[rad\].
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

    /// Root-mean-square error \[rad\] (NaN without samples).
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
    /// Error statistics per estimator, in the bank's order, when the log has `theta`,
    /// over the rows of `window`.
    pub errors: Option<Vec<(String, ErrorStats)>>,
    /// The rows scored ([`Window::resolve`]).
    pub window: Window,
    /// Restarts of estimators after long sensor gaps.
    pub restarts: u64,
    /// Columns whose scale disagrees with the physics (degrees read as radians), each
    /// also handed to `warn`.
    pub unit_findings: Vec<Finding>,
}

/// The error table printed by `estimate`: RMS and max error per estimator, in degrees,
/// over the rows of `window`.
pub fn error_table(errors: &[(String, ErrorStats)], window: &Window) -> String {
    let n = errors.first().map_or(0, |(_, e)| e.count + e.missing);
    let score_from = window.from;
    let mut s = format!(
        "error against theta, {}:\n\
         estimator        RMS [deg]   max [deg]   samples  missing\n",
        window.heading(n)
    );
    for (name, e) in errors {
        s.push_str(&format!(
            "{name:<15} {:>10.4} {:>11.4} {:>9} {:>8}\n",
            e.rms().to_degrees(),
            e.max_abs.to_degrees(),
            e.count,
            e.missing
        ));
    }
    if n == 0 {
        s.push_str(&format!(
            "no row scored: the log ends before t0 + {score_from} s (t0 its first time); \
             score earlier with --score-from SECONDS\n"
        ));
    }
    s
}
