//! Metrics and claims as Markdown tables, and metrics as JSON.
use super::claims::{fmt_sig, Claim};
use super::metrics::Metrics;
use super::ReportError;

/// Column headers of the metrics tables (Markdown and HTML), with units.
pub const METRIC_COLUMNS: &[&str] = &[
    "estimator",
    "RMS [deg]",
    "max abs err [deg]",
    "bias [deg]",
    "err std [deg]",
    "lag [ms]",
    "overshoot [%]",
    "settling [s]",
    "within tol [%]",
    "used / non-finite",
];

/// What each column of [`METRIC_COLUMNS`] after "estimator" means, in that order, with the
/// tolerance band `tolerance_deg` of "within tol". Shown under every metrics table (HTML
/// and Markdown), so that no number stands without its definition.
pub fn metric_definitions(tolerance_deg: f64) -> Vec<(&'static str, String)> {
    vec![
        (
            METRIC_COLUMNS[1],
            "root mean square of the error (estimate - truth) over the samples used".into(),
        ),
        (METRIC_COLUMNS[2], "largest |estimate - truth|".into()),
        (METRIC_COLUMNS[3], "mean of estimate - truth".into()),
        (
            METRIC_COLUMNS[4],
            "standard deviation of the error about its mean (RMS^2 = bias^2 + std^2)".into(),
        ),
        (
            METRIC_COLUMNS[5],
            "delay of the estimate behind the truth at the peak of their cross-correlation; \
             positive = late"
                .into(),
        ),
        (
            METRIC_COLUMNS[6],
            "on a truth that is one step: the largest excursion beyond the truth's final value \
             after the step's 50 % point, in % of the step; n/a otherwise"
                .into(),
        ),
        (
            METRIC_COLUMNS[7],
            "on a step: time from its 50 % point until the estimate stays within the settling \
             band of the final value; n/a otherwise"
                .into(),
        ),
        (
            METRIC_COLUMNS[8],
            format!(
                "share of the samples used whose |estimate - truth| <= {} deg (the \
                 tolerance)",
                fmt_sig(tolerance_deg)
            ),
        ),
        (
            METRIC_COLUMNS[9],
            "samples in the metrics / samples left out (estimate or truth NaN or infinite)".into(),
        ),
    ]
}

fn opt(v: Option<f64>) -> String {
    v.map(fmt_sig).unwrap_or_else(|| "n/a".to_string())
}

/// The cells of one metrics row, in the order of [`METRIC_COLUMNS`] (plain text).
pub fn metric_cells(m: &Metrics) -> Vec<String> {
    vec![
        m.name.clone(),
        fmt_sig(m.rms_deg),
        fmt_sig(m.max_abs_deg),
        fmt_sig(m.bias_deg),
        fmt_sig(m.std_deg),
        opt(m.lag_ms),
        opt(m.overshoot_pct),
        opt(m.settling_time_s),
        fmt_sig(m.within_tolerance_pct),
        format!(
            "{} / {}",
            m.samples_used,
            m.non_finite_estimate + m.non_finite_truth
        ),
    ]
}

/// Escapes a cell for a Markdown table (pipes and line breaks).
fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace(['\n', '\r'], " ")
}

fn md_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut out = String::new();
    let head: Vec<String> = header.iter().map(|c| md_cell(c)).collect();
    out.push_str(&format!("| {} |\n", head.join(" | ")));
    out.push_str(&format!(
        "|{}\n",
        header.iter().map(|_| "---|").collect::<String>()
    ));
    for r in rows {
        let cells: Vec<String> = r.iter().map(|c| md_cell(c)).collect();
        out.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    out
}

/// The metrics as a Markdown table, one row per estimator, with the tolerance band in the
/// header line below it ("n/a": not measured, see the JSON's `notes`).
pub fn metrics_markdown(metrics: &[Metrics]) -> String {
    let rows: Vec<Vec<String>> = metrics.iter().map(metric_cells).collect();
    let mut out = md_table(METRIC_COLUMNS, &rows);
    if let Some(m) = metrics.first() {
        out.push('\n');
        for (col, def) in metric_definitions(m.tolerance_deg) {
            out.push_str(&format!("- {col}: {def}\n"));
        }
    }
    out
}

/// A [`TextTable`](super::html::TextTable) as Markdown: the table, then its definitions as
/// a list.
pub fn text_table_markdown(t: &super::html::TextTable) -> String {
    let header: Vec<&str> = t.columns.iter().map(String::as_str).collect();
    let mut out = md_table(&header, &t.rows);
    if !t.definitions.is_empty() {
        out.push('\n');
        for (col, def) in &t.definitions {
            out.push_str(&format!("- {col}: {def}\n"));
        }
    }
    out
}

/// The claims as a Markdown table: claim, measured, holds, why.
pub fn claims_markdown(claims: &[Claim]) -> String {
    let rows: Vec<Vec<String>> = claims
        .iter()
        .map(|c| {
            vec![
                c.claim.clone(),
                c.measured.clone(),
                c.verdict().to_string(),
                c.why.clone(),
            ]
        })
        .collect();
    md_table(&["claim", "measured", "holds", "why"], &rows)
}

/// The metrics as pretty-printed JSON (an array of [`Metrics`]; unmeasured values are
/// `null`).
pub fn metrics_json(metrics: &[Metrics]) -> Result<String, ReportError> {
    Ok(serde_json::to_string_pretty(metrics)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::metrics::{compute_metrics, AngleUnit, MetricsConfig};

    fn row(name: &str) -> Metrics {
        let cfg = MetricsConfig {
            input_unit: AngleUnit::Deg,
            ..MetricsConfig::default()
        };
        compute_metrics(name, &[1.0, 2.0, f64::NAN], &[1.5, 2.5, 3.0], 10.0, &cfg).unwrap()
    }

    #[test]
    fn markdown_table_has_one_row_per_estimator() {
        let md = metrics_markdown(&[row("alg1"), row("a|b")]);
        let lines: Vec<&str> = md.lines().collect();
        assert!(lines[0].starts_with("| estimator | RMS [deg]"));
        assert!(lines[1].starts_with("|---|"));
        assert!(lines[2].starts_with("| alg1 | 0.500 | 0.500 | -0.500 | 0.0 | n/a"));
        assert!(lines[2].ends_with("| 2 / 1 |"));
        assert!(lines[3].starts_with("| a\\|b |"));
    }

    #[test]
    fn json_round_trips() {
        let js = metrics_json(&[row("alg2")]).unwrap();
        let v: serde_json::Value = serde_json::from_str(&js).unwrap();
        assert_eq!(v[0]["name"], "alg2");
        assert_eq!(v[0]["non_finite_estimate"], 1);
        assert!(v[0]["lag_ms"].is_null());
    }
}
