//! Figures with `plotters`, each written as PNG and SVG.
//!
//! The plotting code knows no estimator: it draws named curves, and the colour of each comes
//! from a [`Palette`] (name → colour). The text uses the DejaVu Sans font embedded in the
//! binary, so figures render on a machine without system fonts.
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::prelude::*;
use serde::Serialize;

use super::interactive::{Plot, PlotShade};
use super::palette::Palette;
use super::ReportError;

mod draw;
mod prepare;
mod range;
use draw::{render, Axis};
pub use prepare::decimate_min_max;
use prepare::prepare;
use range::{count_beyond, data_extent, excursion_marks, padded, robust_y};
pub use range::{Beyond, RobustRange};

/// The embedded font (DejaVu Sans, see `assets/LICENSE-DejaVuSans.txt`).
pub const FONT_BYTES: &[u8] = include_bytes!("../../../assets/DejaVuSans.ttf");

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
    /// Drawn whole: a reference without a start-up (the truth), whose every point the
    /// robust ordinate range ([`RobustRange`]) covers.
    pub whole: bool,
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
            whole: false,
        }
    }

    /// The truth (or another reference) as a line of width `width`, drawn whole
    /// ([`Self::whole`]).
    pub fn reference(name: &'a str, x: &'a [f64], y: &'a [f64], width: u32) -> Self {
        Self {
            width,
            whole: true,
            ..Self::line(name, x, y)
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
            whole: false,
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
    /// Outside the plot area, in a column on its right (with the shades' labels and the
    /// note on points beyond the axis under it): covers no data.
    Outside,
}

/// A stretch of the abscissa shaded behind the curves (a phase of a ride, the unscored
/// start-up), listed in the legend by its label.
#[derive(Debug, Clone, PartialEq)]
pub struct Shade {
    /// Start, in abscissa units.
    pub from: f64,
    /// End.
    pub to: f64,
    /// Its fill (drawn with [`SHADE_ALPHA`]).
    pub colour: RGBColor,
    /// Legend label (shades with the same label share one entry).
    pub label: String,
}

/// Opacity of a [`Shade`]: light enough that the grid and the curves read through it.
pub const SHADE_ALPHA: f64 = 0.22;

/// Width of the [`LegendPosition::Outside`] column \[px\].
const OUTSIDE_W: u32 = 210;

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
    /// Fixed abscissa range; `None`: the data's. Figures meant to be read one above the
    /// other (a 3-D report's roll and pitch) share one, and so their time ticks.
    pub x_range: Option<(f64, f64)>,
    /// Fixed ordinate range; `None`: fit the data with a 5% margin, within `robust`.
    pub y_range: Option<(f64, f64)>,
    /// How far the ordinate range may follow the data when it is not fixed: `None`, every
    /// point; default, robust percentiles after the start-up ([`RobustRange`]), the rest
    /// marked as beyond the axis.
    pub robust: Option<RobustRange>,
    /// Legend corner.
    pub legend: LegendPosition,
    /// Stretches shaded behind the curves, in drawing order.
    pub shades: Vec<Shade>,
}

/// One drawn set of axes of a figure: its ordinate range and what lies beyond it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisInfo {
    /// The panel's title.
    pub title: String,
    /// The abscissa range drawn.
    pub x_range: (f64, f64),
    /// The ordinate range drawn.
    pub y_range: (f64, f64),
    /// The points cut at the frame.
    pub beyond: Beyond,
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
            x_range: None,
            y_range: None,
            robust: Some(RobustRange::default()),
            legend: LegendPosition::UpperLeft,
            shades: Vec::new(),
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
    /// One entry per set of axes (one, or one per panel), top to bottom.
    pub axes: Vec<AxisInfo>,
    /// The interactive plots of the page, one per set of axes, top to bottom; empty when
    /// a set of axes is not lines on one shared, sorted abscissa (points, x-y curves).
    #[serde(skip)]
    pub plots: Vec<Plot>,
}

