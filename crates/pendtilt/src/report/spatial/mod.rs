//! 3-D reports (MODEL.md 7): every estimator's roll and pitch against the
//! truth and its inclination error (MODEL.md 7.9) over time, as figures, a table of RMS,
//! max and mean, `report.md`, `report.json` and one HTML page.
//!
//! Like the planar [`Report`](super::Report) it knows no estimator: it takes the time, the
//! true roll and pitch and named (roll, pitch) series \[rad\]. The scores are those
//! `pendtilt estimate` prints on a 3-D log: [`crate::bank::spatial::score::Inclination`] over the
//! rows with `t >= t0 + score_from` (t0 the first finite time).
//!
//! - [`draw`]: the three figures (one panel per estimator each);
//! - [`phases`]: a ride's turning, braking and accelerating, found from the log;
//! - [`ride`]: on a log with a speed, the filter with and without it, per phase;
//! - [`page`]: the tables, Markdown, JSON and HTML.
use std::path::PathBuf;

use pendtilt_core::spatial::attitude::inclination_error;
use serde::Serialize;

use super::figures::{AxisInfo, FigureFiles};
use super::palette::Palette;
use super::ReportError;
use crate::bank::spatial::score::Inclination;

pub mod draw;
pub mod page;
pub mod phases;
pub mod ride;

pub use ride::{Ride, RideData};

pub use crate::bank::spatial::RollPitch;

/// One row of the inclination error table \[deg\].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InclinationRow {
    /// The estimator.
    pub name: String,
    /// RMS over the scored rows \[deg\].
    pub rms_deg: f64,
    /// Largest \[deg\].
    pub max_deg: f64,
    /// Mean \[deg\].
    pub mean_deg: f64,
    /// Rows with the truth but no estimate (not scored).
    pub missing: u64,
}

/// A figure as `report.json` lists it: file names relative to the report's directory.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpatialFigure {
    /// The PNG.
    pub png: String,
    /// The SVG.
    pub svg: String,
    /// Its title.
    pub title: String,
    /// Its caption on the page.
    pub caption: String,
    /// Each panel's ordinate range and the points beyond it.
    pub axes: Vec<AxisInfo>,
}

/// Everything a 3-D report computed (written as `report.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpatialData {
    /// Title.
    pub title: String,
    /// Rows.
    pub samples: usize,
    /// Median sample rate \[Hz\].
    pub rate_hz: f64,
    /// Scoring starts this long after the first row \[s\].
    pub score_from_s: f64,
    /// Rows scored (with a finite truth, from `score_from_s` on).
    pub scored: u64,
    /// The inclination error of every estimator, in the order given.
    pub inclination: Vec<InclinationRow>,
    /// The figures, in page order.
    pub figures: Vec<SpatialFigure>,
    /// Notes at the end of the page.
    pub notes: Vec<String>,
    /// On a ride (a log with a speed, [`SpatialReport::ride`]): the filter with and
    /// without the speed, per phase.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ride: Option<RideData>,
}

/// What [`SpatialReport::write`] wrote.
#[derive(Debug, Clone)]
pub struct SpatialOutput {
    /// The HTML page.
    pub html: PathBuf,
    /// `report.md`.
    pub markdown: PathBuf,
    /// `report.json` ([`SpatialData`]).
    pub json: PathBuf,
    /// The figures, in page order.
    pub figures: Vec<FigureFiles>,
    /// The numbers.
    pub data: SpatialData,
}

/// A 3-D report being put together: the truth, the estimates and the words around them.
#[derive(Debug, Clone)]
pub struct SpatialReport {
    title: String,
    t: Vec<f64>,
    truth: RollPitch,
    estimates: Vec<RollPitch>,
    score_from: f64,
    intro: Vec<String>,
    notes: Vec<String>,
    palette: Palette,
    ride: Option<Ride>,
}

impl SpatialReport {
    /// A report on rows at times `t` \[s\] with the true roll and pitch \[rad\], scored
    /// from `score_from` \[s\] after the first finite time. Errors: lengths that differ,
    /// fewer than two rows, no finite time step, a score start that is not finite.
    pub fn new(
        title: &str,
        t: Vec<f64>,
        roll: Vec<f64>,
        pitch: Vec<f64>,
        score_from: f64,
    ) -> Result<Self, ReportError> {
        let truth = RollPitch {
            name: "truth".into(),
            roll,
            pitch,
        };
        check_len(&truth, t.len())?;
        if t.len() < 2 {
            return Err(ReportError::Empty("time column (needs two rows)".into()));
        }
        if !score_from.is_finite() {
            return Err(ReportError::Invalid(format!(
                "score_from {score_from} s is not finite"
            )));
        }
        median_rate(&t)?;
        Ok(Self {
            title: title.to_string(),
            t,
            truth,
            estimates: Vec::new(),
            score_from,
            intro: Vec::new(),
            notes: Vec::new(),
            palette: Palette::default(),
            ride: None,
        })
    }

