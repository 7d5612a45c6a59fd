//! [`Report`]: named series in, metrics + figures + Markdown/JSON + HTML page out.
//!
//! ```no_run
//! # fn main() -> Result<(), pendtilt::report::ReportError> {
//! use pendtilt::report::{claims::{ClaimSpec, Expect, MetricKind}, Report};
//! let t: Vec<f64> = (0..5000).map(|k| k as f64 / 1000.0).collect();
//! let truth = vec![0.0; 5000];
//! let (alg1, alg2) = (vec![0.01; 5000], vec![0.002; 5000]);
//! let out = Report::new("Sigmoid", t, truth)?
//!     .estimate("alg1", alg1)?
//!     .estimate("alg2", alg2)?
//!     .claim(ClaimSpec::new("Alg 2 beats Alg 1").expect("alg2", MetricKind::Rms, Expect::Lower, "alg1"))
//!     .write(std::path::Path::new("out"))?;
//! println!("{}", out.html.display());
//! # Ok(()) }
//! ```
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::claims::{Claim, ClaimSpec};
use super::families::{self};
use super::fig3::{fig3_data, plot_fig3, Fig3Config, Fig3Data};
use super::figures::{
    plot_errors, plot_panels, plot_time_series, Curve, FigureFiles, FigureSpec, Panel,
};
use super::html::{FigureRef, HtmlPage, MetricsTable};
use super::markdown::{claims_markdown, metrics_markdown};
use super::metrics::{
    compute_metrics, detect_step, rate_from_times, settling_band, Metrics, MetricsConfig,
};
use super::palette::Palette;
use super::ReportError;

mod write;
pub use write::file_safe;

/// Named series, in order.
type NamedSeries = Vec<(String, Vec<f64>)>;

/// A transform applied to every series (truth included) to make a view, e.g. the paper's
/// 20 Hz FIR. It must return as many samples as it is given.
pub type ViewFn = Box<dyn Fn(&[f64]) -> Vec<f64>>;

/// An extra figure: the truth plus the named series (angles), and their errors.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureGroup {
    /// File stem; the error figure gets `_error` appended.
    pub stem: String,
    /// Title of the angle figure (the error figure's title adds "error").
    pub title: String,
    /// Series to show, in drawing order (the truth is drawn first, always).
    pub names: Vec<String>,
    /// Time window \[s\] shown, or the whole record.
    pub window: Option<(f64, f64)>,
}

/// Metrics of every estimator under one view.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewMetrics {
    /// View name ("unfiltered" for the raw series).
    pub view: String,
    /// One row per estimator, in the order they were added.
    pub metrics: Vec<Metrics>,
    /// Estimators whose metrics could not be computed, with the reason.
    pub skipped: Vec<(String, String)>,
    /// How the truth was judged as a step (for overshoot and settling), in words.
    pub step: String,
}

/// Everything a report computed (also written as `report.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReportData {
    /// Report title.
    pub title: String,
    /// Sample rate \[Hz\] used by the metrics.
    pub rate_hz: f64,
    /// Number of samples.
    pub samples: usize,
    /// Metrics settings.
    pub config: MetricsConfig,
    /// Metrics per view, the unfiltered view first.
    pub views: Vec<ViewMetrics>,
    /// Claims, evaluated on the claims view.
    pub claims: Vec<Claim>,
    /// View the claims were evaluated on.
    pub claims_view: String,
    /// Fig. 3 data, when asked for.
    pub fig3: Option<Fig3Data>,
    /// Notes added by the caller.
    pub notes: Vec<String>,
}

/// What [`Report::write`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportOutput {
    /// The HTML page.
    pub html: PathBuf,
    /// The Markdown summary (metrics and claims tables).
    pub markdown: PathBuf,
    /// The JSON with everything in [`ReportData`].
    pub json: PathBuf,
    /// Every figure, in page order.
    pub figures: Vec<FigureFiles>,
    /// The numbers.
    pub data: ReportData,
}

