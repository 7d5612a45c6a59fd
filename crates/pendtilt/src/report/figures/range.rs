//! The ordinate range of a set of axes: from the bulk of the data ([`RobustRange`]), and
//! what lies beyond it ([`Beyond`], the excursion marks, lines cut at the frame).
use serde::Serialize;

use super::prepare::Prepared;
use super::Curve;

/// An ordinate range from the bulk of the data: the `lo_pct`-`hi_pct` percentiles of every
/// curve's points after the first `skip_x` of the abscissa (a start-up transient), widened by
/// `margin` times their spread. Data inside that is drawn whole; what lies beyond is cut at
/// the frame, marked with a triangle at the edge and counted in a note on the plot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobustRange {
    /// Start of the abscissa left out of the percentiles (s on a time axis). Default 1.
    pub skip_x: f64,
    /// Lower percentile \[%\]. Default 0.5.
    pub lo_pct: f64,
    /// Upper percentile \[%\]. Default 99.5.
    pub hi_pct: f64,
    /// Widening beyond the percentiles, as a fraction of their spread. Default 0.25 (a
    /// sine's peaks, 0.5 % of its samples, stay on the plot).
    pub margin: f64,
}

impl Default for RobustRange {
    fn default() -> Self {
        Self {
            skip_x: 1.0,
            lo_pct: 0.5,
            hi_pct: 99.5,
            margin: 0.25,
        }
    }
}

/// The points of a figure's curves that lie beyond its ordinate axis (cut at the frame).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Beyond {
    /// Points above the axis.
    pub above: usize,
    /// Points below it.
    pub below: usize,
    /// The highest of them.
    pub highest: Option<f64>,
    /// The lowest of them.
    pub lowest: Option<f64>,
}

impl Beyond {
    /// Points beyond the axis in all.
    pub fn total(&self) -> usize {
        self.above + self.below
    }

    /// The note drawn on the plot ("12 points beyond the axis: 10 above (max 35.2), 2
    /// below (min -31)"), or `None` when every point is shown.
    pub fn note(&self) -> Option<String> {
        if self.total() == 0 {
            return None;
        }
        let mut parts = Vec::new();
        if let (n @ 1.., Some(v)) = (self.above, self.highest) {
            parts.push(format!(
                "{n} above (max {})",
                crate::report::claims::fmt_sig(v)
            ));
        }
        if let (n @ 1.., Some(v)) = (self.below, self.lowest) {
            parts.push(format!(
                "{n} below (min {})",
                crate::report::claims::fmt_sig(v)
            ));
        }
        Some(format!(
            "{} point{} beyond the axis: {}",
            self.total(),
            if self.total() == 1 { "" } else { "s" },
            parts.join(", ")
        ))
    }
}

pub(super) fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if hi > lo {
        let m = 0.05 * (hi - lo);
        (lo - m, hi + m)
    } else {
        (lo - 1.0, hi + 1.0)
    }
}

/// Cuts line runs to the ordinate range \[y0, y1\]: a segment crossing a bound ends (or
/// starts) on it, and the part outside is not drawn (plotters would otherwise flatten
/// out-of-range points onto the frame, which reads as data).
pub(super) fn clip_runs(runs: &[Vec<(f64, f64)>], (y0, y1): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let inside = |y: f64| y >= y0 && y <= y1;
    // point where the segment a-b meets the bound it crosses towards b
    let cross = |a: (f64, f64), b: (f64, f64), bound: f64| {
        let s = (bound - a.1) / (b.1 - a.1);
        (a.0 + s * (b.0 - a.0), bound)
    };
    let mut out = Vec::new();
    for run in runs {
        let mut cur: Vec<(f64, f64)> = Vec::new();
        for (i, &p) in run.iter().enumerate() {
            let prev = if i > 0 { Some(run[i - 1]) } else { None };
            match (prev, inside(p.1)) {
                (None, true) => cur.push(p),
                (None, false) => {}
                (Some(a), true) => {
                    if !inside(a.1) {
                        let bound = if a.1 > y1 { y1 } else { y0 };
                        cur.push(cross(a, p, bound));
                    }
                    cur.push(p);
                }
                (Some(a), false) => {
                    if inside(a.1) {
                        let bound = if p.1 > y1 { y1 } else { y0 };
                        cur.push(cross(a, p, bound));
                        out.push(std::mem::take(&mut cur));
                    } else if (a.1 > y1 && p.1 < y0) || (a.1 < y0 && p.1 > y1) {
                        // jumps clean across the range
                        let (ba, bp) = if a.1 > y1 { (y1, y0) } else { (y0, y1) };
                        out.push(vec![cross(a, p, ba), cross(a, p, bp)]);
                    }
                }
            }
        }
        if !cur.is_empty() {
            out.push(cur);
        }
    }
    out
}

