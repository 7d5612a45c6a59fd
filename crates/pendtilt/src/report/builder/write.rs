//! Writing a [`Report`]: the figures of the plot view, `report.md`, `report.json` and the
//! HTML page.
use super::*;

impl Report {
    /// Computes everything and writes into `dir`: `index.html`, `report.md`, `report.json`
    /// and the figures (`*.png` + `*.svg`).
    pub fn write(&self, dir: &Path) -> Result<ReportOutput, ReportError> {
        let data = self.compute()?;
        std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
            path: dir.display().to_string(),
            source,
        })?;
        let pv = self.view_index(&self.plot_view)?;
        let pv_name = self.view_names()[pv].clone();
        let (figures, captions) = self.draw_figures(dir, &data, pv)?;
        let (md_path, json_path) = self.write_markdown_and_json(dir, &data)?;
        let html = self.write_page(dir, &data, &figures, &captions, &pv_name)?;
        Ok(ReportOutput {
            html,
            markdown: md_path,
            json: json_path,
            figures,
            data,
        })
    }

    /// Draws every figure of the plot view `pv` (in degrees) into `dir`: the family
    /// overview and its errors, each figure group (one per estimator beside the reference
    /// when asked) with its errors, and Fig. 3. Returns the figures and their captions.
    fn draw_figures(
        &self,
        dir: &Path,
        data: &ReportData,
        pv: usize,
    ) -> Result<(Vec<FigureFiles>, Vec<String>), ReportError> {
        let pv_name = self.view_names()[pv].clone();
        let (truth, est) = self.view_series(pv)?;
        let f = self.config.input_unit.to_deg_factor();
        let deg = |v: &[f64]| v.iter().map(|x| x * f).collect::<Vec<f64>>();
        let est_deg: Vec<(String, Vec<f64>)> =
            est.iter().map(|(n, v)| (n.clone(), deg(v))).collect();
        let find = |n: &str| {
            est_deg
                .iter()
                .find(|(m, _)| m == n)
                .map(|(_, v)| v.as_slice())
        };
        let v = PlotView {
            dir,
            suffix: if pv == 0 {
                String::new()
            } else {
                format!(" ({pv_name})")
            },
            pv_name,
            truth_deg: deg(&truth),
        };
        let mut d = Drawn::default();
        self.draw_overview(&v, &est_deg, &mut d)?;
        if let Some((g, peer)) = comparison_group(&self.title, &v.suffix, &data.views[pv]) {
            self.draw_comparison(&v, &g, peer, &find, &mut d)?;
        }
        for g in &self.figure_groups(&est_deg, &find) {
            self.draw_group(&v, g, &find, &mut d)?;
        }
        if let Some(fig3) = &data.fig3 {
            d.figures
                .push(plot_fig3(dir, "fig3_kalman_variance", fig3, &self.palette)?);
            d.captions.push(format!(
                "Fig. 3: Eq (12) posterior variance against R, with a seeded Monte-Carlo check \
                 ({} draws per point; largest deviation {:.2} standard errors).",
                fig3.config.draws,
                fig3.worst_z()
            ));
        }
        Ok((d.figures, d.captions))
    }

    /// The overview: small multiples, one panel per estimator family (17 overlaid lines
    /// cannot be told apart), of the angles and of the errors.
    fn draw_overview(
        &self,
        v: &PlotView,
        est_deg: &[(String, Vec<f64>)],
        d: &mut Drawn,
    ) -> Result<(), ReportError> {
        let all: Vec<(&str, &[f64])> = est_deg
            .iter()
            .map(|(n, v)| (n.as_str(), v.as_slice()))
            .collect();
        let (angles, errors) = family_panels(
            &self.title,
            &v.suffix,
            &self.t,
            &v.truth_deg,
            &all,
            v.dir,
            &self.palette,
        )?;
        let n_fam = angles.axes.len();
        d.figures.push(angles);
        d.captions.push(format!(
            "Every estimate against the true angle (theta, black), one panel per estimator \
             family ({n_fam} panels). Ordinate ranges: 0.5-99.5 % of the data after the \
             first second, widened by a quarter, and the whole true angle; points beyond are \
             cut at the frame, marked red and counted on the panel."
        ));
        d.figures.push(errors);
        d.captions.push(
            "Error (estimate - truth) of every estimate, one panel per estimator family, \
             ranges as above."
                .to_string(),
        );
        Ok(())
    }

    /// The comparison group `g` (with the best `peer` and its RMS error, when there is one):
    /// its angles and its errors on one set of axes each.
    fn draw_comparison<'a>(
        &self,
        v: &PlotView,
        g: &FigureGroup,
        peer: Option<(String, f64)>,
        find: &dyn Fn(&str) -> Option<&'a [f64]>,
        d: &mut Drawn,
    ) -> Result<(), ReportError> {
        let (t, truth_w, series) = windowed(&self.t, &v.truth_deg, &g.names, find, None)?;
        let mut lines: Vec<(&str, &[f64])> = vec![("theta", &truth_w)];
        lines.extend(series.iter().map(|(n, v)| (n.as_str(), v.as_slice())));
        d.figures.push(plot_time_series(
            v.dir,
            &g.stem,
            &g.title,
            &t,
            &lines,
            &self.palette,
        )?);
        let pv_name = &v.pv_name;
        let why = peer
            .map(|(p, rms)| {
                format!(
                    " {p} is the best peer here: the lowest RMS error ({rms:.3} deg) of \
                     the peers on the {pv_name} series."
                )
            })
            .unwrap_or_default();
        d.captions.push(format!(
            "{} against the true angle, on one set of axes.{why}{}",
            g.names.join(", "),
            beyond_caption(d.figures.last())
        ));
        d.figures.push(plot_errors(
            v.dir,
            &format!("{}_error", g.stem),
            &format!("{}: error", g.title),
            &t,
            &truth_w,
            &lines[1..],
            &self.palette,
        )?);
        d.captions.push(format!(
            "Error of {}, on one set of axes, the ordinate scaled to them.{}",
            g.names.join(", "),
            beyond_caption(d.figures.last())
        ));
        Ok(())
    }

    /// Figure group `g`: its estimates against the truth, and their errors (the reference's
    /// left out when it would set the ordinate).
    fn draw_group<'a>(
        &self,
        v: &PlotView,
        g: &FigureGroup,
        find: &dyn Fn(&str) -> Option<&'a [f64]>,
        d: &mut Drawn,
    ) -> Result<(), ReportError> {
        let suffix = &v.suffix;
        let (t, truth_w, series) = windowed(&self.t, &v.truth_deg, &g.names, find, g.window)?;
        let mut lines: Vec<(&str, &[f64])> = vec![("theta", &truth_w)];
        lines.extend(series.iter().map(|(n, v)| (n.as_str(), v.as_slice())));
        d.figures.push(plot_time_series(
            v.dir,
            &g.stem,
            &format!("{}{suffix}", g.title),
            &t,
            &lines,
            &self.palette,
        )?);
        d.captions.push(format!(
            "{} against the true angle.{}",
            g.names.join(", "),
            beyond_caption(d.figures.last())
        ));
        // The reference's error (the accelerometer's, +-15 deg on a ride) would set
        // the ordinate and flatten a sub-degree estimator's: it is in the overview.
        let errors: Vec<(&str, &[f64])> = lines[1..]
            .iter()
            .filter(|(n, _)| lines.len() == 2 || Some(*n) != self.reference.as_deref())
            .copied()
            .collect();
        let error_names: Vec<&str> = errors.iter().map(|(n, _)| *n).collect();
        let error_title = if errors.len() + 1 < lines.len() {
            format!("{}: {}: error{suffix}", self.title, error_names.join(", "))
        } else {
            format!("{}: error{suffix}", g.title)
        };
        d.figures.push(plot_errors(
            v.dir,
            &format!("{}_error", g.stem),
            &error_title,
            &t,
            &truth_w,
            &errors,
            &self.palette,
        )?);
        let left_out = match &self.reference {
            Some(r) if errors.len() + 1 < lines.len() => format!(
                " The ordinate is scaled to {}; {r}'s error is in the overview of errors.",
                error_names.join(", ")
            ),
            _ => String::new(),
        };
        d.captions.push(format!(
            "Error of {}.{left_out}{}",
            error_names.join(", "),
            beyond_caption(d.figures.last())
        ));
        Ok(())
    }

    /// The figure groups to draw: the ones added, then (with per-estimator figures) one
    /// per estimate beside the reference.
    fn figure_groups<'a>(
        &self,
        est_deg: &[(String, Vec<f64>)],
        find: &dyn Fn(&str) -> Option<&'a [f64]>,
    ) -> Vec<FigureGroup> {
        let mut groups = self.groups.clone();
        if self.per_estimator_figures {
            for (n, _) in est_deg {
                if Some(n) == self.reference.as_ref() {
                    continue;
                }
                let mut names = Vec::new();
                if let Some(r) = &self.reference {
                    if find(r).is_some() {
                        names.push(r.clone());
                    }
                }
                names.push(n.clone());
                groups.push(FigureGroup {
                    stem: format!("est_{}", file_safe(n)),
                    title: format!("{}: {}", self.title, names.join(" and ")),
                    names,
                    window: None,
                });
            }
        }
        groups
    }

    /// `report.md` and `report.json` in `dir`.
    fn write_markdown_and_json(
        &self,
        dir: &Path,
        data: &ReportData,
    ) -> Result<(PathBuf, PathBuf), ReportError> {
        let mut md = format!("# {}\n\n", self.title);
        for p in &self.intro {
            md.push_str(&format!("{p}\n\n"));
        }
        for v in &data.views {
            md.push_str(&format!(
                "## Metrics: {}\n\n{}\n",
                v.view,
                metrics_markdown(&v.metrics)
            ));
            md.push_str(&format!("Step: {}.\n\n", v.step));
            for (n, why) in &v.skipped {
                md.push_str(&format!("- {n}: no metrics ({why})\n"));
            }
        }
        if !data.claims.is_empty() {
            md.push_str(&format!(
                "## Claims (on the {} metrics)\n\n{}\n",
                data.claims_view,
                claims_markdown(&data.claims)
            ));
        }
        let md_path = dir.join("report.md");
        write_file(&md_path, md.as_bytes())?;
        let json_path = dir.join("report.json");
        write_file(&json_path, serde_json::to_string_pretty(data)?.as_bytes())?;

        Ok((md_path, json_path))
    }

    /// `index.html` in `dir`: the intro, metrics tables, claims, `figures` with their
    /// `captions`, and the notes.
    fn write_page(
        &self,
        dir: &Path,
        data: &ReportData,
        figures: &[FigureFiles],
        captions: &[String],
        pv_name: &str,
    ) -> Result<PathBuf, ReportError> {
        let rel = |p: &Path| {
            p.file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        let mut intro = self.intro.clone();
        intro.push(format!(
            "{} samples at {:.1} Hz ({:.2} s); estimators: {}. Figures drawn from the {} series.",
            data.samples,
            data.rate_hz,
            data.samples as f64 / data.rate_hz,
            self.estimates
                .iter()
                .map(|(n, _)| n.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            pv_name
        ));
        let mut notes = Vec::new();
        for v in &data.views {
            notes.push(format!("{}: {}.", v.view, v.step));
            for (n, why) in &v.skipped {
                notes.push(format!("{}: {n} has no metrics: {why}.", v.view));
            }
        }
        notes.push(format!(
            "Lag: delay of the estimate behind the truth from the peak of their cross-correlation \
             (searched over +-{} ms, refined by a parabola through the peak); positive = late.",
            self.config.max_lag_s * 1e3
        ));
        notes.extend(self.notes.iter().cloned());
        let page = HtmlPage {
            title: self.title.clone(),
            intro,
            tables: data
                .views
                .iter()
                .map(|v| MetricsTable {
                    heading: v.view.clone(),
                    rows: v.metrics.clone(),
                })
                .collect(),
            text_tables: Vec::new(),
            claims: data.claims.clone(),
            figures: figures
                .iter()
                .zip(captions)
                .map(|(f, c)| FigureRef {
                    caption: c.clone(),
                    png: rel(&f.png),
                    svg: Some(rel(&f.svg)),
                    plots: f.plots.clone(),
                })
                .collect(),
            notes,
        };
        page.write(dir, "index.html", &self.palette)
    }
}

/// What every figure of the plot view shares.
struct PlotView<'a> {
    dir: &'a Path,
    /// ` (name)` after a title, for a view other than the first.
    suffix: String,
    pv_name: String,
    /// The true angle \[deg\].
    truth_deg: Vec<f64>,
}

