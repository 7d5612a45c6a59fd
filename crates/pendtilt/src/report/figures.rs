//! Figures with `plotters`, each written as PNG and SVG.
//!
//! The plotting code knows no estimator: it draws named curves, and the colour of each comes
//! from a [`Palette`] (name → colour). The text uses the DejaVu Sans font embedded in the
//! binary, so figures render on a machine without system fonts.
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use serde::Serialize;

use super::palette::Palette;
use super::ReportError;

/// The embedded font (DejaVu Sans, see `assets/LICENSE-DejaVuSans.txt`).
pub const FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The font family name the figures use (registered by [`register_font`]).
const FAMILY: &str = "sans-serif";

/// Registers the embedded font with plotters under "sans-serif" (once per process).
///
/// Called by every figure function; public so that callers drawing their own figures can
/// use the same font.
pub fn register_font() -> Result<(), ReportError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, FONT_BYTES).is_ok()
            && plotters::style::register_font(FAMILY, FontStyle::Bold, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(ReportError::Invalid(
            "embedded font could not be parsed".into(),
        ))
    }
}

/// How a curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveKind {
    /// A line through the points (broken at non-finite values).
    Line,
    /// A filled circle at each point (with error bars when `y_err` is given).
    Points,
}

/// One named curve of a figure.
#[derive(Debug, Clone, Copy)]
pub struct Curve<'a> {
    /// Legend label; also the key of its colour in the palette.
    pub name: &'a str,
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates, as many as `x`.
    pub y: &'a [f64],
    /// Line or points.
    pub kind: CurveKind,
    /// Line width or point radius \[px\].
    pub width: u32,
    /// Half-length of a vertical error bar per point (`Points` only), as many as `x`.
    pub y_err: Option<&'a [f64]>,
}

impl<'a> Curve<'a> {
    /// A line of width 2.
    pub fn line(name: &'a str, x: &'a [f64], y: &'a [f64]) -> Self {
        Self {
            name,
            x,
            y,
            kind: CurveKind::Line,
            width: 2,
            y_err: None,
        }
    }

    /// Points of radius 4.
    pub fn points(name: &'a str, x: &'a [f64], y: &'a [f64]) -> Self {
        Self {
            name,
            x,
            y,
            kind: CurveKind::Points,
            width: 4,
            y_err: None,
        }
    }
}

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegendPosition {
    /// Top left of the plot area.
    UpperLeft,
    /// Top right.
    UpperRight,
    /// Bottom left.
    LowerLeft,
    /// Bottom right.
    LowerRight,
}

/// Title, axis labels and size of a figure.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureSpec {
    /// Title, drawn at the top (and searchable in the SVG).
    pub title: String,
    /// Abscissa label, with its unit.
    pub x_label: String,
    /// Ordinate label, with its unit.
    pub y_label: String,
    /// Width \[px\] of the PNG (and of the SVG's view box).
    pub width: u32,
    /// Height \[px\].
    pub height: u32,
    /// Fixed ordinate range; `None`: fit the data with a 5% margin.
    pub y_range: Option<(f64, f64)>,
    /// Legend corner.
    pub legend: LegendPosition,
}

impl FigureSpec {
    /// A 1200 x 675 figure, legend top left.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            width: 1200,
            height: 675,
            y_range: None,
            legend: LegendPosition::UpperLeft,
        }
    }
}

/// The files of one figure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FigureFiles {
    /// The figure's title.
    pub title: String,
    /// PNG file.
    pub png: PathBuf,
    /// SVG file.
    pub svg: PathBuf,
    /// Pixel width of the PNG.
    pub width: u32,
    /// Pixel height of the PNG.
    pub height: u32,
}

