//! A ride: on a log with a `speed` column, the estimator that uses the
//! speed (`ekf3d`) beside the same filter run without it, per phase of the ride
//! ([`super::phases`]: turning, braking, accelerating, found from the log), as a figure
//! of roll, pitch and inclination error over time with the phases shaded, a table and
//! `report.json`'s `ride`.
use std::path::Path;

use plotters::style::RGBColor;
use serde::Serialize;

use super::phases::{self, Phase, PhaseKind, RideSignals};
use super::{RollPitch, SpatialReport};
use crate::report::claims::fmt_sig;
use crate::report::figures::{
    plot_panels, Curve, FigureFiles, FigureSpec, LegendPosition, Panel, Shade,
};
use crate::report::html::TextTable;
use crate::report::ReportError;
use pendtilt_core::spatial::attitude::inclination_error;

/// What a ride section is given besides the report's estimates.
#[derive(Debug, Clone, PartialEq)]
pub struct Ride {
    /// Forward speed per row \[m/s\] (the log's `speed`).
    pub speed: Vec<f64>,
    /// Gyro z per row \[rad/s\].
    pub gyro_z: Vec<f64>,
    /// The estimate (one of the report's) that used the speed.
    pub compensated: String,
    /// The same estimator run without the speed.
    pub uncompensated: RollPitch,
    /// How the uncompensated run was made (a sentence for the page).
    pub how: String,
    /// The peers among the report's estimates: the best of them (lowest inclination RMS
    /// over the whole scored log) is set beside the two runs.
    pub peers: Vec<String>,
}

impl Ride {
    /// The ride of a log with `speed` and `gyro_z` per row, beside `without_speed`'s run
    /// (as many rows), or `None` when the vehicle does not move
    /// ([`crate::bank::spatial::ride::moves`]): nothing to compare.
    pub fn of(
        without_speed: crate::bank::spatial::ride::WithoutSpeed,
        speed: Vec<f64>,
        gyro_z: Vec<f64>,
    ) -> Option<Ride> {
        use crate::bank::spatial::ride::{moves, peers, COMPENSATED, HOW};
        if !moves(&speed) {
            return None;
        }
        Some(Ride {
            speed,
            gyro_z,
            compensated: COMPENSATED.into(),
            uncompensated: without_speed.run(),
            how: HOW.into(),
            peers: peers(),
        })
    }
}

/// RMS and max of one run's roll, pitch and inclination error over some rows \[deg\]
/// (infinite when an estimate was not finite there; NaN over no row).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunScores {
    /// The run.
    pub name: String,
    /// Roll error (estimate - truth) RMS \[deg\].
    pub roll_rms_deg: f64,
    /// Largest |roll error| \[deg\].
    pub roll_max_deg: f64,
    /// Pitch error RMS \[deg\].
    pub pitch_rms_deg: f64,
    /// Largest |pitch error| \[deg\].
    pub pitch_max_deg: f64,
    /// Inclination error (MODEL.md 7.9) RMS \[deg\].
    pub inclination_rms_deg: f64,
    /// Largest inclination error \[deg\].
    pub inclination_max_deg: f64,
}

/// The runs' scores over the scored rows of one phase kind.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseScores {
    /// "turning", "braking", "accelerating", "steady" (none of those) or "all".
    pub phase: String,
    /// Scored rows in it.
    pub rows: u64,
    /// Their time \[s\] (rows over the median rate).
    pub seconds: f64,
    /// Compensated, uncompensated, then the best peer when there is one.
    pub runs: Vec<RunScores>,
}

/// `report.json`'s `ride`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RideData {
    /// [`phases::PHASE_ACCEL`] \[m/s^2\].
    pub threshold_mps2: f64,
    /// [`phases::SMOOTH_S`] \[s\].
    pub smooth_s: f64,
    /// [`phases::DIFF_S`] \[s\].
    pub diff_s: f64,
    /// [`phases::MIN_PHASE_S`] \[s\].
    pub min_phase_s: f64,
    /// The phases found, by kind then time.
    pub phases: Vec<Phase>,
    /// The run with the speed.
    pub compensated: String,
    /// The same filter without it.
    pub uncompensated: String,
    /// How the uncompensated run was made.
    pub uncompensated_how: String,
    /// The best peer of the report, if it has peers.
    pub best_peer: Option<String>,
    /// Per phase kind that has scored rows, then "steady" and "all" (when they have).
    pub scores: Vec<PhaseScores>,
}

