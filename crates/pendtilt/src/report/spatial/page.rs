//! Writing a 3-D report: the figures, the inclination error table, `report.md`,
//! `report.json` and `index.html`.
use std::path::Path;

use super::{InclinationRow, SpatialData, SpatialFigure, SpatialOutput, SpatialReport};
use crate::report::claims::fmt_sig;
use crate::report::html::{FigureRef, HtmlPage, TextTable};
use crate::report::markdown::text_table_markdown;
use crate::report::ReportError;

/// The inclination error table: estimator, RMS, max, mean \[deg\], with its definitions.
/// `scored` rows from `score_from` \[s\] after the first row.
pub fn inclination_table(rows: &[InclinationRow], score_from: f64, scored: u64) -> TextTable {
    TextTable {
        heading: format!(
            "Inclination error, t >= t0 + {} s ({scored} rows)",
            super::secs(score_from)
        ),
        columns: ["estimator", "RMS [deg]", "max [deg]", "mean [deg]"]
            .map(String::from)
            .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    r.name.clone(),
                    fmt_sig(r.rms_deg),
                    fmt_sig(r.max_deg),
                    fmt_sig(r.mean_deg),
                ]
            })
            .collect(),
        definitions: vec![(
            "inclination error".into(),
            "the angle between the estimated and the true up direction (MODEL.md 7.9), \
             whatever the heading; RMS, max and mean over the rows with the truth from t0 + \
             score_from on, t0 the first row's time (as `pendtilt estimate` prints them); \
             inf: an estimate was missing there"
                .into(),
        )],
    }
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    std::fs::write(path, bytes).map_err(|source| ReportError::Io {
        path: path.display().to_string(),
        source,
    })
}

impl SpatialReport {
    /// Scores, draws and writes everything into `dir` (created): `index.html`,
    /// `report.md`, `report.json`, `roll`, `pitch` and `inclination` (`.png`, `.svg`).
    pub fn write(&self, dir: &Path) -> Result<SpatialOutput, ReportError> {
        let (rows, scored) = self.scores()?;
        std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
            path: dir.display().to_string(),
            source,
        })?;
        let drawn = self.draw(dir, &rows)?;
        let samples = self.t.len();
        let rate_hz = super::median_rate(&self.t)?;
        let data = SpatialData {
            title: self.title.clone(),
            samples,
            rate_hz,
            score_from_s: self.score_from,
            scored,
            inclination: rows,
            figures: drawn
                .iter()
                .map(|(f, caption)| SpatialFigure {
                    png: file_name(&f.png),
                    svg: file_name(&f.svg),
                    title: f.title.clone(),
                    caption: caption.clone(),
                    axes: f.axes.clone(),
                })
                .collect(),
            notes: self.notes.clone(),
        };
        let table = inclination_table(&data.inclination, self.score_from, scored);
        let mut intro = self.intro.clone();
        intro.push(format!(
            "{samples} rows at {:.1} Hz ({:.2} s); estimators: {}.",
            rate_hz,
            samples as f64 / rate_hz,
            self.estimates
                .iter()
                .map(|e| e.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ));
        let markdown = dir.join("report.md");
        write_file(&markdown, self.markdown(&intro, &table, &data).as_bytes())?;
        let json = dir.join("report.json");
        write_file(&json, serde_json::to_string_pretty(&data)?.as_bytes())?;
        let page = HtmlPage {
            title: self.title.clone(),
            intro,
            text_tables: vec![table],
            figures: data
                .figures
                .iter()
                .map(|f| FigureRef {
                    caption: f.caption.clone(),
                    png: f.png.clone(),
                    svg: Some(f.svg.clone()),
                })
                .collect(),
            notes: self.notes.clone(),
            ..HtmlPage::default()
        };
        let html = page.write(dir, "index.html", &self.palette)?;
        Ok(SpatialOutput {
            html,
            markdown,
            json,
            figures: drawn.into_iter().map(|(f, _)| f).collect(),
            data,
        })
    }

    fn markdown(&self, intro: &[String], table: &TextTable, data: &SpatialData) -> String {
        let mut md = format!("# {}\n\n", self.title);
        for p in intro {
            md.push_str(&format!("{p}\n\n"));
        }
        md.push_str(&format!(
            "## {}\n\n{}\n",
            table.heading,
            text_table_markdown(table)
        ));
        md.push_str("## Figures\n\n");
        for f in &data.figures {
            md.push_str(&format!("![{}]({})\n\n{}\n\n", f.title, f.png, f.caption));
        }
        if !self.notes.is_empty() {
            md.push_str("## Notes\n\n");
            for n in &self.notes {
                md.push_str(&format!("- {n}\n"));
            }
        }
        md
    }
}
