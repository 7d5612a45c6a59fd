//! A whole report on synthetic data: every figure exists, the page references only files
//! that exist, the tables and claims come from the numbers.
use std::path::Path;

use pendtilt::report::claims::{ClaimSpec, Expect, MetricKind};
use pendtilt::report::fig3::Fig3Config;
use pendtilt::report::html::referenced_paths;
use pendtilt::report::{FigureGroup, Report, ReportError};

const RATE: f64 = 1000.0;

fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    (
        u32::from_be_bytes(b[16..20].try_into().unwrap()),
        u32::from_be_bytes(b[20..24].try_into().unwrap()),
    )
}

/// Named estimates, in order.
type Estimates = Vec<(&'static str, Vec<f64>)>;

/// Sigmoid truth (rad) and three fake estimators: late, late + overshoot + noise, biased.
fn series() -> (Vec<f64>, Vec<f64>, Estimates) {
    let d = 10f64.to_radians();
    let s = |t: f64| d / (1.0 + (-(t - 2.0) / 0.2).exp());
    let t: Vec<f64> = (0..5000).map(|k| k as f64 / RATE).collect();
    let truth: Vec<f64> = t.iter().map(|&t| s(t)).collect();
    let alg1: Vec<f64> = t.iter().map(|&t| s(t - 0.030)).collect();
    let alg2: Vec<f64> = t.iter().map(|&t| s(t - 0.010)).collect();
    // accelerometer-like: vibration noise, and one missing sample
    let mut accel: Vec<f64> = t
        .iter()
        .map(|&t| s(t) + 0.05 * (2.0 * std::f64::consts::PI * 37.0 * t).sin())
        .collect();
    accel[1234] = f64::NAN;
    (
        t,
        truth,
        vec![("accel", accel), ("alg1", alg1), ("alg2", alg2)],
    )
}

fn build() -> Report {
    let (t, truth, est) = series();
    let mut r = Report::new("Synthetic sigmoid", t, truth).unwrap();
    for (n, v) in est {
        r = r.estimate(n, v).unwrap();
    }
    r.reference("accel")
        // a moving average standing in for the FIR: same length out
        .view(
            "smoothed",
            Box::new(|v: &[f64]| {
                (0..v.len())
                    .map(|k| {
                        let lo = k.saturating_sub(4);
                        let w = &v[lo..=k];
                        w.iter().sum::<f64>() / w.len() as f64
                    })
                    .collect()
            }),
        )
        .claim(
            ClaimSpec::new("Alg 2 beats Alg 1")
                .expect("alg2", MetricKind::Rms, Expect::Lower, "alg1")
                .expect("alg2", MetricKind::LagMs, Expect::Lower, "alg1"),
        )
        .claim(
            ClaimSpec::new("Alg 1 beats the accelerometer")
                .expect("alg1", MetricKind::Rms, Expect::Lower, "accel")
                .because(
                    "",
                    "alg1 here is the truth 30 ms late, worse than small noise",
                ),
        )
        .figure_group(FigureGroup {
            stem: "zoom".into(),
            title: "Around the step".into(),
            names: vec!["alg1".into(), "alg2".into()],
            window: Some((1.5, 3.0)),
        })
        .fig3(Fig3Config {
            draws: 5000,
            ..Fig3Config::default()
        })
        .note("Synthetic data for the test.")
}

#[test]
fn report_writes_every_file_and_the_page_references_only_existing_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = build().write(dir.path()).unwrap();
    // 2 overview + 2 comparison (alg1, alg2) + 2 per non-reference estimator (alg1,
    // alg2) + 2 zoom + fig3
    assert_eq!(out.figures.len(), 2 + 2 + 4 + 2 + 1);
    for f in &out.figures {
        assert_eq!(png_size(&f.png), (f.width, f.height), "{}", f.png.display());
        let svg = std::fs::read_to_string(&f.svg).unwrap();
        let title_start: String = f.title.chars().take(20).collect();
        assert!(
            svg.contains(&title_start),
            "{} lacks {title_start:?}",
            f.svg.display()
        );
    }
    let html = std::fs::read_to_string(&out.html).unwrap();
    let refs = referenced_paths(&html);
    assert_eq!(refs.len(), 2 * out.figures.len());
    for r in &refs {
        assert!(
            !r.contains('/') && !r.contains(':'),
            "not a plain relative file: {r}"
        );
        assert!(dir.path().join(r).is_file(), "page references missing {r}");
    }
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "network reference"
    );
    assert!(html.contains("<style>"));
    // every metric column shown is defined on the page, with the tolerance of "within tol"
    for col in &pendtilt::report::markdown::METRIC_COLUMNS[1..] {
        let dt = format!("<dt>{}</dt><dd>", pendtilt::report::html::escape(col));
        assert_eq!(
            html.matches(&dt).count(),
            2,
            "{col} not defined under each table"
        );
    }
    assert!(html.contains("|estimate - truth| &lt;= 0.500 deg"));
    // the overview is one panel per estimator family, not every series overlaid
    let overview = &out.figures[0];
    assert!(overview.png.ends_with("angles_all.png"));
    assert!(overview.axes.len() >= 2, "{:?}", overview.axes);
    assert!(html.contains("Metrics: unfiltered") && html.contains("Metrics: smoothed"));
    assert!(std::fs::read_to_string(&out.markdown)
        .unwrap()
        .contains("| alg2 |"));
    // a copy for a human look when PENDTILT_KEEP_REPORT names a directory
    if let Ok(keep) = std::env::var("PENDTILT_KEEP_REPORT") {
        build().write(Path::new(&keep)).unwrap();
    }
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out.json).unwrap()).unwrap();
    assert_eq!(js["views"][0]["metrics"][0]["name"], "accel");
    assert_eq!(js["views"][0]["metrics"][0]["non_finite_estimate"], 1);
}