/// The figures drawn so far, and their captions.
#[derive(Default)]
struct Drawn {
    figures: Vec<FigureFiles>,
    captions: Vec<String>,
}

/// " n points beyond the axis (marked red)." for a figure that cut any, else "".
fn beyond_caption(f: Option<&FigureFiles>) -> String {
    match f.map(FigureFiles::beyond_total) {
        Some(n @ 1..) => format!(
            " {n} point{} beyond the ordinate axis (start-up or spikes; marked red on the \
             frame).",
            if n == 1 { "" } else { "s" }
        ),
        _ => String::new(),
    }
}

/// The overview figures `angles_all` and `errors_all`: one panel per estimator family
/// ([`families::Family`]), the truth in every angle panel.
fn family_panels(
    title: &str,
    suffix: &str,
    t: &[f64],
    truth: &[f64],
    series: &[(&str, &[f64])],
    dir: &Path,
    palette: &Palette,
) -> Result<(FigureFiles, FigureFiles), ReportError> {
    let groups = families::group(series.iter().map(|(n, _)| *n));
    let find = |n: &str| series.iter().find(|(m, _)| *m == n).map(|(_, v)| *v);
    let errors: Vec<(&str, Vec<f64>)> = series
        .iter()
        .map(|(n, v)| (*n, v.iter().zip(truth).map(|(e, x)| e - x).collect()))
        .collect();
    let find_err = |n: &str| {
        errors
            .iter()
            .find(|(m, _)| *m == n)
            .map(|(_, v)| v.as_slice())
    };
    let mut angle_panels = Vec::new();
    let mut error_panels = Vec::new();
    for (family, names) in &groups {
        let mut curves = vec![Curve::reference("theta", t, truth, 2)];
        curves.extend(
            names
                .iter()
                .filter_map(|n| find(n).map(|v| Curve::line(n, t, v))),
        );
        angle_panels.push(Panel {
            spec: FigureSpec::new(family.label(), "time [s]", "angle [deg]"),
            curves,
        });
        error_panels.push(Panel {
            spec: FigureSpec::new(family.label(), "time [s]", "error [deg]"),
            curves: names
                .iter()
                .filter_map(|n| find_err(n).map(|v| Curve::line(n, t, v)))
                .collect(),
        });
    }
    let angles = plot_panels(
        dir,
        "angles_all",
        &format!("{title}: every estimate and the true angle{suffix}"),
        (1200, 420),
        &angle_panels,
        palette,
    )?;
    let errors = plot_panels(
        dir,
        "errors_all",
        &format!("{title}: error (estimate - truth) of every estimate{suffix}"),
        (1200, 420),
        &error_panels,
        palette,
    )?;
    Ok((angles, errors))
}

