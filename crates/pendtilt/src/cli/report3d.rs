//! `pendtilt report` on a 3-D log (MODEL.md 7.6 columns, with the truth `roll`, `pitch`):
//! the same pass over the log as `pendtilt estimate` (`pipeline::spatial::pass`, so the
//! same rig, sensor figures, scoring start and row handling), kept in memory and drawn by
//! [`crate::report::spatial::SpatialReport`]: roll, pitch and inclination error figures, the
//! RMS / max / mean table, `report.md`, `report.json`, `index.html`. On a log with a
//! `speed` column it is a ride report too ([`crate::report::spatial::ride`]): `ekf3d` is
//! run once more without the speed ([`crate::bank::spatial::ride::WithoutSpeed`]) and set beside
//! itself per phase of the ride.
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::report::Args;
use crate::bank::spatial::ride::WithoutSpeed;
use crate::io::output::{self, OutputDir};
use crate::pipeline::spatial::{pass, setup, Options3d, Row, Sink3d};
use crate::report::markdown::text_table_markdown;
use crate::report::spatial::page::inclination_table;
use crate::report::spatial::{Ride, RollPitch, SpatialReport};

/// The rows of a pass, in memory, and the ride's extra run.
struct Memory {
    t: Vec<f64>,
    truth: (Vec<f64>, Vec<f64>),
    est: Vec<RollPitch>,
    file: String,
    speed: Vec<f64>,
    gyro_z: Vec<f64>,
    without_speed: WithoutSpeed,
}

impl Sink3d for Memory {
    fn start(
        &mut self,
        names: &[&'static str],
        _quaternion: &[bool],
        truth: bool,
    ) -> anyhow::Result<()> {
        anyhow::ensure!(
            truth,
            "{}: the log has no `roll` and `pitch` columns (the truth): a report compares \
             the estimates with them (`pendtilt estimate` runs without)",
            self.file
        );
        self.est = names
            .iter()
            .map(|n| RollPitch {
                name: n.to_string(),
                roll: Vec::new(),
                pitch: Vec::new(),
            })
            .collect();
        Ok(())
    }

    fn row(&mut self, r: Row) -> anyhow::Result<()> {
        self.t.push(r.t);
        self.truth.0.push(r.truth.0);
        self.truth.1.push(r.truth.1);
        for (s, a) in self.est.iter_mut().zip(r.est) {
            s.roll.push(a.roll);
            s.pitch.push(a.pitch);
        }
        self.speed.push(r.sample.speed);
        self.gyro_z.push(r.sample.gyro[2]);
        self.without_speed.update(r.sample);
        Ok(())
    }
}

fn options(args: &Args) -> Options3d<'_> {
    Options3d {
        log: &args.log,
        log_name: None,
        params: args.params.as_deref(),
        scenario: args.scenario.as_deref(),
        score_from: args.score_from,
        columns: &args.columns,
        only: None,
        quiet: args.quiet,
    }
}

/// Runs `pendtilt report` on a 3-D log: everything is written into a staging directory
/// and moved into `-o` only when the whole report was made.
pub fn run(args: Args) -> anyhow::Result<()> {
    let opts = options(&args);
    let out = OutputDir::create("-o", &args.output)?;
    let html =
        report(&args, &opts, out.staging()).with_context(|| output::not_written(&args.output))?;
    let html = out.final_path(&html);
    out.commit(&opts.inputs())?;
    super::summary::say!("wrote {}", html.display());
    Ok(())
}

/// Makes the report in `dir`; returns the page's path.
fn report(args: &Args, opts: &Options3d, dir: &Path) -> anyhow::Result<PathBuf> {
    let setup = setup(opts)?;
    let file = args.log.display().to_string();
    let mut mem = Memory {
        t: Vec::new(),
        truth: (Vec::new(), Vec::new()),
        est: Vec::new(),
        file: file.clone(),
        speed: Vec::new(),
        gyro_z: Vec::new(),
        without_speed: WithoutSpeed::new(&setup.settings),
    };
    let result = pass(opts, &setup, false, &mut mem)?;
    if !args.quiet {
        for w in &result.warnings {
            eprintln!("warning: {w}");
        }
    }
    let title = args.title.clone().unwrap_or_else(|| {
        args.log
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| file.clone())
    });
    let mut report =
        SpatialReport::new(&title, mem.t, mem.truth.0, mem.truth.1, result.window.from)
            .with_context(|| format!("{file}: cannot build the report"))?
            .intro(&format!(
                "The 3-D log {file} through every 3-D estimator, as `pendtilt estimate` runs \
             them{}.",
                match (opts.params, opts.scenario) {
                    (Some(p), Some(s)) => format!(
                        " with the rig {} and the sensor figures of {}",
                        p.display(),
                        s.display()
                    ),
                    (Some(p), None) => format!(
                        " with the rig {} and the filters' default sensor figures",
                        p.display()
                    ),
                    (None, Some(s)) =>
                        format!(" with the rig and sensor figures of {}", s.display()),
                    (None, None) => " with MODEL.md 7.6's rig and the filters' default sensor \
                                 figures"
                        .to_string(),
                }
            ));
    let said: Vec<String> = result.warnings.iter().map(|w| w.to_string()).collect();
    if let Some(text) = super::report::warnings_paragraph(&said, said.len()) {
        report = report.intro(&text);
    }
    for w in &result.warnings {
        report = report.note(&format!("warning: {w}"));
    }
    let compared = mem
        .est
        .iter()
        .any(|e| e.name == crate::bank::spatial::ride::COMPENSATED);
    for s in mem.est {
        report = report.estimate(s)?;
    }
    if let Some(ride) = Ride::of(mem.without_speed, mem.speed, mem.gyro_z) {
        if compared {
            report = report.ride(ride)?;
        }
    }
    let out = report
        .write(dir)
        .with_context(|| format!("cannot write the report into {}", args.output.display()))?;
    let table = inclination_table(
        &out.data.inclination,
        out.data.score_from_s,
        out.data.scored,
    );
    super::summary::say!("{}:\n{}", table.heading, text_table_markdown(&table));
    Ok(out.html)
}
