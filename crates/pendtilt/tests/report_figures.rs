//! Every figure is written as a non-empty PNG of the expected size and an SVG with its title.
use std::path::Path;

use pendtilt::report::fig3::{fig3_data, plot_fig3, Fig3Config};
use pendtilt::report::figures::{
    plot_curves, plot_errors, plot_time_series, plot_xy, Curve, FigureFiles, FigureSpec,
};
use pendtilt::report::palette::Palette;

/// Width and height from a PNG's IHDR chunk (bytes 16..24), after checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert!(b.len() > 24, "{} is too short", path.display());
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    assert_eq!(&b[12..16], b"IHDR");
    let w = u32::from_be_bytes(b[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(b[20..24].try_into().unwrap());
    (w, h)
}

fn check(f: &FigureFiles, w: u32, h: u32, title_part: &str) {
    assert_eq!(png_size(&f.png), (w, h));
    assert!(
        std::fs::metadata(&f.png).unwrap().len() > 5_000,
        "PNG nearly empty"
    );
    let svg = std::fs::read_to_string(&f.svg).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..40.min(svg.len())]);
    assert!(
        svg.contains(title_part),
        "SVG lacks its title {title_part:?}"
    );
    assert!(svg.contains("<text"), "SVG has no text (labels missing)");
    assert!(svg.trim_end().ends_with("</svg>"));
}

fn sigmoid_run(n: usize, rate: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..n).map(|k| k as f64 / rate).collect();
    let truth: Vec<f64> = t
        .iter()
        .map(|t| 10.0 / (1.0 + (-(t - 2.0) / 0.2).exp()))
        .collect();
    let late: Vec<f64> = t
        .iter()
        .map(|t| 10.0 / (1.0 + (-(t - 2.08) / 0.2).exp()) + 0.3 * (40.0 * t).sin())
        .collect();
    let mut noisy: Vec<f64> = truth
        .iter()
        .enumerate()
        .map(|(k, v)| v + 2.0 * ((k * 7919 % 1000) as f64 / 1000.0 - 0.5))
        .collect();
    noisy[1000] = f64::NAN; // a hole: the line breaks, nothing panics
    (t, truth, late, noisy)
}

#[test]
fn time_series_and_error_figures() {
    let dir = tempfile::tempdir().unwrap();
    let (t, truth, late, noisy) = sigmoid_run(5000, 1000.0);
    let p = Palette::default();
    let f = plot_time_series(
        dir.path(),
        "angles",
        "Sigmoid: estimates against the true angle",
        &t,
        &[("theta", &truth), ("accel", &noisy), ("alg1", &late)],
        &p,
    )
    .unwrap();
    check(&f, 1200, 675, "Sigmoid: estimates against the true angle");
    let f = plot_errors(
        dir.path(),
        "errors",
        "Sigmoid: error of each estimate",
        &t,
        &truth,
        &[("accel", &noisy), ("alg1", &late)],
        &p,
    )
    .unwrap();
    check(&f, 1200, 675, "Sigmoid: error of each estimate");
    // mismatched estimate length is an error, not a panic
    assert!(plot_errors(
        dir.path(),
        "bad",
        "x",
        &t,
        &truth,
        &[("a", &late[..10])],
        &p
    )
    .is_err());
}

#[test]
fn xy_figure_of_custom_size_and_points() {
    let dir = tempfile::tempdir().unwrap();
    let x: Vec<f64> = (0..50).map(|k| k as f64 * 0.1).collect();
    let y: Vec<f64> = x.iter().map(|v| v * v).collect();
    let mut spec = FigureSpec::new("Quadratic & friends <xy>", "x [m]", "y [m²]");
    spec.width = 640;
    spec.height = 480;
    let p = Palette::default();
    let f = plot_xy(dir.path(), "xy", &spec, &[("square", &x, &y)], &p).unwrap();
    // the title is escaped in the SVG
    check(&f, 640, 480, "Quadratic &amp; friends &lt;xy&gt;");
    let err = vec![0.5; x.len()];
    let mut pts = Curve::points("samples", &x, &y);
    pts.y_err = Some(&err);
    let f = plot_curves(dir.path(), "points", &spec, &[pts], &p).unwrap();
    check(&f, 640, 480, "Quadratic");
}