/// The estimators compared directly on one set of axes: Algorithms 1 and 2, the EKF.
const COMPARED: [&str; 3] = ["alg1", "alg2", "ekf"];

/// The comparison figure of [`COMPARED`] and the best peer (lowest RMS error of the
/// peers' family in `view`), with the best peer and its RMS; `None` when fewer than two
/// of them are in the report.
fn comparison_group(
    title: &str,
    suffix: &str,
    view: &ViewMetrics,
) -> Option<(FigureGroup, Option<(String, f64)>)> {
    let has = |n: &str| view.metrics.iter().any(|m| m.name == n);
    let peer = view
        .metrics
        .iter()
        .filter(|m| families::Family::of(&m.name) == families::Family::Peers)
        .filter(|m| m.rms_deg.is_finite())
        .min_by(|a, b| a.rms_deg.total_cmp(&b.rms_deg))
        .map(|m| (m.name.clone(), m.rms_deg));
    let mut names: Vec<String> = COMPARED
        .iter()
        .filter(|n| has(n))
        .map(|n| n.to_string())
        .collect();
    names.extend(peer.as_ref().map(|(p, _)| p.clone()));
    (names.len() >= 2).then(|| {
        (
            FigureGroup {
                stem: "compare".into(),
                title: format!("{title}: {}{suffix}", names.join(", ")),
                names,
                window: None,
            },
            peer,
        )
    })
}