/// The x range and the full y range of the prepared points (bars included); `None` when
/// there is no finite point.
pub(super) fn data_extent(prepared: &[Prepared]) -> Option<((f64, f64), (f64, f64))> {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in prepared {
        for &(x, y) in p.runs.iter().flatten() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        for &(x, lo, hi) in &p.bars {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(lo);
            y1 = y1.max(hi);
        }
    }
    if x0 > x1 {
        return None;
    }
    let xr = if x1 > x0 {
        (x0, x1)
    } else {
        (x0 - 1.0, x1 + 1.0)
    };
    Some((xr, (y0, y1)))
}

/// The `pct` percentile of sorted values (nearest rank).
pub(super) fn percentile(sorted: &[f64], pct: f64) -> f64 {
    let i = (pct / 100.0 * (sorted.len() - 1) as f64).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// `full` (the data's y extent) narrowed to the robust limits of `r` over the raw curves,
/// widened to cover every point of a curve drawn whole ([`Curve::whole`], the truth:
/// before, a 10 s 3-D report's roll axis, ranged on its last 5 s, cut the truth's first
/// seconds off at the frame); `full` itself when fewer than 20 points follow the start-up.
pub(super) fn robust_y(curves: &[Curve], full: (f64, f64), r: &RobustRange) -> (f64, f64) {
    let x_first = curves
        .iter()
        .flat_map(|c| c.x.iter().copied())
        .filter(|x| x.is_finite())
        .fold(f64::INFINITY, f64::min);
    let mut ys: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.x.iter().zip(c.y))
        .filter(|(x, y)| x.is_finite() && y.is_finite() && **x >= x_first + r.skip_x)
        .map(|(_, y)| *y)
        .collect();
    if ys.len() < 20 {
        return full;
    }
    ys.sort_by(f64::total_cmp);
    let (lo, hi) = (percentile(&ys, r.lo_pct), percentile(&ys, r.hi_pct));
    let spread = hi - lo;
    let (mut a, mut b) = (lo - r.margin * spread, hi + r.margin * spread);
    for y in curves
        .iter()
        .filter(|c| c.whole)
        .flat_map(|c| c.y.iter())
        .filter(|y| y.is_finite())
    {
        a = a.min(*y);
        b = b.max(*y);
    }
    (full.0.max(a), full.1.min(b))
}

/// The raw points of `curves` beyond `(y0, y1)`, counted.
pub(super) fn count_beyond(curves: &[Curve], (y0, y1): (f64, f64)) -> Beyond {
    let mut b = Beyond::default();
    for c in curves {
        for (x, &y) in c.x.iter().zip(c.y) {
            if !(x.is_finite() && y.is_finite()) {
                continue;
            }
            if y > y1 {
                b.above += 1;
                b.highest = Some(b.highest.map_or(y, |h: f64| h.max(y)));
            } else if y < y0 {
                b.below += 1;
                b.lowest = Some(b.lowest.map_or(y, |l: f64| l.min(y)));
            }
        }
    }
    b
}

/// Where to mark excursions: for every stretch of a line beyond `(y0, y1)`, the abscissa
/// of its extreme point and whether it is above; at most `cap` of them.
pub(super) fn excursion_marks(
    prepared: &[Prepared],
    (y0, y1): (f64, f64),
    cap: usize,
) -> Vec<(f64, bool)> {
    let mut marks = Vec::new();
    for p in prepared {
        for run in &p.runs {
            let mut best: Option<(f64, f64, bool)> = None;
            for &(x, y) in run {
                let side = if y > y1 {
                    Some(true)
                } else if y < y0 {
                    Some(false)
                } else {
                    None
                };
                match (side, best) {
                    (Some(up), Some((_, by, bup))) if up == bup => {
                        if (up && y > by) || (!up && y < by) {
                            best = Some((x, y, up));
                        }
                    }
                    (Some(up), other) => {
                        if let Some((bx, _, bup)) = other {
                            marks.push((bx, bup));
                        }
                        best = Some((x, y, up));
                    }
                    (None, Some((bx, _, bup))) => {
                        marks.push((bx, bup));
                        best = None;
                    }
                    (None, None) => {}
                }
            }
            if let Some((bx, _, bup)) = best {
                marks.push((bx, bup));
            }
        }
    }
    if marks.len() > cap {
        let step = marks.len().div_ceil(cap);
        marks = marks.into_iter().step_by(step).collect();
    }
    marks
}