#[test]
fn fig3_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let data = fig3_data(&Fig3Config::default()).unwrap();
    let f = plot_fig3(
        dir.path(),
        "fig3_kalman_variance",
        &data,
        &Palette::default(),
    )
    .unwrap();
    check(&f, 1200, 675, "Fig 3: Kalman posterior variance");
    // keep a copy for a human look when PENDTILT_KEEP_FIGURES is set
    if let Ok(keep) = std::env::var("PENDTILT_KEEP_FIGURES") {
        std::fs::create_dir_all(&keep).unwrap();
        for p in [&f.png, &f.svg] {
            std::fs::copy(p, Path::new(&keep).join(p.file_name().unwrap())).unwrap();
        }
    }
}

/// 10 s at 100 Hz of a unit sine.
fn sine_run() -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..1000).map(|k| k as f64 / 100.0).collect();
    let y = t.iter().map(|t| (2.0 * t).sin()).collect();
    (t, y)
}

/// A start-up transient (50 samples at 50 in the first 0.5 s) does not set the ordinate
/// range: the range comes from the sine after the first second (by hand: percentiles
/// about -1 and 1, widened by a quarter of their spread to 1.5 at most, padded 5 %), and the
/// 50 points cut at the frame are counted and named on the plot.
#[test]
fn the_y_range_ignores_a_start_up_transient_and_counts_what_it_cuts() {
    let dir = tempfile::tempdir().unwrap();
    let (t, mut y) = sine_run();
    for v in y.iter_mut().take(50) {
        *v = 50.0;
    }
    let f = plot_time_series(
        dir.path(),
        "startup",
        "start-up",
        &t,
        &[("alg2", &y)],
        &Palette::default(),
    )
    .unwrap();
    let (lo, hi) = f.axes[0].y_range;
    assert!(lo > -1.3 && lo < -1.0 && hi > 1.0 && hi < 1.8, "{lo} {hi}");
    let b = f.axes[0].beyond;
    assert_eq!((b.above, b.below, b.highest), (50, 0, Some(50.0)));
    let svg = std::fs::read_to_string(&f.svg).unwrap();
    assert!(
        svg.contains("50 points beyond the axis: 50 above (max 50.00)"),
        "the note is missing"
    );
    // The same data with the robust range switched off: everything on the plot.
    let mut spec = FigureSpec::new("all", "time [s]", "angle [deg]");
    spec.robust = None;
    let g = plot_curves(
        dir.path(),
        "all",
        &spec,
        &[Curve::line("alg2", &t, &y)],
        &Palette::default(),
    )
    .unwrap();
    assert!(g.axes[0].y_range.1 >= 50.0 && g.beyond_total() == 0);
}

/// The truth, drawn whole ([`Curve::reference`]), is never cut, start-up or not: a truth
/// that starts at -3 and settles to the unit sine keeps the axis down to -3, while an
/// estimate's start-up transient beside it (50 points at 50) is still cut and counted
/// (earlier: a 10 s 3-D report ranged on its scored last 5 s cut the truth's first
/// seconds off, 4451 points of pendulum3d's roll panel beyond the axis, the truth's
/// among them).
#[test]
fn the_truth_drawn_whole_is_never_cut_by_the_robust_range() {
    let dir = tempfile::tempdir().unwrap();
    let (t, sine) = sine_run();
    let truth: Vec<f64> = t
        .iter()
        .zip(&sine)
        .map(|(t, y)| if *t < 0.8 { -3.0 } else { *y })
        .collect();
    let mut est = sine.clone();
    for v in est.iter_mut().take(50) {
        *v = 50.0;
    }
    let p = Palette::default();
    let spec = FigureSpec::new("whole", "time [s]", "angle [deg]");
    let f = plot_curves(
        dir.path(),
        "whole",
        &spec,
        &[
            Curve::line("alg2", &t, &est),
            Curve::reference("theta", &t, &truth, 1),
        ],
        &p,
    )
    .unwrap();
    let (lo, hi) = f.axes[0].y_range;
    assert!(lo <= -3.0 && hi < 2.0, "{lo} {hi}");
    let b = f.axes[0].beyond;
    assert_eq!((b.above, b.below), (50, 0), "{b:?}");
    // Drawn as a plain line, the truth's start is cut with the transient.
    let g = plot_curves(
        dir.path(),
        "cut",
        &spec,
        &[
            Curve::line("alg2", &t, &est),
            Curve::line("theta", &t, &truth),
        ],
        &p,
    )
    .unwrap();
    assert!(g.axes[0].beyond.below > 0, "{:?}", g.axes[0]);
}

