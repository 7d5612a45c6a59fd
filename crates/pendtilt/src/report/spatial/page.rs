//! Writing a 3-D report: the figures, the inclination error table, `report.md`,
//! `report.json` and `index.html`.
use std::path::{Path, PathBuf};

use super::ride::{phase_shades, ride_table};
use super::{InclinationRow, SpatialData, SpatialFigure, SpatialOutput, SpatialReport};
use crate::report::claims::fmt_sig;
use crate::report::figures::{FigureFiles, Shade};
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
        columns: [
            "estimator",
            "RMS [deg]",
            "max [deg]",
            "mean [deg]",
            "missing",
        ]
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
                    r.missing.to_string(),
                ]
            })
            .collect(),
        definitions: vec![
            (
                "inclination error".into(),
                "the angle between the estimated and the true up direction (MODEL.md 7.9), \
                 whatever the heading; RMS, max and mean over the rows with the truth from \
                 t0 + score_from on, t0 the first row's time (as `pendtilt estimate` prints \
                 them)"
                    .into(),
            ),
            (
                "missing".into(),
                "rows with the truth but no estimate (flagged; e.g. a sensor missing for \
                 longer than the restart gap), left out of RMS, max and mean"
                    .into(),
            ),
        ],
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
    /// The unscored start-up, shaded grey (none when scoring starts at the first row).
    fn start_shade(&self) -> Option<Shade> {
        let t0 = self.t.iter().copied().find(|t| t.is_finite())?;
        (self.score_from > 0.0).then(|| Shade {
            from: t0,
            to: t0 + self.score_from,
            colour: plotters::style::RGBColor(110, 110, 110),
            label: "not scored".into(),
        })
    }

    /// The best of the ride's peers by the inclination table (lowest finite RMS).
    fn best_peer<'a>(&self, rows: &'a [InclinationRow]) -> Option<&'a str> {
        let peers = &self.ride.as_ref()?.peers;
        rows.iter()
            .filter(|r| peers.contains(&r.name) && r.rms_deg.is_finite())
            .min_by(|a, b| a.rms_deg.total_cmp(&b.rms_deg))
            .map(|r| r.name.as_str())
    }

    /// On a ride: its data and figure (first on the page), else `None`.
    fn ride_part(
        &self,
        dir: &Path,
        rows: &[InclinationRow],
        shades: &mut Vec<Shade>,
    ) -> Result<Option<(super::RideData, FigureFiles, String)>, ReportError> {
        let Some((signals, phases)) = self.ride_phases() else {
            return Ok(None);
        };
        shades.extend(phase_shades(&phases));
        let Some(data) = self.ride_data(&phases, self.best_peer(rows)) else {
            return Ok(None);
        };
        let f = self.ride_figure(dir, &data, &signals, shades)?;
        let peer = data
            .best_peer
            .as_ref()
            .map(|p| format!(", and the best peer of this report, {p},"))
            .unwrap_or_default();
        let caption = format!(
            "{c} with the speed (its colour) and the same filter without it ({u}, grey){peer} \
             over time: roll and pitch error (estimate - truth) and inclination error, in \
             degrees; the phases found from the log shaded (turning blue, braking purple, \
             accelerating green; {n} found), the unscored start-up grey. Bottom panel: the \
             accelerations the phases are found from, smoothed (v w_z centripetal, dv/dt \
             longitudinal), thresholds +-{thr} m/s^2. Each error ordinate covers 0.5-99.5 % \
             of its points after the start-up, widened by a quarter.{}",
            super::draw::beyond(&f),
            c = data.compensated,
            u = data.uncompensated,
            n = data.phases.len(),
            thr = super::secs(data.threshold_mps2),
        );
        Ok(Some((data, f, caption)))
    }

    /// Scores, draws and writes everything into `dir` (created): `index.html`,
    /// `report.md`, `report.json`, `roll`, `pitch` and `inclination` (`.png`, `.svg`), and
    /// on a ride `ride` first.
    pub fn write(&self, dir: &Path) -> Result<SpatialOutput, ReportError> {
        let (rows, scored) = self.scores()?;
        std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
            path: dir.display().to_string(),
            source,
        })?;
        let mut shades: Vec<Shade> = self.start_shade().into_iter().collect();
        let mut drawn = Vec::new();
        let ride = match self.ride_part(dir, &rows, &mut shades)? {
            Some((data, f, caption)) => {
                drawn.push((f, caption));
                Some(data)
            }
            None => None,
        };
        drawn.extend(self.draw(dir, &rows, &shades)?);
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
            ride,
        };
        let mut tables = vec![inclination_table(
            &data.inclination,
            self.score_from,
            scored,
        )];
        tables.extend(data.ride.as_ref().map(ride_table));
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
        write_file(&markdown, self.markdown(&intro, &tables, &data).as_bytes())?;
        let json = dir.join("report.json");
        write_file(&json, serde_json::to_string_pretty(&data)?.as_bytes())?;
        let html = self.write_html(dir, intro, tables, &data, &drawn)?;
        Ok(SpatialOutput {
            html,
            markdown,
            json,
            figures: drawn.into_iter().map(|(f, _)| f).collect(),
            data,
        })
    }

    /// Writes `index.html`: the intro, the tables and the `drawn` figures (with their
    /// interactive plots), the ride table's swatches in its phases' shades.
    fn write_html(
        &self,
        dir: &Path,
        intro: Vec<String>,
        tables: Vec<TextTable>,
        data: &SpatialData,
        drawn: &[(FigureFiles, String)],
    ) -> Result<PathBuf, ReportError> {
        let page = HtmlPage {
            title: self.title.clone(),
            intro,
            text_tables: tables,
            figures: data
                .figures
                .iter()
                .zip(drawn)
                .map(|(f, (files, _))| FigureRef {
                    caption: f.caption.clone(),
                    png: f.png.clone(),
                    svg: Some(f.svg.clone()),
                    plots: files.plots.clone(),
                })
                .collect(),
            notes: self.notes.clone(),
            ..HtmlPage::default()
        };
        // the ride table's swatches are its phases' shades
        let mut palette = self.palette.clone();
        for k in super::phases::PhaseKind::ALL {
            palette.set(k.word(), super::ride::shade_style(k));
        }
        for blank in ["steady", "all"] {
            palette.set(blank, plotters::style::RGBColor(255, 255, 255));
        }
        let html = page.write(dir, "index.html", &palette)?;
        Ok(html)
    }

    fn markdown(&self, intro: &[String], tables: &[TextTable], data: &SpatialData) -> String {
        let mut md = format!("# {}\n\n", self.title);
        for p in intro {
            md.push_str(&format!("{p}\n\n"));
        }
        for table in tables {
            md.push_str(&format!(
                "## {}\n\n{}\n",
                table.heading,
                text_table_markdown(table)
            ));
        }
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
