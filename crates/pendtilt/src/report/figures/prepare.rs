//! Curves reduced to what is drawn: finite runs of points, thinned to the figure's width.
use plotters::prelude::RGBColor;

use super::{Curve, CurveKind};
use crate::report::palette::Palette;
use crate::report::ReportError;

/// A curve reduced to what is drawn: finite runs of points (lines), or points with bars.
pub(super) struct Prepared {
    pub(super) name: String,
    pub(super) colour: RGBColor,
    pub(super) kind: CurveKind,
    pub(super) width: u32,
    pub(super) runs: Vec<Vec<(f64, f64)>>,
    pub(super) bars: Vec<(f64, f64, f64)>,
}

/// Keeps, of every bucket of `bucket` consecutive points, the lowest and the highest (in
/// their order): the drawn envelope is unchanged at screen resolution, the files stay small.
pub fn decimate_min_max(points: &[(f64, f64)], bucket: usize) -> Vec<(f64, f64)> {
    if bucket <= 2 || points.len() <= 2 * bucket {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity(2 * points.len() / bucket + 2);
    for chunk in points.chunks(bucket) {
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[lo].1 {
                lo = i;
            }
            if p.1 > chunk[hi].1 {
                hi = i;
            }
        }
        let (a, b) = (lo.min(hi), lo.max(hi));
        out.push(chunk[a]);
        if b != a {
            out.push(chunk[b]);
        }
    }
    // keep the very last point so the line reaches the end of the record
    if out.last() != points.last() {
        out.push(points[points.len() - 1]);
    }
    out
}

pub(super) fn prepare(
    curve: &Curve,
    palette: &Palette,
    width_px: u32,
) -> Result<Prepared, ReportError> {
    if curve.x.len() != curve.y.len() {
        return Err(ReportError::LengthMismatch {
            name: curve.name.to_string(),
            expected: curve.x.len(),
            got: curve.y.len(),
        });
    }
    if let Some(e) = curve.y_err {
        if e.len() != curve.x.len() {
            return Err(ReportError::LengthMismatch {
                name: format!("{} error bars", curve.name),
                expected: curve.x.len(),
                got: e.len(),
            });
        }
    }
    let mut runs = Vec::new();
    let mut bars = Vec::new();
    match curve.kind {
        CurveKind::Line => {
            let mut run = Vec::new();
            for (&x, &y) in curve.x.iter().zip(curve.y) {
                if x.is_finite() && y.is_finite() {
                    run.push((x, y));
                } else if !run.is_empty() {
                    runs.push(std::mem::take(&mut run));
                }
            }
            if !run.is_empty() {
                runs.push(run);
            }
            let total: usize = runs.iter().map(Vec::len).sum();
            let bucket = total / (2 * width_px as usize).max(1);
            runs = runs.iter().map(|r| decimate_min_max(r, bucket)).collect();
        }
        CurveKind::Points => {
            let pts: Vec<(f64, f64)> = curve
                .x
                .iter()
                .zip(curve.y)
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .map(|(x, y)| (*x, *y))
                .collect();
            if let Some(err) = curve.y_err {
                for ((&x, &y), &e) in curve.x.iter().zip(curve.y).zip(err) {
                    if x.is_finite() && y.is_finite() && e.is_finite() {
                        bars.push((x, y - e.abs(), y + e.abs()));
                    }
                }
            }
            runs.push(pts);
        }
    }
    Ok(Prepared {
        name: curve.name.to_string(),
        colour: palette.colour(curve.name),
        kind: curve.kind,
        width: curve.width.max(1),
        runs,
        bars,
    })
}
