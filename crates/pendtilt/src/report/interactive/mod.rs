//! The page's interactive plots: every time-series panel of a figure, decimated
//! ([`decimate`]) and embedded in the page as JSON, drawn by uPlot (vendored in `assets/`,
//! MIT, inlined in the page so it works offline) with zoom and pan.
//!
//! uPlot was chosen because it is one 50 kB file with no dependencies that draws tens of
//! thousands of points per plot on a canvas at interactive speed; the PNG and SVG figures
//! stay beside the page for other tools and the Markdown report.
//!
//! Identical traces (the truth drawn in every panel, a series in several figures) are
//! stored once in the page: the data grows with the number of distinct series, not with
//! the number of figures, and never with the length of the log.
use std::collections::HashMap;
use std::fmt::Write as _;

pub mod decimate;

/// Buckets per trace: two points each, so a trace holds at most 4002 points (about twice a
/// wide screen's pixel columns).
pub const BUCKETS: usize = 2000;

/// uPlot 1.6.32 (`npm pack uplot`, `dist/uPlot.iife.min.js`), MIT, `assets/LICENSE-uPlot.txt`.
pub const UPLOT_JS: &str = include_str!("../../../assets/uPlot.iife.min.js");

/// [`UPLOT_JS`] as inlined in the page: its banner comment's project address without the
/// scheme, so that no "http(s)://" appears on a page that must not touch the network.
pub fn uplot_js() -> String {
    UPLOT_JS.replacen("/*! https://", "/*! ", 1)
}
/// uPlot's style sheet (`dist/uPlot.min.css`).
pub const UPLOT_CSS: &str = include_str!("../../../assets/uPlot.min.css");
/// The page's own script: builds one uPlot per plot from the embedded JSON, with zoom, pan,
/// reset and tick labels without "-0.0".
pub const PAGE_JS: &str = include_str!("../../../assets/report-plots.js");

/// One series of a [`Plot`], decimated.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotSeries {
    /// Legend label.
    pub name: String,
    /// CSS colour.
    pub colour: String,
    /// Line width \[px\].
    pub width: u32,
    /// Ordinates, point for point with [`Plot::x`]; NaN is a gap.
    pub y: Vec<f64>,
}

/// A shaded stretch of the abscissa behind a plot's lines.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotShade {
    /// Start.
    pub from: f64,
    /// End.
    pub to: f64,
    /// CSS colour (with its opacity).
    pub colour: String,
    /// What it marks.
    pub label: String,
}

/// One interactive plot: a set of axes of a figure, its traces decimated.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Plot {
    /// Title over the plot.
    pub title: String,
    /// Abscissa label.
    pub x_label: String,
    /// Ordinate label.
    pub y_label: String,
    /// Decimated abscissae, shared by every series.
    pub x: Vec<f64>,
    /// The series, in drawing order.
    pub series: Vec<PlotSeries>,
    /// Abscissa range shown first (the figure's).
    pub x_range: (f64, f64),
    /// Ordinate range shown first (the figure's, robust to spikes and start-ups).
    pub y_range: (f64, f64),
    /// Stretches shaded behind the lines.
    pub shades: Vec<PlotShade>,
}

impl Plot {
    /// A plot of `series` (name, colour, width, ordinates) on the shared abscissae `x`,
    /// each decimated to at most `2 * BUCKETS + 2` points; `None` when `x` is not finite
    /// and non-decreasing (the plot needs a sorted axis) or a series' length differs.
    pub fn decimated(
        title: &str,
        (x_label, y_label): (&str, &str),
        x: &[f64],
        series: &[(&str, String, u32, &[f64])],
        ranges: ((f64, f64), (f64, f64)),
    ) -> Option<Self> {
        let sorted = x.iter().all(|v| v.is_finite()) && x.windows(2).all(|w| w[1] >= w[0]);
        if x.is_empty() || !sorted || series.iter().any(|s| s.3.len() != x.len()) {
            return None;
        }
        let bounds = decimate::buckets(x.len(), BUCKETS);
        Some(Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            x: decimate::abscissae(x, bounds.as_deref()),
            series: series
                .iter()
                .map(|(name, colour, width, y)| PlotSeries {
                    name: name.to_string(),
                    colour: colour.clone(),
                    width: *width,
                    y: decimate::ordinates(y, bounds.as_deref()),
                })
                .collect(),
            x_range: ranges.0,
            y_range: ranges.1,
            shades: Vec::new(),
        })
    }
}

