//! The three figures of a 3-D report, one panel per estimator each (eight lines on one
//! set of axes cannot be told apart): roll and pitch against the truth, and the
//! inclination error.
use std::path::Path;

use super::{InclinationRow, RollPitch, SpatialReport};
use crate::report::claims::fmt_sig;
use crate::report::figures::{
    plot_panels, Curve, FigureFiles, FigureSpec, LegendPosition, Panel, RobustRange, Shade,
};
use crate::report::ReportError;

/// Width of a figure and height of one panel \[px\].
const PANEL: (u32, u32) = (1200, 270);

/// Which angle a figure shows.
#[derive(Debug, Clone, Copy)]
enum Angle {
    Roll,
    Pitch,
}

impl Angle {
    fn word(self) -> &'static str {
        match self {
            Angle::Roll => "roll",
            Angle::Pitch => "pitch",
        }
    }

    fn of(self, s: &RollPitch) -> &[f64] {
        match self {
            Angle::Roll => &s.roll,
            Angle::Pitch => &s.pitch,
        }
    }
}

fn degrees(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_degrees()).collect()
}

impl SpatialReport {
    /// The first and last finite time: the abscissa of every figure, so that their time
    /// ticks line up (the pitch figure, its first row without a finite pitch, once
    /// started 1 ms later and ticked at other times than the roll figure).
    pub(super) fn time_span(&self) -> Option<(f64, f64)> {
        let first = self.t.iter().copied().find(|t| t.is_finite())?;
        let last = self.t.iter().rev().copied().find(|t| t.is_finite())?;
        (last > first).then_some((first, last))
    }

    /// Draws `roll`, `pitch` and `inclination` (PNG and SVG) into `dir`, `shades` behind
    /// every panel ([`SpatialReport::shades`]); returns each with its caption. `rows` are
    /// the scores, in estimator order (for the panel titles).
    pub(super) fn draw(
        &self,
        dir: &Path,
        rows: &[InclinationRow],
        shades: &[Shade],
    ) -> Result<Vec<(FigureFiles, String)>, ReportError> {
        let from = super::secs(self.score_from);
        let shaded = shade_words(shades);
        let scaling = format!(
            "Each panel's ordinate covers 0.5-99.5 % of its points from {from} s after the \
             first row on (the start-up before that is left out of the scaling, not out of \
             the plot), widened by a quarter, and the whole truth"
        );
        let mut out = Vec::new();
        for angle in [Angle::Roll, Angle::Pitch] {
            let f = self.angle_figure(dir, angle, shades)?;
            let caption = format!(
                "{} of every estimator (colour) against the true {} (black), in degrees, one \
                 panel per estimator. {scaling}.{shaded}{}",
                capitalised(angle.word()),
                angle.word(),
                beyond(&f)
            );
            out.push((f, caption));
        }
        let f = self.inclination_figure(dir, rows, shades)?;
        let caption = format!(
            "Inclination error (the angle between the estimated and the true up direction, \
             MODEL.md 7.9) of every estimator, in degrees; each panel's title gives its RMS \
             and max over the scored rows (t >= t0 + {from} s), as in the table. Each \
             ordinate runs from 0 to the largest error from t0 + {from} s on, or to 1.5 times \
             the 99.5th percentile there when a few spikes reach higher.{shaded}{}",
            beyond(&f)
        );
        out.push((f, caption));
        Ok(out)
    }

    /// Roll or pitch \[deg\]: per estimator, the truth and its estimate.
    fn angle_figure(
        &self,
        dir: &Path,
        angle: Angle,
        shades: &[Shade],
    ) -> Result<FigureFiles, ReportError> {
        let truth = degrees(angle.of(&self.truth));
        let est: Vec<Vec<f64>> = self
            .estimates
            .iter()
            .map(|e| degrees(angle.of(e)))
            .collect();
        let robust = RobustRange {
            skip_x: self.score_from.max(0.0),
            ..RobustRange::default()
        };
        let panels: Vec<Panel> = self
            .estimates
            .iter()
            .zip(&est)
            .map(|(e, v)| {
                let mut spec =
                    FigureSpec::new(&e.name, "time [s]", &format!("{} [deg]", angle.word()));
                spec.robust = Some(robust);
                spec.x_range = self.time_span();
                spec.legend = LegendPosition::Outside;
                spec.shades = shades.to_vec();
                Panel {
                    spec,
                    // the truth on top, thin: visible through a noisy estimate, and an
                    // estimate on the truth still shows beside it
                    curves: vec![
                        Curve::line(&e.name, &self.t, v),
                        Curve::reference("truth", &self.t, &truth, 1),
                    ],
                }
            })
            .collect();
        plot_panels(
            dir,
            angle.word(),
            &format!(
                "{}: {}, every estimator against the truth (black)",
                self.title,
                angle.word()
            ),
            PANEL,
            &panels,
            &self.palette,
        )
    }