impl FigureFiles {
    /// Points beyond the axes of every panel, in all.
    pub fn beyond_total(&self) -> usize {
        self.axes.iter().map(|a| a.beyond.total()).sum()
    }
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

/// Tick labels as plotters writes them, but never "-0.0" (a tick a rounding error below
/// zero).
pub fn tick_label(v: &f64) -> String {
    let s = plotters::data::float::FloatPrettyPrinter {
        allow_scientific: false,
        min_decimal: 1,
        max_decimal: 5,
    }
    .print(*v);
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// The interactive plot of one set of axes: its lines decimated on their shared abscissa
/// (`None` when the curves are not all lines on one abscissa). Ranges are set when drawn.
fn interactive_plot(spec: &FigureSpec, curves: &[Curve], palette: &Palette) -> Option<Plot> {
    let x = curves.first()?.x;
    let shared = curves
        .iter()
        .all(|c| c.kind == CurveKind::Line && (std::ptr::eq(c.x, x) || c.x == x));
    if !shared {
        return None;
    }
    let series: Vec<(&str, String, u32, &[f64])> = curves
        .iter()
        .map(|c| (c.name, palette.css(c.name), c.width.clamp(1, 3), c.y))
        .collect();
    let mut plot = Plot::decimated(
        &spec.title,
        (&spec.x_label, &spec.y_label),
        x,
        &series,
        ((0.0, 1.0), (0.0, 1.0)),
    )?;
    plot.shades = spec
        .shades
        .iter()
        .map(|s| PlotShade {
            from: s.from,
            to: s.to,
            colour: format!(
                "rgba({},{},{},{SHADE_ALPHA})",
                s.colour.0, s.colour.1, s.colour.2
            ),
            label: s.label.clone(),
        })
        .collect();
    Some(plot)
}

/// Prepares `curves` for one set of axes: thinned runs, the ranges (fixed, or robust, see
/// [`RobustRange`]) and the points beyond them.
fn build_axis(
    stem: &str,
    spec: &FigureSpec,
    curves: &[Curve],
    palette: &Palette,
) -> Result<Axis, ReportError> {
    if curves.is_empty() {
        return Err(ReportError::Empty(format!("figure {stem}: curve list")));
    }
    let mut prepared = curves
        .iter()
        .map(|c| prepare(c, palette, spec.width))
        .collect::<Result<Vec<_>, _>>()?;
    let (xr, full) = data_extent(&prepared)
        .ok_or_else(|| ReportError::Empty(format!("figure {stem}: no finite point")))?;
    let xr = match spec.x_range {
        Some((a, b)) if a.is_finite() && b.is_finite() && b > a => (a, b),
        _ => xr,
    };
    let yr = match (spec.y_range, spec.robust) {
        (Some((a, b)), _) if a.is_finite() && b.is_finite() && b > a => (a, b),
        (_, Some(r)) => {
            let (a, b) = robust_y(curves, full, &r);
            padded(a, b)
        }
        _ => padded(full.0, full.1),
    };
    let beyond = count_beyond(curves, yr);
    let marks = excursion_marks(&prepared, yr, 400);
    for p in prepared.iter_mut() {
        if p.kind == CurveKind::Points {
            for run in p.runs.iter_mut() {
                run.retain(|q| q.1 >= yr.0 && q.1 <= yr.1);
            }
        }
    }
    Ok(Axis {
        spec: spec.clone(),
        prepared,
        ranges: (xr, yr),
        beyond,
        marks,
        plot: interactive_plot(spec, curves, palette),
    })
}

/// Writes `dir/stem.png` and `dir/stem.svg` of `axes`.
fn write_figure(
    dir: &Path,
    stem: &str,
    title: &str,
    overall: Option<&str>,
    size: (u32, u32),
    axes: &[Axis],
) -> Result<FigureFiles, ReportError> {
    std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let plot_err = |path: &Path| {
        let path = path.display().to_string();
        move |message| ReportError::Plot { path, message }
    };
    render(
        BitMapBackend::new(&png, size).into_drawing_area(),
        overall,
        axes,
    )
    .map_err(plot_err(&png))?;
    render(
        SVGBackend::new(&svg, size).into_drawing_area(),
        overall,
        axes,
    )
    .map_err(plot_err(&svg))?;
    Ok(FigureFiles {
        title: title.to_string(),
        png,
        svg,
        width: size.0,
        height: size.1,
        axes: axes
            .iter()
            .map(|a| AxisInfo {
                title: a.spec.title.clone(),
                x_range: a.ranges.0,
                y_range: a.ranges.1,
                beyond: a.beyond,
            })
            .collect(),
        plots: if axes.iter().all(|a| a.plot.is_some()) {
            axes.iter()
                .filter_map(|a| {
                    let mut p = a.plot.clone()?;
                    (p.x_range, p.y_range) = a.ranges;
                    Some(p)
                })
                .collect()
        } else {
            Vec::new()
        },
    })
}

/// Draws named curves and writes `dir/stem.png` and `dir/stem.svg`.
///
/// Lines are broken at non-finite values and thinned to the screen resolution
/// ([`decimate_min_max`]); the ordinate range follows [`FigureSpec::y_range`] or
/// [`FigureSpec::robust`], and points beyond it are marked and counted
/// ([`FigureFiles::axes`]). Errors: a bad file stem, mismatched lengths, no finite point at
/// all, a zero size, or the backend failing to write.
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
    let axis = build_axis(stem, spec, curves, palette)?;
    write_figure(
        dir,
        stem,
        &spec.title,
        None,
        (spec.width, spec.height),
        &[axis],
    )
}

/// One panel of [`plot_panels`]: its title, axis labels and curves (the spec's size is
/// ignored).
#[derive(Debug, Clone)]
pub struct Panel<'a> {
    /// Title, labels, range rules.
    pub spec: FigureSpec,
    /// Its curves.
    pub curves: Vec<Curve<'a>>,
}