/// Writes a number with at most four decimals (plenty for degrees and seconds on a
/// screen), no trailing zeros, `null` for NaN and infinities, never "-0".
fn push_num(out: &mut String, v: f64) {
    if !v.is_finite() {
        out.push_str("null");
        return;
    }
    let mut s = format!("{:.4}", v);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    out.push_str(&s);
}

fn num_array(v: &[f64]) -> String {
    let mut s = String::with_capacity(v.len() * 8);
    s.push('[');
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        push_num(&mut s, *x);
    }
    s.push(']');
    s
}

/// A JSON string literal, safe inside a `<script>` element (no `<`, `>` or `&`).
fn json_str(s: &str) -> String {
    serde_json::to_string(s)
        .unwrap_or_else(|_| "\"\"".into())
        .replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

/// The page's plot data as JSON: `{"traces": [[...], ...], "plots": [...]}`, each plot
/// naming its abscissae and series by their index in `traces` (identical arrays stored
/// once). Safe to put inside a `<script type="application/json">` element.
pub fn page_json(plots: &[&Plot]) -> String {
    let mut traces: Vec<String> = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut intern = |v: &[f64]| {
        let s = num_array(v);
        let n = index.len();
        *index.entry(s.clone()).or_insert_with(|| {
            traces.push(s);
            n
        })
    };
    let mut body = String::new();
    for (i, p) in plots.iter().enumerate() {
        if i > 0 {
            body.push(',');
        }
        let x = intern(&p.x);
        let _ = write!(
            body,
            "{{\"title\":{},\"xl\":{},\"yl\":{},\"x\":{x},\"xr\":{},\"yr\":{},\"series\":[",
            json_str(&p.title),
            json_str(&p.x_label),
            json_str(&p.y_label),
            num_array(&[p.x_range.0, p.x_range.1]),
            num_array(&[p.y_range.0, p.y_range.1]),
        );
        for (k, s) in p.series.iter().enumerate() {
            let data = intern(&s.y);
            let _ = write!(
                body,
                "{}{{\"name\":{},\"colour\":{},\"width\":{},\"data\":{data}}}",
                if k > 0 { "," } else { "" },
                json_str(&s.name),
                json_str(&s.colour),
                s.width
            );
        }
        body.push_str("],\"shades\":[");
        for (k, s) in p.shades.iter().enumerate() {
            let _ = write!(
                body,
                "{}{{\"from_to\":{},\"colour\":{},\"label\":{}}}",
                if k > 0 { "," } else { "" },
                num_array(&[s.from, s.to]),
                json_str(&s.colour),
                json_str(&s.label)
            );
        }
        body.push_str("]}");
    }
    format!("{{\"traces\":[{}],\"plots\":[{body}]}}", traces.join(","))
}

/// A script's text made safe to inline in `<script>`: a `</script` inside it (none in the
/// vendored files, but checked) would end the element early.
pub fn inline_script(js: &str) -> String {
    js.replace("</script", "<\\/script")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_never_negative_zero() {
        let mut s = String::new();
        for v in [-0.0, -0.00001, 1.5, 2.0, f64::NAN, -12.34567] {
            push_num(&mut s, v);
            s.push(' ');
        }
        assert_eq!(s, "0 0 1.5 2 null -12.3457 ");
    }

    #[test]
    fn identical_traces_are_stored_once_and_text_is_script_safe() {
        let x: Vec<f64> = (0..10).map(f64::from).collect();
        let truth = vec![1.0; 10];
        let p = Plot::decimated(
            "a </script> b",
            ("t", "y"),
            &x,
            &[
                ("theta", "#000".into(), 2, &truth),
                ("est", "#f00".into(), 2, &x),
            ],
            ((0.0, 9.0), (-1.0, 10.0)),
        )
        .unwrap();
        let q = Plot {
            title: "other".into(),
            ..p.clone()
        };
        let json = page_json(&[&p, &q]);
        assert!(!json.contains("</script"));
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        // x and est are the same numbers: one trace; truth the other
        assert_eq!(v["traces"].as_array().unwrap().len(), 2);
        assert_eq!(v["plots"].as_array().unwrap().len(), 2);
        assert_eq!(v["plots"][1]["series"][0]["data"], 1);
        assert_eq!(v["plots"][0]["title"], "a </script> b");
    }

    #[test]
    fn an_unsorted_axis_gets_no_plot() {
        let x = [0.0, 2.0, 1.0];
        let y = [0.0; 3];
        let s = [("a", "#000".to_string(), 1, &y[..])];
        assert!(Plot::decimated("t", ("x", "y"), &x, &s, ((0.0, 2.0), (0.0, 1.0))).is_none());
    }
}