/// A curve reduced to what is drawn: finite runs of points (lines), or points with bars.
struct Prepared {
    name: String,
    colour: RGBColor,
    kind: CurveKind,
    width: u32,
    runs: Vec<Vec<(f64, f64)>>,
    bars: Vec<(f64, f64, f64)>,
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

fn prepare(curve: &Curve, palette: &Palette, width_px: u32) -> Result<Prepared, ReportError> {
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

fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if hi > lo {
        let m = 0.05 * (hi - lo);
        (lo - m, hi + m)
    } else {
        (lo - 1.0, hi + 1.0)
    }
}

fn ranges(prepared: &[Prepared], spec: &FigureSpec) -> Option<((f64, f64), (f64, f64))> {
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
    let yr = match spec.y_range {
        Some((a, b)) if a.is_finite() && b.is_finite() && b > a => (a, b),
        _ => padded(y0, y1),
    };
    Some((xr, yr))
}

/// Cuts line runs to the ordinate range \[y0, y1\]: a segment crossing a bound ends (or
/// starts) on it, and the part outside is not drawn (plotters would otherwise flatten
/// out-of-range points onto the frame, which reads as data).
fn clip_runs(runs: &[Vec<(f64, f64)>], (y0, y1): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
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

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    spec: &FigureSpec,
    prepared: &[Prepared],
    (xr, yr): ((f64, f64), (f64, f64)),
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(&spec.title, (FAMILY, 26).into_font())
        .margin(18)
        .x_label_area_size(60)
        .y_label_area_size(80)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(spec.x_label.as_str())
        .y_desc(spec.y_label.as_str())
        .axis_desc_style((FAMILY, 20))
        .label_style((FAMILY, 16))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()
        .map_err(e)?;
    for p in prepared {
        let style = p.colour.stroke_width(p.width);
        let colour = p.colour;
        let mut labelled = false;
        match p.kind {
            CurveKind::Line => {
                for run in &p.runs {
                    let ann = chart
                        .draw_series(LineSeries::new(run.iter().copied(), style))
                        .map_err(e)?;
                    // one legend entry per curve, on its first run
                    if !labelled {
                        ann.label(p.name.as_str()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                        });
                        labelled = true;
                    }
                }
            }
            CurveKind::Points => {
                chart
                    .draw_series(p.bars.iter().map(|&(x, lo, hi)| {
                        PathElement::new(vec![(x, lo), (x, hi)], colour.stroke_width(1))
                    }))
                    .map_err(e)?;
                let r = p.width;
                let ann = chart
                    .draw_series(
                        p.runs
                            .iter()
                            .flatten()
                            .map(|&pt| Circle::new(pt, r, colour.filled())),
                    )
                    .map_err(e)?;
                ann.label(p.name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 12, y), 4, colour.filled()));
                labelled = true;
            }
        }
        if !labelled {
            // a curve with no finite point still appears in the legend, so it is not
            // silently missing
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
                .map_err(e)?
                .label(format!("{} (no data)", p.name))
                .legend(move |(x, y)| Circle::new((x + 12, y), 4, colour.stroke_width(1)));
        }
    }
    let pos = match spec.legend {
        LegendPosition::UpperLeft => SeriesLabelPosition::UpperLeft,
        LegendPosition::UpperRight => SeriesLabelPosition::UpperRight,
        LegendPosition::LowerLeft => SeriesLabelPosition::LowerLeft,
        LegendPosition::LowerRight => SeriesLabelPosition::LowerRight,
    };
    chart
        .configure_series_labels()
        .position(pos)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(120, 120, 120))
        .label_font((FAMILY, 18))
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

fn check_stem(stem: &str) -> Result<(), ReportError> {
    let ok = !stem.is_empty()
        && stem
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
        && !stem.starts_with('.');
    if ok {
        Ok(())
    } else {
        Err(ReportError::Invalid(format!(
            "figure name {stem:?}: use letters, digits, '_', '-', '.'"
        )))
    }
}

/// Draws named curves and writes `dir/stem.png` and `dir/stem.svg`.
///
/// Lines are broken at non-finite values and thinned to the screen resolution
/// ([`decimate_min_max`]). Errors: a bad file stem, mismatched lengths, no finite point at all,
/// a zero size, or the backend failing to write.
pub fn plot_curves(
    dir: &Path,
    stem: &str,
    spec: &FigureSpec,
    curves: &[Curve],
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    check_stem(stem)?;
    register_font()?;
    if spec.width < 200 || spec.height < 150 {
        return Err(ReportError::Invalid(format!(
            "figure size {}x{} is under 200x150",
            spec.width, spec.height
        )));
    }
    if curves.is_empty() {
        return Err(ReportError::Empty(format!("figure {stem}: curve list")));
    }
    let prepared = curves
        .iter()
        .map(|c| prepare(c, palette, spec.width))
        .collect::<Result<Vec<_>, _>>()?;
    let r = ranges(&prepared, spec)
        .ok_or_else(|| ReportError::Empty(format!("figure {stem}: no finite point")))?;
    let mut prepared = prepared;
    for p in prepared.iter_mut() {
        if p.kind == CurveKind::Line {
            p.runs = clip_runs(&p.runs, r.1);
        } else {
            let (y0, y1) = r.1;
            for run in p.runs.iter_mut() {
                run.retain(|q| q.1 >= y0 && q.1 <= y1);
            }
        }
    }
    std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let size = (spec.width, spec.height);
    let plot_err = |path: &Path| {
        let path = path.display().to_string();
        move |message| ReportError::Plot { path, message }
    };
    draw(
        BitMapBackend::new(&png, size).into_drawing_area(),
        spec,
        &prepared,
        r,
    )
    .map_err(plot_err(&png))?;
    draw(
        SVGBackend::new(&svg, size).into_drawing_area(),
        spec,
        &prepared,
        r,
    )
    .map_err(plot_err(&svg))?;
    Ok(FigureFiles {
        title: spec.title.clone(),
        png,
        svg,
        width: spec.width,
        height: spec.height,
    })
}

