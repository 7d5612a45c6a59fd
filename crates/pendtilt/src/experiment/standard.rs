//! The standard report of a record with a true angle: the one `pendtilt report` writes and
//! `pendtilt reproduce` writes for each ride.
use pendtilt_core::filters::fir::PaperFir;

use crate::report::fig3::Fig3Config;
use crate::report::{FigureGroup, Report, ReportError, ViewFn};

use super::estimate::Series;

/// Name of the view after the paper's FIR.
pub const FIR_VIEW: &str = "FIR 20 Hz";

/// The paper's 50th-order 20 Hz FIR (section V) applied to a whole series, causally, as a
/// [`ViewFn`]; `None` when the rate is too low for a 20 Hz low-pass.
pub fn fir_view(rate_hz: f64) -> Option<ViewFn> {
    PaperFir::<f64>::paper(rate_hz).ok()?;
    Some(Box::new(move |v: &[f64]| {
        // The rate was checked above, so the design cannot fail here; an empty filter
        // output would be caught by the report's length check anyway.
        match PaperFir::<f64>::paper(rate_hz) {
            Ok(mut f) => v.iter().map(|&x| f.update(x)).collect(),
            Err(_) => Vec::new(),
        }
    }))
}

/// The Kalman outputs compared in the "accelerometer vs pendulum" figure, in drawing order.
pub const KALMAN_NAMES: &[&str] = &["kf_accel", "kf_alg1", "kf_alg2", "kf_alg3"];

/// The report of a record: the estimates against `theta`, unfiltered and after the
/// paper's FIR (figures drawn after the FIR, as the paper's), each algorithm beside the
/// accelerometer (Figs 7-14), the Kalman filters fed by the accelerometer and by the
/// pendulum algorithms, and Fig. 3. Returns the builder (add claims, notes, groups) and
/// whether the FIR view exists.
pub fn standard_report(
    title: &str,
    t: Vec<f64>,
    theta: Vec<f64>,
    series: Series,
) -> Result<(Report, bool), ReportError> {
    let rate = crate::report::metrics::rate_from_times(&t)?;
    let mut report = Report::new(title, t, theta)?;
    let names: Vec<String> = series.iter().map(|(n, _)| n.clone()).collect();
    for (n, v) in series {
        report = report.estimate(&n, v)?;
    }
    if names.iter().any(|n| n == "accel") {
        report = report.reference("accel");
    }
    let kalman: Vec<String> = KALMAN_NAMES
        .iter()
        .filter(|k| names.iter().any(|n| n == *k))
        .map(|k| k.to_string())
        .collect();
    if kalman.len() >= 2 {
        report = report.figure_group(FigureGroup {
            stem: "kalman_accel_vs_pendulum".into(),
            title: "Kalman filter fed by the accelerometer vs by the pendulum".to_string(),
            names: kalman,
            window: None,
        });
    }
    if names
        .iter()
        .any(|n| ["madgwick", "mahony", "complementary"].contains(&n.as_str()))
    {
        let peers = crate::peers::PeerSettings::default();
        report = report.note(&format!(
            "Peers: madgwick (beta = {}), mahony (kp = {}, ki = {}) and complementary (tau = {} s) \
             run with the best gains a golden-section search found on the simulated scooter ride \
             (pendtilt::peers::tune::search_peer_gains); ekf and ukf with process and measurement \
             noise derived from the rig and the sensors' noise figures.",
            peers.madgwick_beta,
            peers.mahony[0],
            peers.mahony[1],
            peers.complementary.time_constant
        ));
    }
    let has_fir = match fir_view(rate) {
        Some(f) => {
            report = report
                .view(FIR_VIEW, f)
                .plot_view(FIR_VIEW)
                .claims_view(FIR_VIEW)
                .note(
                    "FIR 20 Hz: the paper's 50th-order (51-tap, Hamming) 20 Hz low-pass, applied \
                     causally to every series, the true angle included, so its 25-sample delay \
                     favours no estimator.",
                );
            true
        }
        None => {
            report = report.note(&format!(
                "No FIR view: at {rate:.1} Hz a 20 Hz low-pass is not possible (the paper's FIR \
                 needs at least 40 Hz)."
            ));
            false
        }
    };
    Ok((report.fig3(Fig3Config::default()), has_fir))
}
