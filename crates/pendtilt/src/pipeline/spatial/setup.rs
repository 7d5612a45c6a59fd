//! What the options and files give a 3-D run: the rig (`--params`, else the scenario's,
//! else MODEL.md 7.6's), the sensors' noise (the scenario's), the scoring start and the
//! columns' units, with a warning for every doubtful figure.
use std::path::Path;

use anyhow::Context;

use super::Options3d;
use crate::bank::spatial::rig::{mounting_doubts, Pendulum3dConfig, Rig3dConfig};
use crate::bank::spatial::Settings3d;
use crate::config::{doubt_gravity, doubt_gyro_full_scale};
use crate::sim::spatial::Scenario3d;

/// What the options and files give the run.
#[derive(Debug, Clone)]
pub struct Setup {
    /// The estimators' settings.
    pub settings: Settings3d,
    /// Scoring starts this long after the first row \[s\], as `--score-from` or the
    /// scenario file says; None: the rule of [`crate::pipeline::Window::resolve`].
    pub score_from: Option<f64>,
    /// Seconds per unit of `t`.
    pub(super) time_scale: f64,
    /// `t`'s unit, when given (checked as the physics would find it).
    pub(super) time_given: Option<crate::io::TimeUnit>,
    /// Radians per unit of the angular columns.
    pub(super) angle_scale: f64,
    /// `--accel-unit` (`None`: m/s^2).
    pub(super) accel_unit: Option<crate::io::AccelUnit>,
    /// The rig or scenario placed O, the point whose speed `speed` gives (`[mounting]`).
    pub(super) speed_at_given: bool,
}

/// Reads the rig and scenario files and checks the options.
pub fn setup(opts: &Options3d) -> anyhow::Result<Setup> {
    let angle_scale = super::Scales3d::of(opts.columns)?.angle;
    let scenario = match opts.scenario {
        Some(p) => Some(read_scenario(p)?),
        None => None,
    };
    let mut speed_at_given = scenario.is_some();
    let mut rig_gives_noise = false;
    let settings = match (opts.params, &scenario) {
        (Some(p), s) => {
            let rig = Rig3dConfig::load(p).map_err(anyhow::Error::msg)?;
            speed_at_given = rig.mounting_given;
            rig_gives_noise = rig.ekf3d.gives_sensor_noise();
            of_rig(opts, p, &rig, s.as_ref())
        }
        (None, Some(s)) => of_scenario(opts, s),
        (None, None) => {
            opts.notice("note: no --params: using the default 3-D rig of MODEL.md 7.6");
            let rig = Rig3dConfig::default();
            Settings3d::new(rig.pendulum3d.params(), rig.mounting, None)
        }
    };
    if scenario.is_none() && !rig_gives_noise {
        opts.notice("note: no --scenario: ekf3d and ukf3d use their default sensor noise figures");
    }
    let score_from = opts.score_from.or(scenario.as_ref().map(|s| s.score_from));
    Ok(Setup {
        settings,
        score_from,
        time_scale: opts.columns.time_unit.map_or(1.0, |u| u.seconds()),
        time_given: opts.columns.time_unit,
        angle_scale,
        accel_unit: opts.columns.accel_unit,
        speed_at_given,
    })
}

/// The scenario file at `p`.
fn read_scenario(p: &Path) -> anyhow::Result<Scenario3d> {
    let text = std::fs::read_to_string(p)
        .with_context(|| format!("cannot read --scenario {}", p.display()))?;
    Ok(Scenario3d::from_toml(&text, &p.display().to_string())?.0)
}

/// The settings of the rig file `rig` (read from `p`), with the scenario's sensor noise
/// when given; its doubtful figures warned.
fn of_rig(opts: &Options3d, p: &Path, rig: &Rig3dConfig, s: Option<&Scenario3d>) -> Settings3d {
    let mut doubts = rig.pendulum3d.length_doubts("pendulum3d");
    doubts.extend(mounting_doubts(&rig.mounting, "mounting"));
    for d in doubts {
        opts.notice(&format!(
            "warning: {}: {}",
            p.display(),
            d.in_file("rig file")
        ));
    }
    let g = rig.pendulum3d.gravity();
    if let Some(d) = doubt_gravity("pendulum3d.gravity", g) {
        opts.notice(&format!("warning: {}: {d}", p.display()));
    }
    let fs = rig.gyro.full_scale;
    if let Some(d) = fs.and_then(|f| doubt_gyro_full_scale("gyro.full_scale", f, "rig file")) {
        opts.notice(&format!("warning: {}: {d}", p.display()));
    }
    let mut settings =
        Settings3d::new(rig.pendulum3d.params(), rig.mounting, s.map(|s| &s.sensors));
    rig.ekf3d.apply(&mut settings.ekf);
    settings.ekf.gyro = rig.gyro;
    settings
}

/// The settings of the scenario `s` (no rig file), its doubtful figures warned.
fn of_scenario(opts: &Options3d, s: &Scenario3d) -> Settings3d {
    let file = opts
        .scenario
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    let mut doubts = Pendulum3dConfig::Physical(s.rig.pendulum3d).length_doubts("rig.pendulum3d");
    doubts.extend(mounting_doubts(&s.rig.mounting, "rig.mounting"));
    for d in doubts {
        opts.notice(&format!("warning: {file}: {}", d.in_file("scenario file")));
    }
    if let Some(d) = doubt_gravity("rig.pendulum3d.gravity", s.rig.pendulum3d.gravity) {
        opts.notice(&format!("warning: {file}: {d}"));
    }
    Settings3d::of_scenario(s)
}