/// Builder of a report from named series.
///
/// Angles are in `config.input_unit` (radians by default, as in the logs); figures and
/// tables are in degrees.
pub struct Report {
    title: String,
    rate_hz: f64,
    t: Vec<f64>,
    truth: Vec<f64>,
    estimates: Vec<(String, Vec<f64>)>,
    config: MetricsConfig,
    palette: Palette,
    views: Vec<(String, ViewFn)>,
    plot_view: Option<String>,
    claims_view: Option<String>,
    reference: Option<String>,
    per_estimator_figures: bool,
    groups: Vec<FigureGroup>,
    claims: Vec<ClaimSpec>,
    fig3: Option<Fig3Config>,
    intro: Vec<String>,
    notes: Vec<String>,
}

const UNFILTERED: &str = "unfiltered";

impl Report {
    /// A report on a log with time column `t` \[s\] and the true angle.
    ///
    /// Errors: empty series, mismatched lengths, times not strictly increasing.
    pub fn new(title: &str, t: Vec<f64>, truth: Vec<f64>) -> Result<Self, ReportError> {
        if t.len() != truth.len() {
            return Err(ReportError::LengthMismatch {
                name: "truth".into(),
                expected: t.len(),
                got: truth.len(),
            });
        }
        let rate_hz = rate_from_times(&t)?;
        Ok(Self::build(title, rate_hz, t, truth))
    }