#[test]
fn claims_are_computed_from_the_run() {
    let data = build().compute().unwrap();
    let unf = &data.views[0].metrics;
    let alg1 = unf.iter().find(|m| m.name == "alg1").unwrap();
    let alg2 = unf.iter().find(|m| m.name == "alg2").unwrap();
    // the fakes are the truth shifted by 30 and 10 ms
    assert!(
        (alg1.lag_ms.unwrap() - 30.0).abs() < 0.1,
        "{:?}",
        alg1.lag_ms
    );
    assert!((alg2.lag_ms.unwrap() - 10.0).abs() < 0.1);
    // the truth is a step, so overshoot and settling are measured
    assert!(data.views[0].step.contains("one step"));
    // (the final value is the mean of the last 0.25 s, a hair under the asymptote)
    assert!(alg2.overshoot_pct.unwrap() < 0.01);
    assert!(alg1.settling_time_s.unwrap() > alg2.settling_time_s.unwrap());

    assert_eq!(data.claims.len(), 2);
    assert!(data.claims[0].holds, "{:?}", data.claims[0]);
    assert!(data.claims[0].measured.contains("alg2"));
    // the second holds or not according to the numbers, and says so
    let accel = unf.iter().find(|m| m.name == "accel").unwrap();
    assert_eq!(data.claims[1].holds, alg1.rms_deg < accel.rms_deg);
    if !data.claims[1].holds {
        assert!(data.claims[1].why.contains("is not lower"));
    }
}

#[test]
fn bad_series_are_errors() {
    let (t, truth, _) = series();
    let r = Report::new("x", t.clone(), truth.clone()).unwrap();
    assert!(matches!(
        r.estimate("a", vec![0.0; 3]),
        Err(ReportError::LengthMismatch { .. })
    ));
    let r = Report::new("x", t.clone(), truth.clone())
        .unwrap()
        .estimate("a", truth.clone())
        .unwrap();
    assert!(matches!(
        r.estimate("a", truth.clone()),
        Err(ReportError::DuplicateName(_))
    ));
    assert!(Report::new("x", vec![0.0, 0.0], vec![1.0, 1.0]).is_err());
    assert!(Report::with_rate("x", 0.0, vec![1.0]).is_err());
    // no estimate at all
    assert!(Report::with_rate("x", 10.0, vec![1.0; 10])
        .unwrap()
        .compute()
        .is_err());
    // an all-NaN estimator is listed as skipped, with the reason, not dropped silently
    let d = Report::with_rate("x", 100.0, truth.clone())
        .unwrap()
        .estimate("dead", vec![f64::NAN; truth.len()])
        .unwrap()
        .estimate("ok", truth.clone())
        .unwrap()
        .compute()
        .unwrap();
    assert_eq!(d.views[0].metrics.len(), 1);
    assert_eq!(d.views[0].skipped[0].0, "dead");
    // a view that changes the length is an error
    let r = Report::with_rate("x", 100.0, truth.clone())
        .unwrap()
        .estimate("ok", truth)
        .unwrap()
        .view("short", Box::new(|v: &[f64]| v[1..].to_vec()));
    assert!(matches!(
        r.compute(),
        Err(ReportError::LengthMismatch { .. })
    ));
}

