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

use super::interactive::{Plot, PlotShade};
use super::palette::Palette;
use super::ReportError;

mod prepare;
mod range;
pub use prepare::decimate_min_max;
use prepare::{prepare, Prepared};
use range::{clip_runs, count_beyond, data_extent, excursion_marks, padded, robust_y};
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

/// One set of axes, ready to draw.
struct Axis {
    spec: FigureSpec,
    prepared: Vec<Prepared>,
    ranges: ((f64, f64), (f64, f64)),
    beyond: Beyond,
    marks: Vec<(f64, bool)>,
    plot: Option<Plot>,
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

/// One entry of a legend drawn outside the plot area.
enum Entry {
    /// A curve: its label, colour, and whether it is drawn as points.
    Curve(String, RGBColor, bool),
    /// A shade's label and colour.
    Shade(String, RGBColor),
}

/// Draws one set of axes on `area`. Lines are cut at the frame ([`clip_runs`]) and drawn as
/// `width` one-pixel polylines stacked a pixel apart: a thick polyline's mitred corners
/// on a spiky signal would reach far outside the plot (through the title and the axis).
// Long because it is one linear drawing routine on one chart: mesh, shades, curves,
// excursion marks, the note, the legend, in drawing order; split, each piece would need
// the chart's full plotters type and the same ranges and pixel sizes handed back and forth.
fn draw_axis<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    axis: &Axis,
    caption_px: u32,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
    let spec = &axis.spec;
    let (xr, yr) = axis.ranges;
    let outside = spec.legend == LegendPosition::Outside;
    let mut chart = ChartBuilder::on(area)
        .caption(&spec.title, (FAMILY, caption_px).into_font())
        .margin(18)
        .margin_right(if outside { 18 + OUTSIDE_W } else { 18 })
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
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()
        .map_err(e)?;
    chart
        .draw_series(
            spec.shades
                .iter()
                .filter(|s| s.to > xr.0 && s.from < xr.1)
                .map(|s| {
                    Rectangle::new(
                        [(s.from.max(xr.0), yr.0), (s.to.min(xr.1), yr.1)],
                        s.colour.mix(SHADE_ALPHA).filled(),
                    )
                }),
        )
        .map_err(e)?;
    let (w_px, h_px) = chart.plotting_area().dim_in_pixel();
    let dx = (xr.1 - xr.0) / f64::from(w_px.max(1));
    let dy = (yr.1 - yr.0) / f64::from(h_px.max(1));
    let mut entries = Vec::new();
    for p in &axis.prepared {
        let colour = p.colour;
        let mut labelled = false;
        match p.kind {
            CurveKind::Line => {
                let w = p.width.max(1);
                let runs = clip_runs(&p.runs, (yr.0 + f64::from(w - 1) * dy, yr.1));
                for run in &runs {
                    for k in 0..w {
                        let shift = f64::from(k) * dy;
                        let ann = chart
                            .draw_series(LineSeries::new(
                                run.iter().map(|&(x, y)| (x, y - shift)),
                                colour.stroke_width(1),
                            ))
                            .map_err(e)?;
                        // one legend entry per curve, on its first run
                        if !labelled {
                            ann.label(p.name.as_str()).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                            });
                            labelled = true;
                            entries.push(Entry::Curve(p.name.clone(), colour, false));
                        }
                    }
                }
            }
            CurveKind::Points => {
                chart
                    .draw_series(p.bars.iter().map(|&(x, lo, hi)| {
                        PathElement::new(
                            vec![(x, lo.max(yr.0)), (x, hi.min(yr.1))],
                            colour.stroke_width(1),
                        )
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
                entries.push(Entry::Curve(p.name.clone(), colour, true));
            }
        }
        if !labelled {
            // a curve with no point on the plot still appears in the legend, so it is
            // not silently missing
            let why = if p.runs.iter().all(Vec::is_empty) {
                "no data"
            } else {
                "beyond the axis"
            };
            let label = format!("{} ({why})", p.name);
            entries.push(Entry::Curve(label.clone(), colour, true));
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
                .map_err(e)?
                .label(label)
                .legend(move |(x, y)| Circle::new((x + 12, y), 4, colour.stroke_width(1)));
        }
    }
    // Excursions: a red triangle at the edge, pointing out, for each stretch beyond.
    let mark = RGBColor(200, 0, 0);
    let (tw, th) = (5.0 * dx, 9.0 * dy);
    chart
        .draw_series(axis.marks.iter().map(|&(x, up)| {
            let (edge, tip) = if up {
                (yr.1 - th, yr.1)
            } else {
                (yr.0 + th, yr.0)
            };
            Polygon::new(
                vec![(x - tw, edge), (x + tw, edge), (x, tip)],
                mark.filled(),
            )
        }))
        .map_err(e)?;
    let note = axis.beyond.note().map(|n| format!("{n} (red marks)"));
    if outside {
        for s in &spec.shades {
            let seen = entries
                .iter()
                .any(|x| matches!(x, Entry::Shade(l, _) if *l == s.label));
            if !seen && s.to > xr.0 && s.from < xr.1 {
                entries.push(Entry::Shade(s.label.clone(), s.colour));
            }
        }
        let plot = chart.plotting_area();
        let origin = (
            plot.get_base_pixel().0 - area.get_base_pixel().0 + w_px as i32 + 14,
            plot.get_base_pixel().1 - area.get_base_pixel().1,
        );
        return draw_outside_legend(area, origin, &entries, note.as_deref());
    }
    if let Some(note) = note {
        let font = (FAMILY, 16).into_font().color(&mark);
        let (tw_px, th_px) = area.estimate_text_size(&note, &font).map_err(e)?;
        let x_right = xr.1 - 8.0 * dx;
        let y_top = yr.1 - 14.0 * dy;
        let x_left = x_right - f64::from(tw_px + 8) * dx;
        let y_bottom = y_top - f64::from(th_px + 6) * dy;
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(x_left, y_top), (x_right, y_bottom)],
                WHITE.mix(0.9).filled(),
            )))
            .map_err(e)?;
        chart
            .draw_series(std::iter::once(Text::new(
                note,
                (x_left + 4.0 * dx, y_top - 3.0 * dy),
                font,
            )))
            .map_err(e)?;
    }
    let pos = match spec.legend {
        LegendPosition::UpperLeft | LegendPosition::Outside => SeriesLabelPosition::UpperLeft,
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
    Ok(())
}

