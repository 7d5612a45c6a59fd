//! A planar log as `pendtilt tune` reads it, and what the tuned rig file's first comment
//! lines (and the command's standard output) say about the log and each fit.
use std::path::Path;

use super::Tuned;
use crate::io::{Column, LogReader, ReaderOptions};
use pendtilt_core::Sample;

/// A planar log's rows as samples, and the true angle per row (NaN without one).
pub struct TuneLog {
    /// The rows as samples.
    pub samples: Vec<Sample<f64>>,
    /// The true angle per row, when the log has a `theta` column.
    pub truth: Option<Vec<f64>>,
    /// The unit check's findings (a gyro in deg/s, ...), as `estimate` says them.
    pub units: Vec<crate::units::Finding>,
    /// The reader's summary line (rows, time span, warnings by kind).
    pub summary: String,
}

impl TuneLog {
    /// Reads the whole log at `path` with `options`; refuses a log without `phi`. `say` is
    /// given each line to tell: the file and its columns, and each warning
    /// (`warning: ...`).
    pub fn read(
        path: &Path,
        options: ReaderOptions,
        mut say: impl FnMut(&str),
    ) -> anyhow::Result<TuneLog> {
        let mut log = LogReader::open(path, options)?;
        say(&format!("{}: {}", log.file(), log.columns()));
        anyhow::ensure!(
            log.columns().has(Column::Phi),
            "{}: no phi column: nothing to tune (map another name with --map phi=NAME)",
            log.file()
        );
        let has_theta = log.columns().has(Column::Theta);
        let (mut samples, mut truth) = (Vec::new(), Vec::new());
        while let Some(rec) = log.next_record()? {
            for w in log.drain_warnings() {
                say(&format!("warning: {w}"));
            }
            samples.push(rec.sample);
            truth.push(rec.theta.unwrap_or(f64::NAN));
        }
        // The end of the log's warnings: the unit check's (a gyro in deg/s tuned on
        // silently gave settings fitted to readings 57x too large, and said only the first
        // ten of those beyond the rig's full scale).
        for w in log.drain_warnings() {
            say(&format!("warning: {w}"));
        }
        let units = log.unit_findings().to_vec();
        Ok(TuneLog {
            samples,
            truth: has_theta.then_some(truth),
            units,
            summary: log.summary().to_string(),
        })
    }
}

/// What the file's first comment lines and standard output say: the log, the target, the
/// likelihood (or error) before and after each fit (`fit_lines`), and whether the time
/// limit cut in. `path` is the log's, `params` the start rig's file (None: the default rig),
/// `time_limit` the `--time-limit` in seconds.
pub fn header(
    path: &Path,
    params: Option<&Path>,
    time_limit: Option<f64>,
    log: &TuneLog,
    t: &Tuned,
) -> Vec<String> {
    let rate = super::sample_rate(&log.samples).unwrap_or(f64::NAN);
    let start = params.map_or("the default rig (MODEL.md)".to_string(), |p| {
        p.display().to_string()
    });
    let mut h = vec![
        format!(
            "pendtilt tune: {} ({} rows, {:.1} s at {:.0} Hz), starting from {start}",
            path.display(),
            log.samples.len(),
            log.samples.len() as f64 / rate,
            rate
        ),
        match t.target {
            "truth" => "target: the true angle (the log's theta column): RMS error [rad]".into(),
            _ => "target: the likelihood of the filters' own innovations (no true angle used): \
                  mean -log-likelihood per innovation, lower is better"
                .to_string(),
        },
    ];
    h.extend(fit_lines(t));
    if t.kalman_fit.is_none() {
        h.push("the filters were not fitted (see the notes): their noise kept as given".into());
    }
    h.push(format!("the log: {}", log.summary));
    for f in &log.units {
        h.push(format!(
            "NOT TO BE TRUSTED: tuned on a log whose units look wrong: {}",
            f.message
        ));
    }
    if t.stopped_by_time_limit {
        h.push(format!(
            "STOPPED EARLY by --time-limit {} s: the best values found so far are written",
            time_limit.unwrap_or(0.0)
        ));
    }
    h
}

/// One line per fit: the Kalman filters' Q and R, the accelerometer's R alone and beside
/// Algorithm 2, the EKF's process noise ([`ekf_line`]).
fn fit_lines(t: &Tuned) -> Vec<String> {
    let mut h = Vec::new();
    let what = if t.target == "truth" {
        "RMS error"
    } else {
        "innovation likelihood (mean -log L)"
    };
    match (&t.kalman_fit, &t.kalman_surrogate) {
        (Some(f), Some(s)) => {
            h.push(format!(
                "kf_alg2 {what}: before {:.5}, after {:.5} (its own optimum {:.5} not adopted: \
                 see [kalman])",
                f.nll_before, s.nll_at, f.nll_after
            ));
            h.push(format!(
                "kf_alg2 predicted RMS error (surrogate from the gyro) [deg]: before {:.4}, \
                 after {:.4}",
                s.rms_before.to_degrees(),
                s.rms_after.to_degrees()
            ));
        }
        (Some(f), None) => h.push(format!(
            "kf_alg2 {what}: before {:.5}, after {:.5}",
            f.nll_before, f.nll_after
        )),
        _ => {}
    }
    match t.accel_fit {
        Some(a) if a.surrogate => h.push(format!(
            "kf_accel predicted RMS error (surrogate from the gyro; the accelerometer's error \
             below {} Hz, the body's own acceleration, taken as its difference from Algorithm \
             2) [deg]: before {:.4}, after {:.4}",
            super::reference::CORNER_HZ,
            a.before.to_degrees(),
            a.after.to_degrees()
        )),
        Some(a) => h.push(format!(
            "kf_accel {what}: before {:.5}, after {:.5}",
            a.before, a.after
        )),
        None => {}
    }
    if let Some(a) = t.fused_fit {
        let on = if a.surrogate {
            "predicted RMS error (surrogates from the gyro)"
        } else {
            "RMS error against the truth"
        };
        h.push(format!(
            "kf_fused {on} [deg], its accelerometer R alone fitted: before {:.4}, after {:.4}",
            a.before.to_degrees(),
            a.after.to_degrees()
        ));
    }
    if let Some(e) = &t.ekf_fit {
        h.push(ekf_line(t, e, what));
    }
    h
}

/// The EKF's fit: its cost before and after, and whether it was adopted and why.
fn ekf_line(t: &Tuned, e: &super::ekf::EkfFitted, what: &str) -> String {
    let adopted = match (t.target, t.ekf_band) {
        ("truth", _) => "adopted".to_string(),
        (_, Some((k, f))) if f < k => format!(
            "adopted: error against the gyro's integral above 0.2 Hz {:.4} -> {:.4} deg",
            k.to_degrees(),
            f.to_degrees()
        ),
        (_, Some((k, f))) => format!(
            "not adopted: error against the gyro's integral above 0.2 Hz {:.4} deg with \
             it, {:.4} without",
            f.to_degrees(),
            k.to_degrees()
        ),
        _ => "not adopted (no gyro bias estimate to check it against)".to_string(),
    };
    format!(
        "ekf {what}: before {:.5}, after {:.5} ({adopted})",
        e.nll_before, e.nll_after
    )
}
