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
    // 2 overview + 2 per non-reference estimator (alg1, alg2) + 2 zoom + fig3
    assert_eq!(out.figures.len(), 2 + 4 + 2 + 1);
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
