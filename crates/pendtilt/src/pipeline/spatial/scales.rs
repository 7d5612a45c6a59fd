//! How a 3-D log's cells become SI units (`--time-unit`, `--deg`, `--accel-unit`), once for
//! `estimate`, `fit` and `tune`, after refusing the column options only planar logs take.
use std::path::Path;

use anyhow::bail;

use super::super::LogColumns;
use crate::io::{DegreeColumns, Log3dReader, Log3dRecord, LOG3D_COLUMNS};

/// The factors a 3-D log's cells are read with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales3d {
    /// Seconds per unit of `t`.
    pub time: f64,
    /// Radians per unit of the angular columns (encoders, gyro, truth).
    pub angle: f64,
    /// m/s^2 per unit of `ax..az`.
    pub accel: f64,
}

impl Scales3d {
    /// The factors of `columns`' options; an error naming the option when it is one that
    /// only planar logs take (`--map` of a planar column, `--negate`, `--deg` with a list).
    pub fn of(columns: &LogColumns) -> anyhow::Result<Self> {
        if let Some(c) = columns.map.planar_only().first() {
            bail!(
                "--map {c}=...: a column of a planar log; a 3-D log's columns are {} \
                 (MODEL.md 7.6)",
                LOG3D_COLUMNS.join(", ")
            );
        }
        if columns.negate.is_some() {
            bail!(
                "--negate: for planar logs only; a 3-D log's columns follow MODEL.md 7.6's \
                 axes (FLU) and signs"
            );
        }
        let angle = match columns.deg {
            None => 1.0,
            Some(d) if d == DegreeColumns::all() => std::f64::consts::PI / 180.0,
            Some(_) => bail!(
                "--deg with a list: for planar logs only; on a 3-D log --deg alone reads every \
                 angular column (phi_x, phi_y, gyro_*, roll, pitch) in degrees"
            ),
        };
        Ok(Self {
            time: columns.time_unit.map_or(1.0, |u| u.seconds()),
            angle,
            accel: columns
                .accel_unit
                .map_or(1.0, |u| u.metres_per_second_squared()),
        })
    }

    /// Record `r` in SI units: its time, encoders, rates, specific force and truth (the
    /// speed is in m/s as written).
    pub fn si(&self, r: &Log3dRecord) -> Log3dRecord {
        let angle = |v: f64| v * self.angle;
        Log3dRecord {
            t: r.t * self.time,
            phi: r.phi.map(angle),
            gyro: r.gyro.map(angle),
            accel: r.accel.map(|v| v * self.accel),
            roll: r.roll.map(angle),
            pitch: r.pitch.map(angle),
            ..*r
        }
    }
}

/// Every record of the 3-D log at `path` (named `name` in errors) in SI units, with
/// `columns`' `--map`, and whether the log has a `speed` column.
pub fn read_si(
    path: &Path,
    name: &str,
    columns: &LogColumns,
) -> anyhow::Result<(Vec<Log3dRecord>, bool)> {
    let scales = Scales3d::of(columns)?;
    let mut reader = Log3dReader::open_as(path, name, columns.map.spatial())?;
    let speed = reader.has("speed");
    let mut out = Vec::new();
    while let Some(r) = reader.next_record()? {
        out.push(scales.si(&r));
    }
    Ok((out, speed))
}
