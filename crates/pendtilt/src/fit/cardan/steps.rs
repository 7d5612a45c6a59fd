//! The steps of a 3-D fit from a log file (`pendtilt fit` on a 3-D log): the log read in
//! SI units, the warning on a start rig without `[mounting]`, the physical form's mass and
//! length, and the settings from the command's options.
use std::path::Path;

use anyhow::bail;

use super::{Fit3dSettings, Log3dColumns, NoiseDensities};
use crate::bank::spatial::rig::Rig3dConfig;
use crate::fit::Target;
use crate::pipeline::LogColumns;

/// Reads the whole 3-D log at `path` (named `name` in errors) with the column options
/// (`--map`'s 3-D names, `--deg`, `--time-unit`, `--accel-unit`), in SI units; and whether
/// it has a `speed` column.
pub fn read_log(
    path: &Path,
    name: &str,
    columns: &LogColumns,
) -> anyhow::Result<(Log3dColumns, bool)> {
    let (records, speed) = crate::pipeline::spatial::read_si(path, name, columns)?;
    let mut log = Log3dColumns::default();
    for r in &records {
        log.t.push(r.t);
        log.phi.push(r.phi);
        log.gyro.push(r.gyro);
        log.accel.push(r.accel);
        log.truth
            .push([r.roll.unwrap_or(f64::NAN), r.pitch.unwrap_or(f64::NAN)]);
    }
    Ok((log, speed))
}

/// The warning when the rig written will have no `[mounting]` (the start rig had none):
/// the fit took the accelerometer as at P1, and `estimate` will take the speed's point and
/// the body's centre there too. Measured on the README's quick start (scooter3d, 60 s,
/// seed 1): ekf3d 0.044 deg with its `[mounting]`, 0.063 without. `params` is the start
/// rig's file, `speed` whether the log has a `speed` column.
pub fn mounting_warning(params: Option<&Path>, rig: &Rig3dConfig, speed: bool) -> Option<String> {
    if rig.mounting_given {
        return None;
    }
    let start = match params {
        Some(p) => format!("the start rig {} has no [mounting]", p.display()),
        None => "no --params was given".to_string(),
    };
    let speed = if speed {
        " and the point whose speed the log's `speed` column gives"
    } else {
        ""
    };
    Some(format!(
        "warning: {start}, so the fit took the accelerometer as at P1, the pendulum's pivot, \
         and the rig written has no [mounting]: estimate will take the body's centre of \
         rotation{speed} there too. If the IMU or the vehicle's centre is elsewhere, fit with \
         --params RIG whose [mounting] says where (docs/rig-file.md); on a standing scooter \
         leaving it out took ekf3d from 0.044 to 0.063 deg RMS"
    ))
}

/// The mass and length of the physical form: with --mass or --length, the other from the
/// start rig's physical form (`mass`, `length`: the options' values).
pub fn mass_length(
    mass: Option<f64>,
    length: Option<f64>,
    rig: &Rig3dConfig,
) -> anyhow::Result<Option<(f64, f64)>> {
    use crate::bank::spatial::rig::Pendulum3dConfig;
    if mass.is_none() && length.is_none() {
        return Ok(None);
    }
    let (m0, l0) = match rig.pendulum3d {
        Pendulum3dConfig::Physical(p) => (Some(p.mass), Some(p.length)),
        Pendulum3dConfig::Normalised(_) => (None, None),
    };
    match (mass.or(m0), length.or(l0)) {
        (Some(m), Some(l)) => Ok(Some((m, l))),
        _ => bail!(
            "the physical form needs both the mass and the length, and the start rig is \
             normalised: give --mass and --length"
        ),
    }
}

/// The options of a 3-D fit, as `pendtilt fit` takes them (each field its option).
#[derive(Debug, Clone, Copy)]
pub struct Fit3dOptions {
    /// What the cost compares with (`--target`).
    pub target: Target,
    /// Seconds left out at the start (`--skip`; at least 1 s is).
    pub skip: f64,
    /// The smoothing of the true angle, Hz (`--smoothing-hz`).
    pub smoothing_hz: f64,
    /// Leave the encoder offsets out (`--no-encoder-offset`).
    pub no_encoder_offset: bool,
    /// The iteration limit (`--max-iterations`).
    pub max_iterations: usize,
    /// The accelerometer's noise density (`--accel-noise`).
    pub accel_noise: Option<f64>,
    /// The gyro's noise density (`--gyro-noise`).
    pub gyro_noise: Option<f64>,
}

/// The fit's settings from the options; the noise densities from them or from the log's
/// initial rest, with where they came from.
pub fn settings(o: &Fit3dOptions, log: &Log3dColumns) -> (Fit3dSettings, String) {
    let rest = NoiseDensities::from_initial_rest(log);
    let accel = o.accel_noise.map(|d| [d; 2]).or(rest.map(|r| r.accel));
    let gyro = o.gyro_noise.map(|d| [d; 2]).or(rest.map(|r| r.gyro));
    let noise = (accel.is_some() || gyro.is_some()).then(|| NoiseDensities {
        accel: accel.unwrap_or([0.0; 2]),
        gyro: gyro.unwrap_or([0.0; 2]),
    });
    let said = match noise {
        Some(d) => format!(
            "noise taken out: accelerometer {:.3e}, {:.3e} m/s^2/sqrt(Hz), gyro {:.3e}, {:.3e} \
             rad/s/sqrt(Hz) ({})",
            d.accel[0],
            d.accel[1],
            d.gyro[0],
            d.gyro[1],
            if o.accel_noise.is_some() || o.gyro_noise.is_some() {
                "options, the rest from the log's initial rest"
            } else {
                "measured over the log's initial rest"
            }
        ),
        None => "no noise correction: the log has no initial rest and no --accel-noise or \
                 --gyro-noise was given (the sensors' noise then pulls the damping up and \
                 the inertia down: see docs/fitting-and-tuning.md)"
            .to_string(),
    };
    let mut s = Fit3dSettings {
        target: o.target,
        skip: o.skip.max(1.0),
        smoothing_hz: o.smoothing_hz,
        encoder_offsets: !o.no_encoder_offset,
        noise,
        ..Fit3dSettings::default()
    };
    s.lm.max_iterations = o.max_iterations;
    (s, said)
}