    /// Inclination error \[deg\] per estimator, the ordinate from 0 ([`error_ceiling`]).
    fn inclination_figure(
        &self,
        dir: &Path,
        rows: &[InclinationRow],
        shades: &[Shade],
    ) -> Result<FigureFiles, ReportError> {
        let scored = self.scored_rows();
        let errors: Vec<Vec<f64>> = self
            .estimates
            .iter()
            .map(|e| self.inclination_deg(e))
            .collect();
        let panels: Vec<Panel> = self
            .estimates
            .iter()
            .zip(&errors)
            .zip(rows)
            .map(|((e, v), r)| {
                let mut spec = FigureSpec::new(
                    &format!(
                        "{}: RMS {} deg, max {} deg",
                        e.name,
                        fmt_sig(r.rms_deg),
                        fmt_sig(r.max_deg)
                    ),
                    "time [s]",
                    "inclination error [deg]",
                );
                let top = error_ceiling(v, &scored);
                // a little below 0, so that a zero error is drawn on the plot, not on the
                // frame
                spec.y_range = Some((-0.02 * top, top));
                spec.robust = None;
                spec.x_range = self.time_span();
                spec.legend = LegendPosition::Outside;
                spec.shades = shades.to_vec();
                Panel {
                    spec,
                    curves: vec![Curve::line(&e.name, &self.t, v)],
                }
            })
            .collect();
        plot_panels(
            dir,
            "inclination",
            &format!("{}: inclination error of every estimator", self.title),
            PANEL,
            &panels,
            &self.palette,
        )
    }
}

/// The top of an error panel: the largest error of the scored rows (plus 5 %), or 1.5
/// times their 99.5th percentile when the largest is beyond that (a few spikes, cut at the
/// frame and counted); at least 0.001 deg (an error of exactly zero still gets an axis).
fn error_ceiling(e: &[f64], scored: &[bool]) -> f64 {
    let mut v: Vec<f64> = e
        .iter()
        .zip(scored)
        .filter(|(x, on)| **on && x.is_finite())
        .map(|(x, _)| *x)
        .collect();
    if v.is_empty() {
        return 1.0;
    }
    v.sort_by(f64::total_cmp);
    let max = v[v.len() - 1];
    let p = v[((v.len() - 1) as f64 * 0.995).round() as usize];
    let top = if max <= 1.5 * p { 1.05 * max } else { 1.5 * p };
    top.max(1e-3)
}

/// " Shaded: the start-up before t0 + 5 s (not scored, grey), turning (blue), ..." for a
/// caption, or "" without shades.
fn shade_words(shades: &[Shade]) -> String {
    let mut seen: Vec<&str> = Vec::new();
    for s in shades {
        if !seen.contains(&s.label.as_str()) {
            seen.push(&s.label);
        }
    }
    if seen.is_empty() {
        return String::new();
    }
    format!(
        " Shaded, as the legend beside each panel says: {}.",
        seen.join(", ")
    )
}

fn capitalised(w: &str) -> String {
    let mut c = w.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// " N points beyond the ordinate axes (...)" when the figure cut any, else "".
pub(super) fn beyond(f: &FigureFiles) -> String {
    match f.beyond_total() {
        0 => String::new(),
        n => {
            let panels: Vec<String> = f
                .axes
                .iter()
                .filter(|a| a.beyond.total() > 0)
                .map(|a| {
                    let name = a.title.split(':').next().unwrap_or(&a.title);
                    format!("{name} {}", a.beyond.total())
                })
                .collect();
            format!(
                " {n} point{} beyond the ordinate axes, cut at the frame and marked red \
                 ({}): the start-up, or an estimator far off.",
                if n == 1 { "" } else { "s" },
                panels.join(", ")
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ceiling_follows_the_scored_rows_and_cuts_lone_spikes() {
        // the start-up (unscored) is left out
        let e = [50.0, 1.0, 2.0, 1.5];
        let on = [false, true, true, true];
        assert!((error_ceiling(&e, &on) - 2.1).abs() < 1e-12);
        // one spike among 1000 rows: 1.5 x the 99.5th percentile
        let mut e = vec![1.0; 1000];
        e[500] = 40.0;
        assert!((error_ceiling(&e, &[true; 1000]) - 1.5).abs() < 1e-12);
        assert_eq!(error_ceiling(&[0.0, 0.0], &[true, true]), 1e-3);
    }
}