/// Angles \[deg\] against time \[s\]: one line per named series, all on the time axis `t`.
///
/// The series are drawn in the order given (put the truth first so the estimates draw on
/// top of it).
pub fn plot_time_series(
    dir: &Path,
    stem: &str,
    title: &str,
    t: &[f64],
    series: &[(&str, &[f64])],
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    let spec = FigureSpec::new(title, "time [s]", "angle [deg]");
    let curves: Vec<Curve> = series.iter().map(|(n, y)| Curve::line(n, t, y)).collect();
    plot_curves(dir, stem, &spec, &curves, palette)
}

/// Errors (estimate - truth) \[deg\] against time \[s\], one line per named estimate, with a
/// black zero line. Values in degrees.
///
/// Errors: an estimate whose length differs from the truth's, plus those of [`plot_curves`].
pub fn plot_errors(
    dir: &Path,
    stem: &str,
    title: &str,
    t: &[f64],
    truth: &[f64],
    estimates: &[(&str, &[f64])],
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    let mut errors = Vec::with_capacity(estimates.len());
    for (name, est) in estimates {
        if est.len() != truth.len() {
            return Err(ReportError::LengthMismatch {
                name: name.to_string(),
                expected: truth.len(),
                got: est.len(),
            });
        }
        errors.push(
            est.iter()
                .zip(truth)
                .map(|(e, x)| e - x)
                .collect::<Vec<f64>>(),
        );
    }
    let spec = FigureSpec::new(title, "time [s]", "error (estimate - truth) [deg]");
    let curves: Vec<Curve> = estimates
        .iter()
        .zip(&errors)
        .map(|((n, _), y)| Curve::line(n, t, y))
        .collect();
    plot_curves(dir, stem, &spec, &curves, palette)
}

/// A plain x-y figure: each named series has its own abscissae; labels carry the units.
pub fn plot_xy(
    dir: &Path,
    stem: &str,
    spec: &FigureSpec,
    series: &[(&str, &[f64], &[f64])],
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    let curves: Vec<Curve> = series
        .iter()
        .map(|(n, x, y)| Curve::line(n, x, y))
        .collect();
    plot_curves(dir, stem, spec, &curves, palette)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_the_envelope_and_the_end() {
        let pts: Vec<(f64, f64)> = (0..1000)
            .map(|k| (k as f64, if k == 537 { 9.0 } else { (k % 7) as f64 }))
            .collect();
        let d = decimate_min_max(&pts, 10);
        assert!(d.len() <= 2 * 100 + 1);
        assert!(d.contains(&(537.0, 9.0)));
        assert_eq!(d.last(), pts.last());
        assert_eq!(d.first(), pts.first());
        // x stays increasing
        assert!(d.windows(2).all(|w| w[1].0 > w[0].0));
    }

    #[test]
    fn lines_are_clipped_to_the_range_not_flattened() {
        let runs = vec![vec![
            (0.0, 0.0),
            (1.0, 2.0),
            (2.0, 4.0),
            (3.0, 0.0),
            (4.0, -4.0),
        ]];
        let c = clip_runs(&runs, (-1.0, 3.0));
        // inside 0..3 until x = 1.5, back in at x = 2.25 down to x = 3.25 (y = -1)
        assert_eq!(c.len(), 2);
        assert_eq!(c[0], vec![(0.0, 0.0), (1.0, 2.0), (1.5, 3.0)]);
        assert_eq!(c[1], vec![(2.25, 3.0), (3.0, 0.0), (3.25, -1.0)]);
        assert!(c.iter().flatten().all(|p| p.1 >= -1.0 && p.1 <= 3.0));
    }

    #[test]
    fn bad_names_and_empty_data_are_errors() {
        let dir = std::env::temp_dir();
        let p = Palette::default();
        let spec = FigureSpec::new("t", "x", "y");
        let x = [0.0, 1.0];
        let y = [f64::NAN, f64::NAN];
        assert!(plot_curves(&dir, "../evil", &spec, &[Curve::line("a", &x, &x)], &p).is_err());
        assert!(matches!(
            plot_curves(&dir, "nan_only", &spec, &[Curve::line("a", &x, &y)], &p),
            Err(ReportError::Empty(_))
        ));
        assert!(matches!(
            plot_curves(&dir, "short", &spec, &[Curve::line("a", &x, &y[..1])], &p),
            Err(ReportError::LengthMismatch { .. })
        ));
    }
}