    /// A report on series sampled at `rate_hz` from t = 0.
    pub fn with_rate(title: &str, rate_hz: f64, truth: Vec<f64>) -> Result<Self, ReportError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(ReportError::InvalidRate(rate_hz));
        }
        if truth.is_empty() {
            return Err(ReportError::Empty("truth".into()));
        }
        let t = (0..truth.len()).map(|k| k as f64 / rate_hz).collect();
        Ok(Self::build(title, rate_hz, t, truth))
    }

    fn build(title: &str, rate_hz: f64, t: Vec<f64>, truth: Vec<f64>) -> Self {
        Self {
            title: title.to_string(),
            rate_hz,
            t,
            truth,
            estimates: Vec::new(),
            config: MetricsConfig::default(),
            palette: Palette::default(),
            views: Vec::new(),
            plot_view: None,
            claims_view: None,
            reference: None,
            per_estimator_figures: true,
            groups: Vec::new(),
            claims: Vec::new(),
            fig3: None,
            intro: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// Adds an estimate. Errors: wrong length, empty or duplicate name.
    pub fn estimate(mut self, name: &str, values: Vec<f64>) -> Result<Self, ReportError> {
        if name.trim().is_empty() {
            return Err(ReportError::Invalid("estimator name is empty".into()));
        }
        if values.len() != self.truth.len() {
            return Err(ReportError::LengthMismatch {
                name: name.to_string(),
                expected: self.truth.len(),
                got: values.len(),
            });
        }
        if self.estimates.iter().any(|(n, _)| n == name) {
            return Err(ReportError::DuplicateName(name.to_string()));
        }
        self.estimates.push((name.to_string(), values));
        Ok(self)
    }

    /// Metrics settings (units, tolerance, lag window, step detection).
    pub fn config(mut self, config: MetricsConfig) -> Self {
        self.config = config;
        self
    }

    /// The name → colour map.
    pub fn palette(mut self, palette: Palette) -> Self {
        self.palette = palette;
        self
    }

    /// Adds a view: `f` is applied to every series, truth included, and the metrics are
    /// computed again on the result (e.g. "after the 20 Hz FIR").
    pub fn view(mut self, name: &str, f: ViewFn) -> Self {
        self.views.push((name.to_string(), f));
        self
    }

    /// The view the figures are drawn from (default: unfiltered).
    pub fn plot_view(mut self, name: &str) -> Self {
        self.plot_view = Some(name.to_string());
        self
    }

    /// The view the claims are evaluated on (default: unfiltered).
    pub fn claims_view(mut self, name: &str) -> Self {
        self.claims_view = Some(name.to_string());
        self
    }

    /// A series drawn beside every estimator in its own figures (the paper shows each
    /// algorithm beside the accelerometer, Figs 7-14).
    pub fn reference(mut self, name: &str) -> Self {
        self.reference = Some(name.to_string());
        self
    }

    /// Whether to draw one angle and one error figure per estimator (default: yes).
    pub fn per_estimator_figures(mut self, on: bool) -> Self {
        self.per_estimator_figures = on;
        self
    }

    /// Adds a figure pair (angles, errors) of chosen series.
    pub fn figure_group(mut self, group: FigureGroup) -> Self {
        self.groups.push(group);
        self
    }

    /// Adds a claim, checked against the claims view's metrics.
    pub fn claim(mut self, claim: ClaimSpec) -> Self {
        self.claims.push(claim);
        self
    }

    /// Adds the paper's Fig. 3 (Eq 12 with a Monte-Carlo check).
    pub fn fig3(mut self, cfg: Fig3Config) -> Self {
        self.fig3 = Some(cfg);
        self
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

    /// The truth and estimates under a view (index 0: unfiltered).
    fn view_series(&self, view: usize) -> Result<(Vec<f64>, NamedSeries), ReportError> {
        if view == 0 {
            return Ok((self.truth.clone(), self.estimates.clone()));
        }
        let (name, f) = &self.views[view - 1];
        let apply = |series: &str, v: &[f64]| {
            let out = f(v);
            if out.len() == v.len() {
                Ok(out)
            } else {
                Err(ReportError::LengthMismatch {
                    name: format!("view {name} of {series}"),
                    expected: v.len(),
                    got: out.len(),
                })
            }
        };
        let truth = apply("truth", &self.truth)?;
        let est = self
            .estimates
            .iter()
            .map(|(n, v)| Ok((n.clone(), apply(n, v)?)))
            .collect::<Result<Vec<_>, ReportError>>()?;
        Ok((truth, est))
    }

    fn view_names(&self) -> Vec<String> {
        std::iter::once(UNFILTERED.to_string())
            .chain(self.views.iter().map(|(n, _)| n.clone()))
            .collect()
    }

    fn view_index(&self, name: &Option<String>) -> Result<usize, ReportError> {
        match name {
            None => Ok(0),
            Some(n) => self
                .view_names()
                .iter()
                .position(|v| v == n)
                .ok_or_else(|| ReportError::Invalid(format!("no view named {n:?}"))),
        }
    }

    /// Computes the metrics of every view and the claims, without writing anything.
    pub fn compute(&self) -> Result<ReportData, ReportError> {
        if self.estimates.is_empty() {
            return Err(ReportError::Empty("estimate list".into()));
        }
        let names = self.view_names();
        let mut views = Vec::new();
        for (i, vname) in names.iter().enumerate() {
            let (truth, est) = self.view_series(i)?;
            let to_deg = self.config.input_unit.to_deg_factor();
            let truth_deg: Vec<f64> = truth.iter().map(|v| v * to_deg).collect();
            let step = match detect_step(&truth_deg, self.rate_hz, &self.config.step) {
                Ok(s) => format!(
                    "the truth is one step of {:.2} deg with its 50% point at t = {:.3} s: \
                     overshoot is the largest excursion beyond the truth's final value after \
                     that point, in % of the step; settling time is from that point until the \
                     estimate stays within {:.2} deg of the final value",
                    s.size,
                    s.time_s,
                    settling_band(&s, &self.config.step)
                ),
                Err(e) => format!("overshoot and settling time not applicable: {e}"),
            };
            let mut metrics = Vec::new();
            let mut skipped = Vec::new();
            for (n, v) in &est {
                match compute_metrics(n, v, &truth, self.rate_hz, &self.config) {
                    Ok(m) => metrics.push(m),
                    Err(e) => skipped.push((n.clone(), e.to_string())),
                }
            }
            views.push(ViewMetrics {
                view: vname.clone(),
                metrics,
                skipped,
                step,
            });
        }
        let cv = self.view_index(&self.claims_view)?;
        let claims = self
            .claims
            .iter()
            .map(|c| c.evaluate(&views[cv].metrics))
            .collect();
        let fig3 = self.fig3.as_ref().map(fig3_data).transpose()?;
        Ok(ReportData {
            title: self.title.clone(),
            rate_hz: self.rate_hz,
            samples: self.truth.len(),
            config: self.config.clone(),
            views,
            claims,
            claims_view: names[cv].clone(),
            fig3,
            notes: self.notes.clone(),
        })
    }
}