/// A phase kind's shade colour (also its swatch in the ride table).
pub fn shade_style(kind: PhaseKind) -> RGBColor {
    match kind {
        PhaseKind::Turning => RGBColor(60, 120, 230),
        PhaseKind::Braking => RGBColor(150, 70, 210),
        PhaseKind::Accelerating => RGBColor(40, 170, 70),
    }
}

/// The shades of the phases (legend label: the kind's word).
pub fn phase_shades(phases: &[Phase]) -> Vec<Shade> {
    phases
        .iter()
        .map(|p| Shade {
            from: p.from_s,
            to: p.to_s,
            colour: shade_style(p.kind),
            label: p.kind.word().into(),
        })
        .collect()
}

/// The colour of the uncompensated run (grey: the compensated one keeps its own).
const UNCOMPENSATED: RGBColor = RGBColor(90, 90, 90);

/// Sums for RMS and max of a signed error \[rad\].
#[derive(Debug, Clone, Copy, Default)]
struct Acc {
    sq: f64,
    max: f64,
    n: u64,
}

impl Acc {
    fn add(&mut self, e: f64) {
        let e = if e.is_finite() {
            e.abs()
        } else {
            f64::INFINITY
        };
        self.sq += e * e;
        self.max = self.max.max(e);
        self.n += 1;
    }
    fn rms_deg(&self) -> f64 {
        if self.n == 0 {
            return f64::NAN;
        }
        (self.sq / self.n as f64).sqrt().to_degrees()
    }
    fn max_deg(&self) -> f64 {
        if self.n == 0 {
            return f64::NAN;
        }
        self.max.to_degrees()
    }
}

/// `a - b` wrapped into (-pi, pi].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    if d > std::f64::consts::PI {
        d - std::f64::consts::TAU
    } else {
        d
    }
}

impl SpatialReport {
    /// The ride's accelerations and phases (empty without a ride).
    pub(super) fn ride_phases(&self) -> Option<(RideSignals, Vec<Phase>)> {
        let r = self.ride.as_ref()?;
        let s = phases::signals(&self.t, &r.speed, &r.gyro_z);
        let p = phases::phases(&self.t, &s);
        Some((s, p))
    }

    /// The scores of `e` over the rows where `on` holds.
    fn run_scores(&self, e: &RollPitch, on: &[bool]) -> RunScores {
        let (mut roll, mut pitch, mut inc) = (Acc::default(), Acc::default(), Acc::default());
        let tr = &self.truth;
        for k in (0..self.t.len()).filter(|&k| on[k]) {
            if !(tr.roll[k].is_finite() && tr.pitch[k].is_finite()) {
                continue;
            }
            roll.add(angle_diff(e.roll[k], tr.roll[k]));
            pitch.add(angle_diff(e.pitch[k], tr.pitch[k]));
            inc.add(inclination_error(
                e.roll[k],
                e.pitch[k],
                tr.roll[k],
                tr.pitch[k],
            ));
        }
        RunScores {
            name: e.name.clone(),
            roll_rms_deg: roll.rms_deg(),
            roll_max_deg: roll.max_deg(),
            pitch_rms_deg: pitch.rms_deg(),
            pitch_max_deg: pitch.max_deg(),
            inclination_rms_deg: inc.rms_deg(),
            inclination_max_deg: inc.max_deg(),
        }
    }

    /// The runs set side by side: compensated, uncompensated, best peer.
    fn ride_runs<'a>(&'a self, r: &'a Ride, best_peer: Option<&str>) -> Vec<&'a RollPitch> {
        let mut runs: Vec<&RollPitch> = self
            .estimates
            .iter()
            .filter(|e| e.name == r.compensated)
            .collect();
        runs.push(&r.uncompensated);
        if let Some(p) = best_peer {
            runs.extend(self.estimates.iter().filter(|e| e.name == p));
        }
        runs
    }

