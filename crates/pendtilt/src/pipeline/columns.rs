//! How a log's columns are named and in which units, as every command that reads a log
//! takes them.
use crate::config::RigConfig;
use crate::io::{AccelUnit, ColumnMap, DegreeColumns, NegatedColumns, ReaderOptions, TimeUnit};

/// How a log's columns are named and in which units: what every command that reads a log
/// takes (`--map`, `--deg`, `--time-unit`, `--accel-unit`), defined here once.
#[derive(Debug, Clone, clap::Args)]
pub struct LogColumns {
    /// Other column names, e.g. `phi=enc_angle,gyro=gz`. Default: none, the MODEL.md
    /// names (t, phi, gyro, ax, ay, theta).
    #[arg(long, default_value = "", hide_default_value = true)]
    pub map: ColumnMap,
    /// Angular columns in degrees: alone, every one (phi, gyro, theta); or a list like
    /// `phi,theta`. Default: none, all in rad and rad/s.
    #[arg(long, num_args = 0..=1, default_missing_value = "all")]
    pub deg: Option<DegreeColumns>,
    /// Unit of the `t` column: s, ms, us or ns. Default: seconds, and a log whose time
    /// steps no sensor rate explains (10 Hz to 1 MHz) is refused with the unit to give here.
    #[arg(long, value_name = "UNIT")]
    pub time_unit: Option<TimeUnit>,
    /// Unit of the accelerometer columns (ax, ay; and az on a 3-D log): m/s2, g or mg.
    /// Default: m/s2, and a log whose specific force is not gravity's in size (its median
    /// magnitude off 9.81 m/s^2 by more than 2x) is told with the unit to give here.
    #[arg(long, value_name = "UNIT")]
    pub accel_unit: Option<AccelUnit>,
    /// Columns that count the other way from MODEL.md section 1's signs (an encoder or a
    /// gyro mounted the other way round), negated as read: a list like `phi,gyro`.
    /// Default: none. A log whose signs disagree with each other is told with the list to
    /// give here. Planar logs only.
    #[arg(long, value_name = "COLUMNS")]
    pub negate: Option<NegatedColumns>,
}

impl LogColumns {
    /// How a planar log is read with these columns and units, and what the rig tells (its
    /// full scales, its pendulum's frequency: [`ReaderOptions::for_rig`]).
    pub fn reader_options(&self, rig: &RigConfig) -> ReaderOptions {
        ReaderOptions {
            map: self.map.clone(),
            degrees: self.deg.unwrap_or_default(),
            time_unit: self.time_unit,
            accel_unit: self.accel_unit,
            negate: self.negate.unwrap_or_default(),
            ..ReaderOptions::for_rig(rig)
        }
    }
}