    /// Adds an estimator's series. Errors: wrong length, empty or repeated name.
    pub fn estimate(mut self, series: RollPitch) -> Result<Self, ReportError> {
        if series.name.trim().is_empty() {
            return Err(ReportError::Invalid("estimator name is empty".into()));
        }
        check_len(&series, self.t.len())?;
        if series.name == self.truth.name || self.estimates.iter().any(|e| e.name == series.name) {
            return Err(ReportError::DuplicateName(series.name));
        }
        self.estimates.push(series);
        Ok(self)
    }

    /// Makes it a ride report: the phases, and `ride.compensated` (an estimate added
    /// before) beside the same filter without the speed. Errors: lengths that differ, an
    /// unknown compensated estimate, an uncompensated name already taken.
    pub fn ride(mut self, ride: Ride) -> Result<Self, ReportError> {
        let n = self.t.len();
        for (what, v) in [("speed", &ride.speed), ("gyro z", &ride.gyro_z)] {
            if v.len() != n {
                return Err(ReportError::LengthMismatch {
                    name: what.into(),
                    expected: n,
                    got: v.len(),
                });
            }
        }
        check_len(&ride.uncompensated, n)?;
        if !self.estimates.iter().any(|e| e.name == ride.compensated) {
            return Err(ReportError::Invalid(format!(
                "ride: no estimate named {}",
                ride.compensated
            )));
        }
        let u = &ride.uncompensated.name;
        if u.trim().is_empty()
            || u == &self.truth.name
            || self.estimates.iter().any(|e| &e.name == u)
        {
            return Err(ReportError::DuplicateName(u.clone()));
        }
        self.ride = Some(ride);
        Ok(self)
    }

    /// A paragraph under the title.
    pub fn intro(mut self, text: &str) -> Self {
        self.intro.push(text.to_string());
        self
    }

    /// A note at the end of the page.
    pub fn note(mut self, text: &str) -> Self {
        self.notes.push(text.to_string());
        self
    }

    /// Whether row `k` is scored: its time at or after the first finite time plus
    /// `score_from` (as `pendtilt estimate` scores).
    fn scored_rows(&self) -> Vec<bool> {
        let t0 = self.t.iter().copied().find(|t| t.is_finite());
        self.t
            .iter()
            .map(|&t| t0.is_some_and(|t0| t >= t0 + self.score_from))
            .collect()
    }

    /// The inclination error of every estimator over the scored rows, and how many rows
    /// were scored. Errors: no estimator, or no scored row with a finite truth.
    pub fn scores(&self) -> Result<(Vec<InclinationRow>, u64), ReportError> {
        if self.estimates.is_empty() {
            return Err(ReportError::Empty("estimate list".into()));
        }
        let scored = self.scored_rows();
        let mut rows = Vec::new();
        let mut count = 0;
        for e in &self.estimates {
            let mut s = Inclination::default();
            for (k, _) in scored.iter().enumerate().filter(|(_, on)| **on) {
                s.add(
                    (e.roll[k], e.pitch[k]),
                    (self.truth.roll[k], self.truth.pitch[k]),
                );
            }
            count = s.count() + s.missing();
            rows.push(InclinationRow {
                name: e.name.clone(),
                rms_deg: s.rms().to_degrees(),
                max_deg: s.max().to_degrees(),
                mean_deg: s.mean().to_degrees(),
                missing: s.missing(),
            });
        }
        if count == 0 {
            return Err(ReportError::Invalid(format!(
                "no row with a finite true roll and pitch from {} s after the first row on \
                 (the scoring start): nothing to score",
                self.score_from
            )));
        }
        Ok((rows, count))
    }

    /// The inclination error of `e` at every row \[deg\] (NaN where either is not finite).
    fn inclination_deg(&self, e: &RollPitch) -> Vec<f64> {
        (0..self.t.len())
            .map(|k| {
                inclination_error(
                    e.roll[k],
                    e.pitch[k],
                    self.truth.roll[k],
                    self.truth.pitch[k],
                )
                .to_degrees()
            })
            .collect()
    }
}

/// Seconds as written in texts: "5", "0.5", "60" (to the millisecond).
pub fn secs(v: f64) -> String {
    format!("{}", (v * 1e3).round() / 1e3)
}

fn check_len(s: &RollPitch, n: usize) -> Result<(), ReportError> {
    for (what, v) in [("roll", &s.roll), ("pitch", &s.pitch)] {
        if v.len() != n {
            return Err(ReportError::LengthMismatch {
                name: format!("{} {what}", s.name),
                expected: n,
                got: v.len(),
            });
        }
    }
    Ok(())
}

/// The median of the positive finite time steps, as a rate \[Hz\]: a log with a missing
/// time here and there still has its rate.
fn median_rate(t: &[f64]) -> Result<f64, ReportError> {
    let mut steps: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if steps.is_empty() {
        return Err(ReportError::TimeNotIncreasing { index: 0 });
    }
    steps.sort_by(f64::total_cmp);
    Ok(1.0 / steps[steps.len() / 2])
}
