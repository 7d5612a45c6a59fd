//! One self-contained HTML page: inline CSS and script, no network. A figure with
//! interactive plots ([`super::interactive`]) shows them (zoom and pan, drawn by the
//! inlined uPlot from the JSON embedded in the page) and links its PNG and SVG; any other
//! figure shows its PNG and links its SVG. Files are referenced by relative paths beside
//! the page.
use std::path::{Path, PathBuf};

use super::claims::Claim;
use super::interactive::{self, Plot};
use super::markdown::{metric_cells, metric_definitions, METRIC_COLUMNS};
use super::metrics::Metrics;
use super::palette::Palette;
use super::ReportError;

/// A figure on the page: paths relative to the page's directory.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureRef {
    /// Caption under the figure.
    pub caption: String,
    /// PNG shown on the page (relative path).
    pub png: String,
    /// SVG linked from the figure (relative path), if any.
    pub svg: Option<String>,
    /// Interactive plots shown instead of the PNG (which is then linked), one per set of
    /// axes; empty: the PNG is shown.
    pub plots: Vec<Plot>,
}

/// A titled metrics table (for example "unfiltered" and "after the 20 Hz FIR").
#[derive(Debug, Clone, PartialEq)]
pub struct MetricsTable {
    /// Heading of the table.
    pub heading: String,
    /// One row per estimator.
    pub rows: Vec<Metrics>,
}

/// A table of preformatted cells (for example the 3-D inclination errors), its first
/// column the series name (with its colour swatch).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct TextTable {
    /// Heading of the table.
    pub heading: String,
    /// Column headers, units in brackets; the first is the name column's.
    pub columns: Vec<String>,
    /// One row per series: its name, then one cell per further column.
    pub rows: Vec<Vec<String>>,
    /// What the columns mean: (column, definition), shown under the table.
    pub definitions: Vec<(String, String)>,
}

/// The content of the page.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HtmlPage {
    /// Page title and top heading.
    pub title: String,
    /// Paragraphs under the title.
    pub intro: Vec<String>,
    /// Metrics tables.
    pub tables: Vec<MetricsTable>,
    /// Tables of preformatted cells, after the metrics tables.
    pub text_tables: Vec<TextTable>,
    /// Claims table rows (omitted when empty).
    pub claims: Vec<Claim>,
    /// Figures, in order.
    pub figures: Vec<FigureRef>,
    /// Notes at the end (definitions, things not measured and why).
    pub notes: Vec<String>,
}

/// Escapes text for HTML element content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

const CSS: &str = "body{font-family:'DejaVu Sans',Verdana,Arial,sans-serif;margin:2em auto;\
max-width:1250px;color:#222;line-height:1.45;padding:0 1em}\
h1{font-size:1.7em;border-bottom:2px solid #444;padding-bottom:.2em}\
h2{font-size:1.3em;margin-top:1.8em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.92em}\
th,td{border:1px solid #bbb;padding:.3em .6em;text-align:right;vertical-align:top}\
th{background:#eee}td.name,td.text{text-align:left}td.name{white-space:nowrap}\
tr:nth-child(even) td{background:#fafafa}\
.sw{display:inline-block;width:.9em;height:.9em;margin-right:.4em;vertical-align:-.1em;\
border:1px solid #888}\
.yes{color:#1a7f1a;font-weight:bold}.no{color:#b00;font-weight:bold}.na{color:#777}\
figure{margin:1.2em 0}figure img{max-width:100%;border:1px solid #ddd}\
figcaption{font-size:.92em;color:#444}.notes li{margin:.2em 0}\
dl.defs{font-size:.85em;color:#333;display:grid;grid-template-columns:max-content auto;\
gap:.1em 1em;margin:.3em 0 1em}dl.defs dt{font-weight:bold}dl.defs dd{margin:0}\
.iplot{margin:.4em 0 .8em}.iplot .u-title{font-size:1em}.hint{font-size:.85em;color:#555}";

impl HtmlPage {
    /// The relative paths the page references (images and links), in order.
    pub fn referenced_files(&self) -> Vec<String> {
        let mut v = Vec::new();
        for f in &self.figures {
            v.push(f.png.clone());
            if let Some(s) = &f.svg {
                v.push(s.clone());
            }
        }
        v
    }