    /// The ride's data (scores per phase), or `None` without a ride. `best_peer` is the
    /// best of [`Ride::peers`] by the report's inclination table.
    pub(super) fn ride_data(&self, phases: &[Phase], best_peer: Option<&str>) -> Option<RideData> {
        let r = self.ride.as_ref()?;
        let scored = self.scored_rows();
        let in_kind = |kind: PhaseKind| -> Vec<bool> {
            self.t
                .iter()
                .map(|&t| {
                    phases
                        .iter()
                        .any(|p| p.kind == kind && t >= p.from_s && t <= p.to_s)
                })
                .collect()
        };
        let mut masks: Vec<(String, Vec<bool>)> = PhaseKind::ALL
            .iter()
            .map(|&k| (k.word().to_string(), in_kind(k)))
            .collect();
        let steady: Vec<bool> = (0..self.t.len())
            .map(|k| !masks.iter().any(|(_, m)| m[k]))
            .collect();
        if !phases.is_empty() {
            // without a phase, steady is all
            masks.push(("steady".into(), steady));
        }
        masks.push(("all".into(), vec![true; self.t.len()]));
        let rate = super::median_rate(&self.t).unwrap_or(f64::NAN);
        let runs = self.ride_runs(r, best_peer);
        // a kind with no scored row (no turn on a ship) is left out, not given NaN
        let scores = masks
            .into_iter()
            .filter_map(|(phase, m)| {
                let on: Vec<bool> = m.iter().zip(&scored).map(|(a, b)| *a && *b).collect();
                let rows = on.iter().filter(|x| **x).count() as u64;
                (rows > 0).then(|| PhaseScores {
                    phase,
                    rows,
                    seconds: rows as f64 / rate,
                    runs: runs.iter().map(|e| self.run_scores(e, &on)).collect(),
                })
            })
            .collect();
        Some(RideData {
            threshold_mps2: phases::PHASE_ACCEL,
            smooth_s: phases::SMOOTH_S,
            diff_s: phases::DIFF_S,
            min_phase_s: phases::MIN_PHASE_S,
            phases: phases.to_vec(),
            compensated: r.compensated.clone(),
            uncompensated: r.uncompensated.name.clone(),
            uncompensated_how: r.how.clone(),
            best_peer: best_peer.map(String::from),
            scores,
        })
    }

    /// Run `e`'s roll, pitch and inclination errors against the truth \[deg\].
    fn errors_deg(&self, e: &RollPitch) -> [Vec<f64>; 3] {
        let deg = |v: Vec<f64>| -> Vec<f64> { v.into_iter().map(f64::to_degrees).collect() };
        let tr = &self.truth;
        let n = self.t.len();
        [
            deg((0..n).map(|k| angle_diff(e.roll[k], tr.roll[k])).collect()),
            deg((0..n)
                .map(|k| angle_diff(e.pitch[k], tr.pitch[k]))
                .collect()),
            self.inclination_deg(e),
        ]
    }

    /// The ride figure: roll, pitch and inclination error of the runs, and the
    /// accelerations the phases come from, the phases and the start-up shaded.
    pub(super) fn ride_figure(
        &self,
        dir: &Path,
        data: &RideData,
        signals: &RideSignals,
        shades: &[Shade],
    ) -> Result<FigureFiles, ReportError> {
        let r = self
            .ride
            .as_ref()
            .ok_or_else(|| ReportError::Empty("ride".into()))?;
        let runs = self.ride_runs(r, data.best_peer.as_deref());
        let errors: Vec<[Vec<f64>; 3]> = runs.iter().map(|e| self.errors_deg(e)).collect();
        let mut palette = self.palette.clone();
        palette.set(&r.uncompensated.name, UNCOMPENSATED);
        palette.set("v w_z", RGBColor(60, 120, 230));
        palette.set("dv/dt", RGBColor(220, 120, 0));
        let spec = |title: String, y: &str| {
            let mut s = FigureSpec::new(&title, "time [s]", y);
            s.legend = LegendPosition::Outside;
            s.x_range = self.time_span();
            s.shades = shades.to_vec();
            s.robust = Some(crate::report::figures::RobustRange {
                skip_x: self.score_from.max(0.0),
                ..Default::default()
            });
            s
        };
        // the uncompensated run first, so that the compensated one draws on top
        let order = [1usize, 0, 2];
        let mut panels = Vec::new();
        for (i, (what, unit)) in [
            ("roll error (estimate - truth)", "roll error [deg]"),
            ("pitch error (estimate - truth)", "pitch error [deg]"),
            ("inclination error", "inclination error [deg]"),
        ]
        .into_iter()
        .enumerate()
        {
            panels.push(Panel {
                spec: spec(what.to_string(), unit),
                curves: order
                    .iter()
                    .filter(|&&j| j < runs.len())
                    .map(|&j| Curve::line(&runs[j].name, &self.t, &errors[j][i]))
                    .collect(),
            });
        }
        let mut accel = spec(
            format!(
                "what the phases are found from: v w_z (centripetal) and dv/dt, thresholds \
                 +-{} m/s^2",
                super::secs(phases::PHASE_ACCEL)
            ),
            "acceleration [m/s^2]",
        );
        accel.robust = None;
        panels.push(Panel {
            spec: accel,
            curves: vec![
                Curve::line("v w_z", &self.t, &signals.lateral),
                Curve::line("dv/dt", &self.t, &signals.longitudinal),
            ],
        });
        plot_panels(
            dir,
            "ride",
            &format!(
                "{}: {} with and without the speed, per phase of the ride",
                self.title, r.compensated
            ),
            (1200, 300),
            &panels,
            &palette,
        )
    }
}