/// Time, truth and named series of a figure window.
type Windowed = (Vec<f64>, Vec<f64>, NamedSeries);

/// The samples of a figure group inside its time window.
fn windowed<'a>(
    t: &[f64],
    truth: &[f64],
    names: &[String],
    find: &dyn Fn(&str) -> Option<&'a [f64]>,
    window: Option<(f64, f64)>,
) -> Result<Windowed, ReportError> {
    let keep: Vec<usize> = match window {
        None => (0..t.len()).collect(),
        Some((a, b)) => (0..t.len()).filter(|&k| t[k] >= a && t[k] <= b).collect(),
    };
    if keep.is_empty() {
        return Err(ReportError::Invalid(format!(
            "figure window {window:?} holds no sample"
        )));
    }
    let pick = |v: &[f64]| keep.iter().map(|&k| v[k]).collect::<Vec<f64>>();
    let mut series = Vec::new();
    for n in names {
        let v = find(n)
            .ok_or_else(|| ReportError::Invalid(format!("figure asks for unknown series {n:?}")))?;
        series.push((n.clone(), pick(v)));
    }
    Ok((pick(t), pick(truth), series))
}

/// A name made safe for a file stem: letters, digits, '_' and '-' kept, others become '_'.
pub fn file_safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    std::fs::write(path, bytes).map_err(|source| ReportError::Io {
        path: path.display().to_string(),
        source,
    })
}
