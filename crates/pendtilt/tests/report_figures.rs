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