/// The legend of [`LegendPosition::Outside`]: one line per entry from `origin` (pixels in
/// `area`, the top left of the column), then the note on points beyond the axis in red,
/// wrapped to the column: beside the plot, it covers neither the data nor the red marks.
fn draw_outside_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x0, mut y): (i32, i32),
    entries: &[Entry],
    note: Option<&str>,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
    let font = (FAMILY, 15).into_font();
    const LINE: i32 = 19;
    for entry in entries {
        let label = match entry {
            Entry::Curve(label, colour, points) => {
                if *points {
                    area.draw(&Circle::new((x0 + 12, y + 8), 4, colour.filled()))
                } else {
                    area.draw(&PathElement::new(
                        vec![(x0, y + 8), (x0 + 24, y + 8)],
                        colour.stroke_width(3),
                    ))
                }
                .map_err(e)?;
                label
            }
            Entry::Shade(label, colour) => {
                area.draw(&Rectangle::new(
                    [(x0, y + 1), (x0 + 24, y + 15)],
                    colour.mix(SHADE_ALPHA * 2.0).filled(),
                ))
                .map_err(e)?;
                label
            }
        };
        area.draw(&Text::new(label.clone(), (x0 + 32, y), font.clone()))
            .map_err(e)?;
        y += LINE;
    }
    if let Some(note) = note {
        let red = (FAMILY, 14).into_font().color(&RGBColor(200, 0, 0));
        let width = OUTSIDE_W - 20;
        let mut line = String::new();
        let mut lines = Vec::new();
        for word in note.split_whitespace() {
            let trial = if line.is_empty() {
                word.to_string()
            } else {
                format!("{line} {word}")
            };
            let (w, _) = area.estimate_text_size(&trial, &red).map_err(e)?;
            if w > width && !line.is_empty() {
                lines.push(std::mem::replace(&mut line, word.to_string()));
            } else {
                line = trial;
            }
        }
        lines.push(line);
        y += 6;
        for l in lines {
            area.draw(&Text::new(l, (x0, y), red.clone())).map_err(e)?;
            y += LINE - 2;
        }
    }
    Ok(())
}

/// Draws the axes top to bottom on `root` (under `title`, when given) and presents it.
fn render<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: Option<&str>,
    axes: &[Axis],
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
    root.fill(&WHITE).map_err(e)?;
    let area = match title {
        Some(t) => root.titled(t, (FAMILY, 28)).map_err(e)?,
        None => root.clone(),
    };
    let caption = if axes.len() > 1 { 20 } else { 26 };
    for (axis, part) in axes.iter().zip(area.split_evenly((axes.len(), 1))) {
        draw_axis(&part, axis, caption)?;
    }
    root.present().map_err(e)?;
    Ok(())
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