/// The ride table: per phase, each run's inclination error RMS / max and its roll and
/// pitch max \[deg\].
pub fn ride_table(d: &RideData) -> TextTable {
    let names: Vec<String> = d
        .scores
        .first()
        .map(|s| s.runs.iter().map(|r| r.name.clone()).collect())
        .unwrap_or_default();
    let mut columns = vec!["phase".to_string(), "time [s]".to_string()];
    columns.extend(names.iter().map(|n| format!("{n}: RMS / max [deg]")));
    let rows = d
        .scores
        .iter()
        .map(|s| {
            let mut row = vec![s.phase.clone(), format!("{:.1}", s.seconds)];
            row.extend(s.runs.iter().map(|r| {
                format!(
                    "{} / {}",
                    fmt_sig(r.inclination_rms_deg),
                    fmt_sig(r.inclination_max_deg)
                )
            }));
            row
        })
        .collect();
    let thr = super::secs(d.threshold_mps2);
    let mut definitions = vec![
        (
            "phase".into(),
            format!(
                "found from the log alone (speed and gyro z, never the truth): turning where \
                 |v w_z| > {thr} m/s^2, braking where dv/dt < -{thr} m/s^2, accelerating \
                 where dv/dt > {thr} m/s^2, v and w_z smoothed by a centred {} s moving \
                 average run twice, dv/dt a centred difference over {} s; stretches under {} \
                 s dropped, gaps under it bridged; a turn while braking counts in both; \
                 steady: none of them; only the scored rows (from score_from on)",
                super::secs(d.smooth_s),
                super::secs(d.diff_s),
                super::secs(d.min_phase_s)
            ),
        ),
        (
            "RMS / max".into(),
            "of the inclination error (MODEL.md 7.9) over the phase's scored rows; \
             report.json's `ride` also has each run's roll and pitch error"
                .into(),
        ),
        (d.uncompensated.clone(), d.uncompensated_how.clone()),
    ];
    if let Some(p) = &d.best_peer {
        definitions.push((
            p.clone(),
            "the peer (IMU filter) of this report with the lowest inclination RMS over the \
             whole scored log, at its settings here (not tuned to this log)"
                .into(),
        ));
    }
    TextTable {
        heading: format!(
            "Per phase of the ride: {} with and without the speed, inclination error",
            d.compensated
        ),
        columns,
        rows,
        definitions,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_differences_wrap() {
        assert!((angle_diff(3.1, -3.1) - (6.2 - std::f64::consts::TAU)).abs() < 1e-12);
        assert_eq!(angle_diff(0.3, 0.1), 0.3 - 0.1);
    }

    #[test]
    fn scores_are_rms_and_max_of_the_rows_given() {
        let mut a = Acc::default();
        for e in [0.03_f64.to_radians(), -0.04_f64.to_radians()] {
            a.add(e);
        }
        assert!((a.rms_deg() - (0.0025_f64 / 2.0).sqrt()).abs() < 1e-12);
        assert!((a.max_deg() - 0.04).abs() < 1e-12);
        a.add(f64::NAN);
        assert!(a.rms_deg().is_infinite());
        assert!(Acc::default().rms_deg().is_nan());
    }
}