/// One spike of 1000 in a sine is cut at the frame and reported as one point above; the
/// sine's own peaks are not cut.
#[test]
fn a_spike_is_reported_and_a_plain_sine_is_not_cut() {
    let dir = tempfile::tempdir().unwrap();
    let (t, y) = sine_run();
    let p = Palette::default();
    let f = plot_time_series(dir.path(), "sine", "sine", &t, &[("alg1", &y)], &p).unwrap();
    assert_eq!(f.beyond_total(), 0, "{:?}", f.axes);
    let (lo, hi) = f.axes[0].y_range;
    assert!(lo <= -1.0 && hi >= 1.0);
    let mut spiky = y.clone();
    spiky[500] = 1000.0;
    let g = plot_errors(
        dir.path(),
        "spike",
        "spike",
        &t,
        &vec![0.0; t.len()],
        &[("accel", &spiky)],
        &p,
    )
    .unwrap();
    assert_eq!(g.axes[0].beyond.above, 1);
    assert_eq!(g.axes[0].beyond.highest, Some(1000.0));
    assert!(g.axes[0].y_range.1 < 2.0);
    let svg = std::fs::read_to_string(&g.svg).unwrap();
    assert!(svg.contains("1 point beyond the axis: 1 above (max 1000.0)"));
}

/// Small multiples: one panel per family, each with its own range and title, stacked in
/// one PNG of 1200 x (3 x 420 + 50).
#[test]
fn panels_are_drawn_one_above_the_other() {
    use pendtilt::report::figures::{plot_panels, Panel};
    let dir = tempfile::tempdir().unwrap();
    let (t, y) = sine_run();
    let big: Vec<f64> = y.iter().map(|v| 100.0 * v).collect();
    // The peers start late: every panel still spans the same time.
    let late: Vec<f64> = y
        .iter()
        .enumerate()
        .map(|(k, v)| if k < y.len() / 4 { f64::NAN } else { *v })
        .collect();
    let panels: Vec<Panel> = [("raw", &y), ("Kalman filters", &big), ("peers", &late)]
        .into_iter()
        .map(|(title, v)| Panel {
            spec: FigureSpec::new(title, "time [s]", "angle [deg]"),
            curves: vec![Curve::line("alg1", &t, v)],
        })
        .collect();
    let f = plot_panels(
        dir.path(),
        "panels",
        "every estimate",
        (1200, 420),
        &panels,
        &Palette::default(),
    )
    .unwrap();
    check(&f, 1200, 3 * 420 + 50, "every estimate");
    assert_eq!(f.axes.len(), 3);
    assert!(f.axes[1].y_range.1 > 50.0 && f.axes[0].y_range.1 < 2.0);
    for a in &f.axes {
        assert_eq!(a.x_range, (t[0], t[t.len() - 1]), "{}", a.title);
    }
    let svg = std::fs::read_to_string(&f.svg).unwrap();
    for title in ["raw", "Kalman filters", "peers"] {
        assert!(
            svg.contains(&format!("\n{title}\n")),
            "panel {title} missing"
        );
    }
}