/// The `<script>` elements of a page: (attributes, text).
fn scripts(html: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = html;
    while let Some(i) = rest.find("<script") {
        rest = &rest[i + "<script".len()..];
        let close = rest.find('>').unwrap();
        let end = rest.find("</script>").unwrap();
        out.push((rest[..close].to_string(), rest[close + 1..end].to_string()));
        rest = &rest[end..];
    }
    out
}

/// The plot data embedded in a page.
fn plot_data(html: &str) -> serde_json::Value {
    let (_, text) = scripts(html)
        .into_iter()
        .find(|(attrs, _)| attrs.contains("id=\"pendtilt-plots\""))
        .expect("no plot data on the page");
    serde_json::from_str(&text).unwrap()
}

#[test]
fn the_page_embeds_its_plotting_library_and_one_plot_per_set_of_axes() {
    let dir = tempfile::tempdir().unwrap();
    let out = build().write(dir.path()).unwrap();
    let html = std::fs::read_to_string(&out.html).unwrap();
    let scripts = scripts(&html);
    // the data, uPlot and the page's script, all inline: nothing to fetch
    assert_eq!(
        scripts.len(),
        3,
        "{:?}",
        scripts.iter().map(|s| &s.0).collect::<Vec<_>>()
    );
    assert!(scripts.iter().all(|(attrs, _)| !attrs.contains("src")));
    assert!(scripts[1].1.contains("uPlot") && scripts[1].1.len() > 40_000);
    assert!(html.contains(".uplot"), "uPlot's style sheet is missing");
    let data = plot_data(&html);
    let plots = data["plots"].as_array().unwrap();
    // one plot per set of axes of every figure but Fig. 3 (points, not a trace)
    let axes: usize = out.figures.iter().map(|f| f.plots.len()).sum();
    let want: usize = out
        .figures
        .iter()
        .filter(|f| !f.png.ends_with("fig3_kalman_variance.png"))
        .map(|f| f.axes.len())
        .sum();
    assert_eq!(axes, want);
    assert_eq!(plots.len(), want);
    assert_eq!(html.matches("<div class=\"iplot\"").count(), want);
    // each plot on the page says what its figure says
    let traces = data["traces"].as_array().unwrap();
    let on_page: Vec<&pendtilt::report::interactive::Plot> =
        out.figures.iter().flat_map(|f| &f.plots).collect();
    for (p, want) in plots.iter().zip(&on_page) {
        assert_eq!(p["title"], want.title.as_str());
        let x = traces[p["x"].as_u64().unwrap() as usize]
            .as_array()
            .unwrap();
        for s in p["series"].as_array().unwrap() {
            let y = traces[s["data"].as_u64().unwrap() as usize]
                .as_array()
                .unwrap();
            assert_eq!(y.len(), x.len(), "{}", s["name"]);
        }
        let yr = p["yr"].as_array().unwrap();
        assert!((yr[0].as_f64().unwrap() - want.y_range.0).abs() < 1e-4);
        assert!((yr[1].as_f64().unwrap() - want.y_range.1).abs() < 1e-4);
    }
    // the truth, drawn in many panels, is stored once per time axis
    assert!(
        traces.len()
            < plots
                .iter()
                .map(|p| p["series"].as_array().unwrap().len())
                .sum::<usize>()
    );
    // the static figures stay, linked
    assert!(html.contains("<a href=\"angles_all.png\">PNG</a>"));
}

#[test]
fn the_embedded_data_does_not_grow_with_the_log() {
    // the same signals over 20 s and over 400 s at 1 kHz
    let page = |seconds: usize| {
        let n = seconds * 1000;
        let t: Vec<f64> = (0..n).map(|k| k as f64 / RATE).collect();
        let truth: Vec<f64> = t.iter().map(|t| 0.1 * (0.7 * t).sin()).collect();
        let noisy: Vec<f64> = truth
            .iter()
            .enumerate()
            .map(|(k, v)| v + 0.01 * ((k * 7919 % 1000) as f64 / 500.0 - 1.0))
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let out = Report::new("long", t, truth)
            .unwrap()
            .estimate("alg1", noisy)
            .unwrap()
            .write(dir.path())
            .unwrap();
        let html = std::fs::read_to_string(&out.html).unwrap();
        let data = plot_data(&html);
        for tr in data["traces"].as_array().unwrap() {
            assert!(tr.as_array().unwrap().len() <= 2 * 2000 + 2);
        }
        html.len()
    };
    let (short, long) = (page(20), page(400));
    // 20 times the samples, about the same page (the decimated traces are full in both)
    assert!(long < short + short / 5, "{short} -> {long} bytes");
    assert!(long < 2_000_000, "{long} bytes");
}

