//! `pendtilt tune LOG3D --params RIG -o TUNED`: ekf3d's `[ekf3d]` table from a 3-D log
//! ([`crate::tune::spatial`]), no true attitude needed; the output is the rig file as
//! given with the tuned table, each value under a comment saying how it was found (or
//! that the log could not tell it: a doubt).
use anyhow::{bail, Context};
use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::StepGate;

use super::tune::{Args, TuneTarget};
use crate::bank::spatial::rig::Rig3dConfig;
use crate::sim::spatial::Pendulum3d;
use crate::tune::spatial::{self, rig_file, Start3d, Tuned3d};
use crate::units::AccelMagnitude;

/// The rig file written when no `--params` is given: MODEL.md 7.6's pendulum alone.
fn default_rig_text() -> anyhow::Result<String> {
    let body = toml::to_string(&Pendulum3d::default()).context("writing the default rig")?;
    Ok(format!(
        "# 3-D rig (MODEL.md 7.6), SI units: the default pendulum.\n[pendulum3d]\n{body}"
    ))
}

/// The log's rows as ekf3d takes them, with `--map`, `--deg`, `--time-unit` and
/// `--accel-unit` applied.
fn read_log(args: &Args) -> anyhow::Result<Vec<SpatialSample<f64>>> {
    let name = args.log.display().to_string();
    let (records, _) = crate::pipeline::spatial::read_si(&args.log, &name, &args.columns)?;
    let mut gate = StepGate::new();
    Ok(records
        .iter()
        .map(|r| SpatialSample {
            speed: r.speed.unwrap_or(f64::NAN),
            ..SpatialSample::new(gate.step(r.t), r.phi, r.gyro, r.accel)
        })
        .collect())
}

/// Reads the 3-D log and the rig, tunes, prints what was found (each value with its
/// evidence) and returns the rig file's text.
pub fn tuned_text(args: &Args) -> anyhow::Result<String> {
    if args.target == TuneTarget::Truth {
        bail!(
            "{}: --target truth: a 3-D log is tuned without its truth; leave --target out",
            args.log.display()
        );
    }
    let (rig, text, from) = match &args.params {
        Some(p) => {
            let rig = Rig3dConfig::load(p).map_err(anyhow::Error::msg)?;
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read --params {}", p.display()))?;
            (rig, text, p.display().to_string())
        }
        None => (
            Rig3dConfig::default(),
            default_rig_text()?,
            "the default 3-D rig (MODEL.md 7.6)".to_string(),
        ),
    };
    let samples = read_log(args)?;
    let t = spatial::tune3d(&samples, &Start3d::from_rig(&rig));
    let mut header = header(args, &samples, &from, &t);
    // A log in the wrong unit is tuned all the same, and says so (as the planar tune does).
    let unit = AccelMagnitude::of_vectors(samples.iter().map(|s| &s.accel))
        .finding("ax, ay, az", args.columns.accel_unit);
    if let Some(f) = unit {
        eprintln!("warning: {}: {}", args.log.display(), f.message);
        header.push(format!(
            "NOT TO BE TRUSTED: tuned on a log whose units look wrong: {}",
            f.message
        ));
    }
    if !args.quiet {
        let on_stdout = crate::io::output::is_stdout(&args.output);
        for h in &header {
            super::summary::print(on_stdout, h);
        }
        for n in &t.notes {
            let kept = if n.kept_default {
                " (KEPT: a doubt)"
            } else {
                ""
            };
            super::summary::print(on_stdout, &format!("  {} = {}{kept}", n.key, n.value));
            super::summary::print(on_stdout, &format!("      {}", n.how));
        }
        for n in t.notes.iter().filter(|n| n.fell_back) {
            eprintln!(
                "warning: {}: {} = {}: {}",
                args.log.display(),
                n.key,
                n.value,
                n.how
            );
        }
    }
    let out = rig_file::tuned_toml(&text, &t, &header);
    // What estimate will read: checked before it is written.
    Rig3dConfig::from_toml_str(&out, "the tuned rig file").map_err(anyhow::Error::msg)?;
    Ok(out)
}

/// The file's first comment lines and what standard output says first.
fn header(args: &Args, samples: &[SpatialSample<f64>], from: &str, t: &Tuned3d) -> Vec<String> {
    let rate = spatial::sample_rate(samples);
    let speed = samples.iter().any(|s| s.speed.is_finite());
    vec![
        format!(
            "pendtilt tune: {} (3-D, {} rows, {:.1} s at {:.0} Hz{}), starting from {from}",
            args.log.display(),
            samples.len(),
            samples.len() as f64 / rate,
            rate,
            if speed { ", with a speed" } else { "" }
        ),
        format!(
            "ekf3d's settings from the log alone (no true attitude used); {} of {} values \
             are doubts (kept from the start, or told only in part)",
            t.notes.iter().filter(|n| rig_file::is_doubt(n)).count(),
            t.notes.len()
        ),
    ]
}