    /// The page as HTML text; `palette` gives each estimator's colour swatch.
    pub fn render(&self, palette: &Palette) -> String {
        let mut h = String::new();
        h.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
        h.push_str(&format!("<title>{}</title>\n", escape(&self.title)));
        h.push_str(&format!("<style>{CSS}</style>\n"));
        let plots: Vec<&Plot> = self.figures.iter().flat_map(|f| &f.plots).collect();
        if !plots.is_empty() {
            h.push_str(&format!("<style>{}</style>\n", interactive::UPLOT_CSS));
        }
        h.push_str("</head>\n<body>\n");
        h.push_str(&format!("<h1>{}</h1>\n", escape(&self.title)));
        for p in &self.intro {
            h.push_str(&format!("<p>{}</p>\n", escape(p)));
        }
        for t in &self.tables {
            metrics_section(&mut h, t, palette);
        }
        for t in &self.text_tables {
            text_section(&mut h, t, palette);
        }
        self.claims_section(&mut h);
        self.figures_section(&mut h);
        self.notes_section(&mut h);
        if !plots.is_empty() {
            h.push_str(&format!(
                "<script type=\"application/json\" id=\"pendtilt-plots\">{}</script>\n",
                interactive::page_json(&plots)
            ));
            for js in [interactive::uplot_js().as_str(), interactive::PAGE_JS] {
                h.push_str(&format!(
                    "<script>{}</script>\n",
                    interactive::inline_script(js)
                ));
            }
        }
        h.push_str(&format!(
            "<p style=\"color:#888;font-size:.85em\">Written by pendtilt {}.</p>\n</body>\n</html>\n",
            env!("CARGO_PKG_VERSION")
        ));
        h
    }

    /// The claims table (nothing without claims).
    fn claims_section(&self, h: &mut String) {
        if !self.claims.is_empty() {
            h.push_str("<h2>Claims</h2>\n<table>\n<tr><th>claim</th><th>measured</th>");
            h.push_str("<th>holds</th><th>why</th></tr>\n");
            for c in &self.claims {
                let word = c.verdict();
                let cls = match word {
                    "yes" => "yes",
                    "no" => "no",
                    _ => "na",
                };
                h.push_str(&format!(
                    "<tr><td class=\"text\">{}</td><td class=\"text\">{}</td>\
                 <td class=\"{cls}\">{word}</td><td class=\"text\">{}</td></tr>\n",
                    escape(&c.claim),
                    escape(&c.measured),
                    escape(&c.why)
                ));
            }
            h.push_str("</table>\n");
        }
    }

    /// The figures: interactive plots linking the PNG and SVG, or the PNG linking its SVG.
    fn figures_section(&self, h: &mut String) {
        if !self.figures.is_empty() {
            h.push_str("<h2>Figures</h2>\n");
        }
        if self.figures.iter().any(|f| !f.plots.is_empty()) {
            h.push_str(
                "<p class=\"hint\">Plots: drag to zoom (sideways: time only; diagonally: both \
                 axes), Shift+wheel to zoom time, Shift+drag to pan, double-click to go back; \
                 the panels of a figure share their time zoom; click a legend entry to hide \
                 its line.</p>\n",
            );
        }
        let mut next_plot = 0;
        for (k, f) in self.figures.iter().enumerate() {
            if !f.plots.is_empty() {
                h.push_str("<figure>");
                for _ in &f.plots {
                    h.push_str(&format!(
                        "<div class=\"iplot\" data-plot=\"{next_plot}\" data-group=\"{k}\"></div>"
                    ));
                    next_plot += 1;
                }
                let svg = f
                    .svg
                    .as_ref()
                    .map(|s| format!(", <a href=\"{}\">SVG</a>", escape(s)))
                    .unwrap_or_default();
                h.push_str(&format!(
                    "<figcaption>{} (static figure: <a href=\"{}\">PNG</a>{svg})</figcaption>\
                     </figure>\n",
                    escape(&f.caption),
                    escape(&f.png)
                ));
                continue;
            }
            let img = format!(
                "<img src=\"{}\" alt=\"{}\">",
                escape(&f.png),
                escape(&f.caption)
            );
            let body = match &f.svg {
                Some(svg) => format!("<a href=\"{}\">{img}</a>", escape(svg)),
                None => img,
            };
            h.push_str(&format!(
                "<figure>{body}<figcaption>{}</figcaption></figure>\n",
                escape(&f.caption)
            ));
        }
    }

    /// The page's notes (nothing without notes).
    fn notes_section(&self, h: &mut String) {
        if !self.notes.is_empty() {
            h.push_str("<h2>Notes</h2>\n<ul class=\"notes\">\n");
            for n in &self.notes {
                h.push_str(&format!("<li>{}</li>\n", escape(n)));
            }
            h.push_str("</ul>\n");
        }
    }

