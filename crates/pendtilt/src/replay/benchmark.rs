//! Scoring the 3-D estimators on a replayed recording (MODEL.md 7.9, 7.10): the inclination
//! error from the first movement on, over the whole movement and where the true tilt stays
//! under [`TILT_LIMIT_DEG`] (the stretches the pendulum's range covers).
use pendtilt_core::spatial::attitude::inclination_error;
use pendtilt_core::spatial::SpatialEstimator;
use pendtilt_core::StepGate;

use super::{Recording, Replay};
use crate::bank::spatial::{Bank3d, Settings3d};

/// The true tilt \[deg\] under which a row also counts towards the "tilt < 60 deg" scores
/// (MODEL.md 7.10): beyond it a real rig's pendulum is at its stops or past them.
pub const TILT_LIMIT_DEG: f64 = 60.0;

/// One estimator's inclination error on one recording \[deg\].
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// The estimator.
    pub estimator: String,
    /// RMS over the scored rows.
    pub rms: f64,
    /// Largest.
    pub max: f64,
    /// RMS over the scored rows whose true tilt is under [`TILT_LIMIT_DEG`].
    pub rms_low_tilt: f64,
    /// Largest over those rows.
    pub max_low_tilt: f64,
    /// Rows scored, and of them under the tilt limit.
    pub rows: [usize; 2],
    /// Time of the largest error \[s\].
    pub t_max: f64,
}

/// The true tilt \[rad\]: the angle between the body's z axis and the world's up,
/// acos(cos roll cos pitch).
pub fn tilt(roll: f64, pitch: f64) -> f64 {
    (roll.cos() * pitch.cos()).clamp(-1.0, 1.0).acos()
}

/// Which rows are scored: from the first movement on (the recording's mark, else the end
/// of the initial rest the replay found, else the first row), inside the recording's
/// movement phase when it marks one, with a finite truth.
pub fn scored_rows(rec: &Recording, replay: &Replay) -> Vec<bool> {
    let first = rec
        .movement
        .or(replay.report.rest.map(|r| r.end))
        .unwrap_or(0);
    replay
        .rows
        .iter()
        .enumerate()
        .map(|(k, r)| {
            k >= first
                && rec.moving.as_ref().is_none_or(|m| m[k])
                && r.roll.is_finite()
                && r.pitch.is_finite()
        })
        .collect()
}

/// Runs every 3-D estimator (or those in `only`) over the replay's log and scores each
/// against the truth; also returns each estimator's inclination error per row \[deg\]
/// (NaN where not scored).
pub fn score(
    rec: &Recording,
    replay: &Replay,
    settings: &Settings3d,
    only: Option<&[String]>,
) -> Result<(Vec<Score>, Vec<Vec<f64>>), String> {
    let mut bank = Bank3d::new(settings, only)?;
    let names = bank.names();
    let scored = scored_rows(rec, replay);
    let mut errors: Vec<Vec<f64>> = vec![Vec::with_capacity(replay.rows.len()); names.len()];
    let mut gate = StepGate::<f64>::new();
    for (k, row) in replay.rows.iter().enumerate() {
        let out = bank.update(&row.sample(gate.step(row.t)));
        for (e, a) in errors.iter_mut().zip(out) {
            e.push(if scored[k] {
                inclination_error(a.roll, a.pitch, row.roll, row.pitch).to_degrees()
            } else {
                f64::NAN
            });
        }
    }
    let scores = names
        .iter()
        .zip(&errors)
        .map(|(name, e)| summarise(name, e, &scored, replay))
        .collect();
    Ok((scores, errors))
}

/// Runs one estimator, built by the caller, over the replay's log and scores it against
/// the truth as [`score`] scores the bank's (the same rows, the same error); also returns
/// its inclination error per row \[deg\] (NaN where not scored). No gap watch: for a log
/// without gaps, such as a BROAD trial, it gives what the bank gives.
pub fn score_one(
    rec: &Recording,
    replay: &Replay,
    name: &str,
    estimator: &mut dyn SpatialEstimator<f64>,
) -> (Score, Vec<f64>) {
    let scored = scored_rows(rec, replay);
    let mut gate = StepGate::<f64>::new();
    let errors: Vec<f64> = replay
        .rows
        .iter()
        .zip(&scored)
        .map(|(row, &keep)| {
            let a = estimator.update(&row.sample(gate.step(row.t)));
            if keep {
                inclination_error(a.roll, a.pitch, row.roll, row.pitch).to_degrees()
            } else {
                f64::NAN
            }
        })
        .collect();
    (summarise(name, &errors, &scored, replay), errors)
}

/// The scores of one estimator's errors `e` \[deg\] over the `scored` rows.
fn summarise(name: &str, e: &[f64], scored: &[bool], replay: &Replay) -> Score {
    let low: Vec<bool> = replay
        .rows
        .iter()
        .map(|r| tilt(r.roll, r.pitch).to_degrees() < TILT_LIMIT_DEG)
        .collect();
    let stats = |keep: &dyn Fn(usize) -> bool| {
        let (mut s2, mut max, mut n, mut t_max) = (0.0, 0.0f64, 0usize, f64::NAN);
        for (k, &x) in e.iter().enumerate() {
            if !scored[k] || !keep(k) {
                continue;
            }
            // A non-finite estimate makes RMS and max infinite (MODEL.md 7.9).
            let x = if x.is_finite() { x } else { f64::INFINITY };
            s2 += x * x;
            if x > max || t_max.is_nan() {
                max = x;
                t_max = replay.rows[k].t;
            }
            n += 1;
        }
        (
            (s2 / n as f64).sqrt(),
            if n > 0 { max } else { f64::NAN },
            n,
            t_max,
        )
    };
    let (rms, max, n, t_max) = stats(&|_| true);
    let (rms_low_tilt, max_low_tilt, n_low, _) = stats(&|k| low[k]);
    Score {
        estimator: name.to_string(),
        rms,
        max,
        rms_low_tilt,
        max_low_tilt,
        rows: [n, n_low],
        t_max,
    }
}
