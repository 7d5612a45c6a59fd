//! Drawing the axes of a figure with plotters: the chart, its curves, the marks of points
//! beyond it, the note and the legend.
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::prepare::Prepared;
use super::range::clip_runs;
use super::{
    tick_label, Beyond, CurveKind, FigureSpec, LegendPosition, FAMILY, OUTSIDE_W, SHADE_ALPHA,
};
use crate::report::interactive::Plot;

/// One set of axes, ready to draw.
pub(super) struct Axis {
    pub(super) spec: FigureSpec,
    pub(super) prepared: Vec<Prepared>,
    pub(super) ranges: ((f64, f64), (f64, f64)),
    pub(super) beyond: Beyond,
    pub(super) marks: Vec<(f64, bool)>,
    pub(super) plot: Option<Plot>,
}

/// One entry of a legend drawn outside the plot area.
enum Entry {
    /// A curve: its label, colour, and whether it is drawn as points.
    Curve(String, RGBColor, bool),
    /// A shade's label and colour.
    Shade(String, RGBColor),
}

/// The chart of one set of axes.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A drawing error as text.
fn e<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> String {
    format!("{e:?}")
}

/// Draws one set of axes on `area`, in drawing order: the mesh and shades, the curves, the
/// excursion marks, the note, the legend.
fn draw_axis<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    axis: &Axis,
    caption_px: u32,
) -> Result<(), String> {
    let spec = &axis.spec;
    let (xr, yr) = axis.ranges;
    let outside = spec.legend == LegendPosition::Outside;
    let mut chart = build_chart(area, axis, caption_px)?;
    let (w_px, h_px) = chart.plotting_area().dim_in_pixel();
    let dx = (xr.1 - xr.0) / f64::from(w_px.max(1));
    let dy = (yr.1 - yr.0) / f64::from(h_px.max(1));
    let mut entries = Vec::new();
    for p in &axis.prepared {
        draw_curve(&mut chart, p, yr, dy, &mut entries)?;
    }
    draw_marks(&mut chart, axis, (dx, dy))?;
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
        draw_note(area, &mut chart, note, axis.ranges, (dx, dy))?;
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

/// The chart of `axis` on `area`: its caption, mesh and shades.
fn build_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    axis: &Axis,
    caption_px: u32,
) -> Result<Chart<'a, DB>, String> {
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
    Ok(chart)
}

/// Draws curve `p` within the ordinates `yr` (`dy` per pixel) and adds its legend entry.
/// Lines are cut at the frame ([`clip_runs`]) and drawn as `width` one-pixel polylines
/// stacked a pixel apart: a thick polyline's mitred corners on a spiky signal would reach
/// far outside the plot (through the title and the axis).
fn draw_curve<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    p: &Prepared,
    yr: (f64, f64),
    dy: f64,
    entries: &mut Vec<Entry>,
) -> Result<(), String> {
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
    Ok(())
}

/// The red colour of points beyond the axis.
const MARK: RGBColor = RGBColor(200, 0, 0);

/// Excursions: a red triangle at the edge, pointing out, for each stretch beyond (`dx`,
/// `dy` per pixel).
fn draw_marks<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    axis: &Axis,
    (dx, dy): (f64, f64),
) -> Result<(), String> {
    let yr = axis.ranges.1;
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
                MARK.filled(),
            )
        }))
        .map_err(e)?;
    Ok(())
}

/// The note on points beyond the axis, in red on white in the plot's upper right corner.
fn draw_note<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &mut Chart<'_, DB>,
    note: String,
    (xr, yr): ((f64, f64), (f64, f64)),
    (dx, dy): (f64, f64),
) -> Result<(), String> {
    let font = (FAMILY, 16).into_font().color(&MARK);
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
pub(super) fn render<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: Option<&str>,
    axes: &[Axis],
) -> Result<(), String> {
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
