//! Reports: metrics against the true angle, figures, Markdown/JSON tables and a
//! self-contained HTML page.
//!
//! The pieces are independent of the estimators: they take named series (the truth and
//! one series per estimator, sampled at a known rate) and write files.
//!
//! - [`metrics`]: RMS, max, bias, std, lag, overshoot, settling, share within tolerance.
//! - [`figures`] and [`palette`]: PNG + SVG figures, one fixed colour per series name;
//!   [`families`]: the panels of the small-multiple overview figures.
//! - [`fig3`]: the paper's Fig. 3 (Eq 12 and a Monte-Carlo check).
//! - [`claims`], [`markdown`], [`html`]: claims table, Markdown/JSON, the HTML page.
//! - [`interactive`]: the page's zoomable plots (uPlot, inlined) of every time-series
//!   panel, each trace min/max-decimated ([`interactive::decimate`]) so that the page's
//!   size does not grow with the log.
//! - [`spatial`]: the 3-D report (roll, pitch and inclination error of every 3-D estimator).
//! - [`Report`]: all of it from named series into one directory. `pendtilt report` is
//!   `Report::new(title, t, theta)`, one `.estimate(name, values)` per estimator column,
//!   `.reference("accel")`, `.view("FIR 20 Hz", ..)` with the paper's filter, then
//!   `.write(out_dir)`. Besides the overviews it draws `compare` (alg1, alg2, ekf and the
//!   best peer on one set of axes) and, per estimator, its angle beside the reference and
//!   its error alone (scaled to it).
mod builder;
pub mod claims;
pub mod families;
pub mod fig3;
pub mod figures;
pub mod html;
pub mod interactive;
pub mod markdown;
pub mod metrics;
pub mod palette;
pub mod spatial;

pub use builder::{file_safe, FigureGroup, Report, ReportData, ReportOutput, ViewFn, ViewMetrics};

/// What can go wrong while computing or writing a report.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A series (named) has no samples.
    #[error("{0} is empty")]
    Empty(String),
    /// A series does not have as many samples as the truth.
    #[error("{name} has {got} samples, expected {expected}")]
    LengthMismatch {
        /// Name of the series.
        name: String,
        /// Length of the truth.
        expected: usize,
        /// Its length.
        got: usize,
    },
    /// The sample rate is not a positive finite number.
    #[error("sample rate {0} Hz is not a positive finite number")]
    InvalidRate(f64),
    /// The time column is not finite and strictly increasing.
    #[error("time column is not finite and strictly increasing at sample {index}")]
    TimeNotIncreasing {
        /// First offending sample.
        index: usize,
    },
    /// No sample pair with both estimate and truth finite.
    #[error(
        "no usable samples: {non_finite_estimate} non-finite in the estimate, \
         {non_finite_truth} more in the truth"
    )]
    NoValidSamples {
        /// Non-finite estimate samples.
        non_finite_estimate: usize,
        /// Non-finite truth samples where the estimate was finite.
        non_finite_truth: usize,
    },
    /// The lag could not be measured.
    #[error("{0}")]
    Lag(String),
    /// The truth is not one step, so overshoot and settling do not apply.
    #[error("not a step: {0}")]
    NotStepLike(String),
    /// An invalid argument (named in the message).
    #[error("{0}")]
    Invalid(String),
    /// Two series with the same name.
    #[error("series {0:?} given twice")]
    DuplicateName(String),
    /// Drawing a figure failed.
    #[error("figure {path}: {message}")]
    Plot {
        /// File being drawn.
        path: String,
        /// What the drawing backend said.
        message: String,
    },
    /// A page references a file that does not exist.
    #[error("page references {0}, which does not exist")]
    MissingFile(String),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// File or directory.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Serialising to JSON failed.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}