/// Small multiples: the panels stacked top to bottom under one `title`, each `width` x
/// `panel_height` pixels with its own ordinate range and one abscissa range for all (the
/// union of theirs, so that a time lines up down the page), written as `dir/stem.png` and
/// `.svg`. Errors as [`plot_curves`], for any panel.
pub fn plot_panels(
    dir: &Path,
    stem: &str,
    title: &str,
    (width, panel_height): (u32, u32),
    panels: &[Panel],
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    check_stem(stem)?;
    register_font()?;
    if width < 200 || panel_height < 150 {
        return Err(ReportError::Invalid(format!(
            "panel size {width}x{panel_height} is under 200x150"
        )));
    }
    if panels.is_empty() {
        return Err(ReportError::Empty(format!("figure {stem}: panel list")));
    }
    let mut axes = panels
        .iter()
        .map(|p| {
            let mut spec = p.spec.clone();
            spec.width = width;
            build_axis(stem, &spec, &p.curves, palette)
        })
        .collect::<Result<Vec<_>, _>>()?;
    // The peers' panel started where their first estimate did, and its ticks fell at
    // other times than the panels above it.
    let x = axes.iter().fold((f64::MAX, f64::MIN), |(a, b), ax| {
        (a.min(ax.ranges.0 .0), b.max(ax.ranges.0 .1))
    });
    for ax in axes.iter_mut() {
        ax.ranges.0 = x;
    }
    let height = panel_height * panels.len() as u32 + 50;
    write_figure(dir, stem, title, Some(title), (width, height), &axes)
}

/// Angles \[deg\] against time \[s\]: one line per named series, all on the time axis `t`.
///
/// The series are drawn in the order given (put the truth first so the estimates draw on
/// top of it). A series named `theta` or `truth` is the truth, drawn whole
/// ([`Curve::reference`]).
pub fn plot_time_series(
    dir: &Path,
    stem: &str,
    title: &str,
    t: &[f64],
    series: &[(&str, &[f64])],
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    let spec = FigureSpec::new(title, "time [s]", "angle [deg]");
    let curves: Vec<Curve> = series
        .iter()
        .map(|(n, y)| match *n {
            "theta" | "truth" => Curve::reference(n, t, y, 2),
            _ => Curve::line(n, t, y),
        })
        .collect();
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
    use super::range::clip_runs;
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
    fn no_tick_reads_negative_zero() {
        // a tick a rounding error below zero (0.1 * 3 - 0.3)
        let tiny = 0.3 - 0.1 * 3.0;
        assert!(tiny < 0.0);
        for v in [tiny, -0.0, -1e-12] {
            assert_eq!(tick_label(&v), "0.0", "{v:e}");
        }
        assert_eq!(tick_label(&-0.5), "-0.5");
        assert_eq!(tick_label(&-10.0), "-10.0");
        assert_eq!(tick_label(&0.05), "0.05");
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
