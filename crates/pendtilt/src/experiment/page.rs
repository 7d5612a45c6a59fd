//! The top page of `pendtilt reproduce`: claims, key metrics and the paper's figures,
//! linking to the full report of each ride.
use std::path::{Path, PathBuf};

use crate::report::claims::Claim;
use crate::report::figures::FigureFiles;
use crate::report::html::{check_reference, FigureRef, HtmlPage, MetricsTable, TextTable};
use crate::report::markdown::{claims_markdown, metrics_markdown, text_table_markdown};
use crate::report::metrics::Metrics;
use crate::report::palette::Palette;
use crate::report::ReportError;

/// A figure of a sub-report to show on the top page: its file stem and caption.
pub struct Pick<'a> {
    /// Sub-directory of the ride's report.
    pub dir: &'a str,
    /// The figures of the ride's report.
    pub figures: &'a [FigureFiles],
    /// File stem of the figure (e.g. `est_alg1`).
    pub stem: &'a str,
    /// Caption on the top page.
    pub caption: String,
}

/// Everything on the top page.
pub struct TopPage<'a> {
    /// Page title.
    pub title: String,
    /// Paragraphs under the title.
    pub intro: Vec<String>,
    /// Links to the full reports: (relative path, text).
    pub links: Vec<(String, String)>,
    /// Metrics tables (heading, rows).
    pub tables: Vec<(String, Vec<Metrics>)>,
    /// Tables of preformatted cells (the 3-D inclination errors), after the metrics.
    pub text_tables: Vec<TextTable>,
    /// The claims.
    pub claims: Vec<Claim>,
    /// Figures picked from the sub-reports.
    pub figures: Vec<Pick<'a>>,
    /// Notes at the end.
    pub notes: Vec<String>,
}

fn stem_of(p: &Path) -> Option<String> {
    p.file_stem().map(|s| s.to_string_lossy().into_owned())
}

impl TopPage<'_> {
    /// The figures that exist, as page references relative to `dir`.
    fn figure_refs(&self) -> Vec<FigureRef> {
        let name = |p: &Path| {
            p.file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        self.figures
            .iter()
            .filter_map(|pick| {
                let f = pick
                    .figures
                    .iter()
                    .find(|f| stem_of(&f.png).as_deref() == Some(pick.stem))?;
                Some(FigureRef {
                    caption: match f.beyond_total() {
                        0 => pick.caption.clone(),
                        n => format!(
                            "{} ({n} point{} beyond the ordinate axis, marked red on the frame.)",
                            pick.caption,
                            if n == 1 { "" } else { "s" }
                        ),
                    },
                    png: format!("{}/{}", pick.dir, name(&f.png)),
                    svg: Some(format!("{}/{}", pick.dir, name(&f.svg))),
                    // the top page stays static: its parts' pages have the plots
                    plots: Vec::new(),
                })
            })
            .collect()
    }

    /// Writes `index.html` and `report.md` into `dir`; every referenced file must exist.
    pub fn write(&self, dir: &Path) -> Result<(PathBuf, PathBuf), ReportError> {
        let palette = Palette::default();
        let page = HtmlPage {
            title: self.title.clone(),
            intro: self.intro.clone(),
            tables: self
                .tables
                .iter()
                .map(|(h, rows)| MetricsTable {
                    heading: h.clone(),
                    rows: rows.clone(),
                })
                .collect(),
            text_tables: self.text_tables.clone(),
            claims: self.claims.clone(),
            figures: self.figure_refs(),
            notes: self.notes.clone(),
        };
        for f in page.referenced_files() {
            check_reference(dir, &f)?;
        }
        let mut links = String::from("<p>Full reports: ");
        for (i, (href, text)) in self.links.iter().enumerate() {
            check_reference(dir, href)?;
            if i > 0 {
                links.push_str(" | ");
            }
            links.push_str(&format!(
                "<a href=\"{}\">{}</a>",
                crate::report::html::escape(href),
                crate::report::html::escape(text)
            ));
        }
        links.push_str("</p>\n");
        let mut html = page.render(&palette);
        if let Some(i) = html.find("</h1>\n") {
            html.insert_str(i + "</h1>\n".len(), &links);
        }
        let html_path = dir.join("index.html");
        write(&html_path, html.as_bytes())?;

        let mut md = format!("# {}\n\n", self.title);
        for p in &self.intro {
            md.push_str(&format!("{p}\n\n"));
        }
        for (href, text) in &self.links {
            md.push_str(&format!("- [{text}]({href})\n"));
        }
        md.push_str(&format!(
            "\n## Claims\n\n{}\n",
            claims_markdown(&self.claims)
        ));
        for (h, rows) in &self.tables {
            md.push_str(&format!("## Metrics: {h}\n\n{}\n", metrics_markdown(rows)));
        }
        for t in &self.text_tables {
            md.push_str(&format!("## {}\n\n{}\n", t.heading, text_table_markdown(t)));
        }
        if !self.notes.is_empty() {
            md.push_str("## Notes\n\n");
            for n in &self.notes {
                md.push_str(&format!("- {n}\n"));
            }
        }
        let md_path = dir.join("report.md");
        write(&md_path, md.as_bytes())?;
        Ok((html_path, md_path))
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    std::fs::write(path, bytes).map_err(|source| ReportError::Io {
        path: path.display().to_string(),
        source,
    })
}