    /// Writes the page to `dir/file_name` after checking that every file it references is a
    /// plain relative path (no "..", no scheme, not absolute) to a file that exists in `dir`.
    pub fn write(
        &self,
        dir: &Path,
        file_name: &str,
        palette: &Palette,
    ) -> Result<PathBuf, ReportError> {
        for f in self.referenced_files() {
            check_reference(dir, &f)?;
        }
        let path = dir.join(file_name);
        std::fs::write(&path, self.render(palette)).map_err(|source| ReportError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Ok(path)
    }
}

/// Checks that `rel` is a local relative path to an existing file under `dir`.
pub fn check_reference(dir: &Path, rel: &str) -> Result<(), ReportError> {
    let p = Path::new(rel);
    let local = !rel.is_empty()
        && !rel.contains("://")
        && !rel.starts_with("data:")
        && p.is_relative()
        && p.components()
            .all(|c| matches!(c, std::path::Component::Normal(_)));
    if !local || !dir.join(p).is_file() {
        return Err(ReportError::MissingFile(rel.to_string()));
    }
    Ok(())
}

/// Every `src="..."` and `href="..."` value in an HTML text, unescaped (for tests and
/// checks of pages written by anyone).
pub fn referenced_paths(html: &str) -> Vec<String> {
    let mut out = Vec::new();
    for attr in ["src=\"", "href=\""] {
        let mut rest = html;
        while let Some(i) = rest.find(attr) {
            rest = &rest[i + attr.len()..];
            if let Some(j) = rest.find('"') {
                out.push(
                    rest[..j]
                        .replace("&quot;", "\"")
                        .replace("&#39;", "'")
                        .replace("&lt;", "<")
                        .replace("&gt;", ">")
                        .replace("&amp;", "&"),
                );
                rest = &rest[j..];
            }
        }
    }
    out
}

/// One table of preformatted cells with its definitions.
fn text_section(h: &mut String, t: &TextTable, palette: &Palette) {
    h.push_str(&format!("<h2>{}</h2>\n<table>\n<tr>", escape(&t.heading)));
    for c in &t.columns {
        h.push_str(&format!("<th>{}</th>", escape(c)));
    }
    h.push_str("</tr>\n");
    for r in &t.rows {
        let Some((name, cells)) = r.split_first() else {
            continue;
        };
        h.push_str(&format!(
            "<tr><td class=\"name\"><span class=\"sw\" style=\"background:{}\"></span>{}</td>",
            palette.css(name),
            escape(name)
        ));
        for c in cells {
            h.push_str(&format!("<td>{}</td>", escape(c)));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    if !t.definitions.is_empty() {
        h.push_str("<dl class=\"defs\">\n");
        for (col, def) in &t.definitions {
            h.push_str(&format!(
                "<dt>{}</dt><dd>{}</dd>\n",
                escape(col),
                escape(def)
            ));
        }
        h.push_str("</dl>\n");
    }
}

/// One metrics table with its column definitions and per-row notes; `palette` gives each
/// estimator's colour swatch.
fn metrics_section(h: &mut String, t: &MetricsTable, palette: &Palette) {
    h.push_str(&format!(
        "<h2>Metrics: {}</h2>\n<table>\n<tr>",
        escape(&t.heading)
    ));
    for c in METRIC_COLUMNS {
        h.push_str(&format!("<th>{}</th>", escape(c)));
    }
    h.push_str("</tr>\n");
    for m in &t.rows {
        let cells = metric_cells(m);
        h.push_str(&format!(
            "<tr><td class=\"name\"><span class=\"sw\" style=\"background:{}\"></span>{}</td>",
            palette.css(&m.name),
            escape(&cells[0])
        ));
        for c in &cells[1..] {
            h.push_str(&format!("<td>{}</td>", escape(c)));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    if let Some(m) = t.rows.first() {
        h.push_str("<dl class=\"defs\">\n");
        for (col, def) in metric_definitions(m.tolerance_deg) {
            h.push_str(&format!(
                "<dt>{}</dt><dd>{}</dd>\n",
                escape(col),
                escape(&def)
            ));
        }
        h.push_str("</dl>\n");
    }
    let row_notes: Vec<String> = t
        .rows
        .iter()
        .flat_map(|m| m.notes.iter().map(move |n| format!("{}: {n}", m.name)))
        .collect();
    if !row_notes.is_empty() {
        h.push_str("<ul class=\"notes\">\n");
        for n in row_notes {
            h.push_str(&format!("<li>{}</li>\n", escape(&n)));
        }
        h.push_str("</ul>\n");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_and_missing_files_refused() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.png"), b"x").unwrap();
        let mut page = HtmlPage {
            title: "A <b> & c".into(),
            figures: vec![FigureRef {
                caption: "cap \"q\"".into(),
                png: "a.png".into(),
                svg: None,
                plots: Vec::new(),
            }],
            ..HtmlPage::default()
        };
        let html = page.render(&Palette::default());
        assert!(html.contains("<h1>A &lt;b&gt; &amp; c</h1>"));
        assert!(html.contains("alt=\"cap &quot;q&quot;\""));
        assert_eq!(referenced_paths(&html), vec!["a.png".to_string()]);
        assert!(page
            .write(dir.path(), "index.html", &Palette::default())
            .is_ok());
        page.figures[0].svg = Some("a.svg".into());
        assert!(matches!(
            page.write(dir.path(), "index.html", &Palette::default()),
            Err(ReportError::MissingFile(f)) if f == "a.svg"
        ));
        for bad in ["../a.png", "/etc/passwd", "http://x/a.png", ""] {
            assert!(check_reference(dir.path(), bad).is_err(), "{bad}");
        }
    }
}