/// Planar series with the compared estimators and two peers (mahony the better).
fn bank_report() -> Report {
    let n = 6000;
    let t: Vec<f64> = (0..n).map(|k| k as f64 / RATE).collect();
    let truth: Vec<f64> = t.iter().map(|t| 0.2 * (1.3 * t).sin()).collect();
    let off = |amp: f64, f: f64| -> Vec<f64> {
        t.iter()
            .zip(&truth)
            .map(|(t, v)| v + amp * (f * t).sin())
            .collect()
    };
    Report::new("bank", t.clone(), truth.clone())
        .unwrap()
        .estimate("accel", off(0.25, 210.0))
        .unwrap()
        .estimate("alg1", off(0.004, 37.0))
        .unwrap()
        .estimate("alg2", off(0.003, 41.0))
        .unwrap()
        .estimate("ekf", off(0.001, 29.0))
        .unwrap()
        .estimate("madgwick", off(0.02, 11.0))
        .unwrap()
        .estimate("mahony", off(0.01, 13.0))
        .unwrap()
        .reference("accel")
}

#[test]
fn error_figures_are_scaled_to_their_estimators_not_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = bank_report().write(dir.path()).unwrap();
    let fig = |stem: &str| {
        out.figures
            .iter()
            .find(|f| f.png.file_stem().unwrap() == stem)
            .unwrap_or_else(|| panic!("no figure {stem}"))
    };
    // accel's error reaches 0.25 rad = 14 deg; ekf's 0.001 rad = 0.057 deg
    for (stem, amp_deg) in [
        ("est_ekf_error", 0.001f64.to_degrees()),
        ("est_alg1_error", 0.004f64.to_degrees()),
    ] {
        let f = fig(stem);
        let (lo, hi) = f.axes[0].y_range;
        assert!(
            lo < -0.9 * amp_deg && hi > 0.9 * amp_deg,
            "{stem}: {lo}..{hi}"
        );
        assert!(hi - lo < 4.0 * amp_deg, "{stem} flattened: {lo}..{hi}");
        let names: Vec<&str> = f.plots[0].series.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names.len(), 1, "{stem}: {names:?}");
        assert_eq!(f.plots[0].y_range, (lo, hi));
    }
    // the angle figure keeps the reference beside the estimator
    let names: Vec<&str> = fig("est_ekf").plots[0]
        .series
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(names, ["theta", "accel", "ekf"]);
}

#[test]
fn one_figure_compares_alg1_alg2_ekf_and_the_best_peer() {
    let dir = tempfile::tempdir().unwrap();
    let out = bank_report().write(dir.path()).unwrap();
    let html = std::fs::read_to_string(&out.html).unwrap();
    for stem in ["compare", "compare_error"] {
        let f = out
            .figures
            .iter()
            .find(|f| f.png.file_stem().unwrap() == stem)
            .unwrap_or_else(|| panic!("no figure {stem}"));
        assert!(f.png.is_file() && f.svg.is_file());
        let names: Vec<&str> = f.plots[0].series.iter().map(|s| s.name.as_str()).collect();
        let want: &[&str] = if stem == "compare" {
            &["theta", "alg1", "alg2", "ekf", "mahony"]
        } else {
            &["alg1", "alg2", "ekf", "mahony"]
        };
        assert_eq!(names, want);
        assert!(html.contains(&format!("<a href=\"{stem}.png\">PNG</a>")));
    }
    assert!(html.contains("mahony is the best peer here"));
}

#[test]
fn no_tick_label_reads_negative_zero() {
    let dir = tempfile::tempdir().unwrap();
    let out = bank_report().write(dir.path()).unwrap();
    let mut zeros = 0;
    for f in &out.figures {
        let svg = std::fs::read_to_string(&f.svg).unwrap();
        // the text of every <text> element
        for chunk in svg.split("</text>") {
            let Some(i) = chunk.rfind('>') else { continue };
            let text = chunk[i + 1..].trim();
            let is_zero = text.parse::<f64>().is_ok_and(|v| v == 0.0);
            assert!(
                !(is_zero && text.starts_with('-')),
                "{} has a tick {text}",
                f.svg.display()
            );
            zeros += usize::from(is_zero);
        }
    }
    // the error axes cross zero: the tick is there, unsigned
    assert!(zeros > 0);
}
