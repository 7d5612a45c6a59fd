//! The sensors a log can carry, in one table: each one's columns (planar and 3-D), unit,
//! physical bound and whether a 3-D log must have it. The readers, the plausibility checks,
//! the gap rule and the sensor sets of the std crate all walk this table, so that a new
//! sensor is a new row here, a field of [`crate::model::SpatialSample`] and the measurement that
//! reads it.

/// One sensor (all its axes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sensor {
    /// The pendulum's encoders (`phi`; 3-D `phi_x`, `phi_y`).
    Encoder,
    /// The rate gyro (`gyro`; 3-D `gyro_x..z`).
    Gyro,
    /// The accelerometer (`ax`, `ay`; 3-D `ax..az`).
    Accel,
}

/// What the readers and checks need to know of a [`Sensor`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorSpec {
    /// The sensor.
    pub sensor: Sensor,
    /// Its short name, as an API names it (`phi`, `gyro`, `accel`).
    pub name: &'static str,
    /// Its columns in a planar log (MODEL.md 5); empty when a planar log has none.
    pub planar_columns: &'static [&'static str],
    /// Its name in planar messages (`ax/ay`).
    pub planar_label: &'static str,
    /// Its columns in a 3-D log (MODEL.md 7.6), in the sample's axis order.
    pub spatial_columns: &'static [&'static str],
    /// Its name in 3-D messages (`gyro_x/y/z`).
    pub spatial_label: &'static str,
    /// A 3-D log must have every one of its columns.
    pub spatial_required: bool,
    /// Its SI unit, as messages write it.
    pub unit: &'static str,
    /// The largest reading a 3-D log's sensor of this kind can give, in `unit`, when the
    /// rig gives no full scale: beyond it a reading is impossible and read as missing.
    pub spatial_limit: f64,
    /// Its readings are angles or rates, read in degrees under `--deg`.
    pub angular: bool,
}

/// The sensors, in [`Sensor`] order.
pub const SENSORS: [SensorSpec; 3] = [
    SensorSpec {
        sensor: Sensor::Encoder,
        name: "phi",
        planar_columns: &["phi"],
        planar_label: "phi",
        spatial_columns: &["phi_x", "phi_y"],
        spatial_label: "phi_x/phi_y",
        spatial_required: true,
        unit: "rad",
        // A Cardan joint's encoders read within (-pi, pi] (MODEL.md 7.2).
        spatial_limit: core::f64::consts::PI,
        angular: true,
    },
    SensorSpec {
        sensor: Sensor::Gyro,
        name: "gyro",
        planar_columns: &["gyro"],
        planar_label: "gyro",
        spatial_columns: &["gyro_x", "gyro_y", "gyro_z"],
        spatial_label: "gyro_x/y/z",
        spatial_required: true,
        unit: "rad/s",
        // 5730 deg/s, 16 turns a second: well beyond the largest full scale of MEMS rate
        // gyros (2000 to 4000 deg/s) and any rate a body carrying a pendulum survives.
        spatial_limit: 100.0,
        angular: true,
    },
    SensorSpec {
        sensor: Sensor::Accel,
        name: "accel",
        planar_columns: &["ax", "ay"],
        planar_label: "ax/ay",
        spatial_columns: &["ax", "ay", "az"],
        spatial_label: "ax/ay/az",
        spatial_required: true,
        unit: "m/s^2",
        // 51 g: beyond the 16 g of common MEMS accelerometers and the shocks a rig survives.
        spatial_limit: 500.0,
        angular: false,
    },
];

/// How many sensors [`SENSORS`] lists.
pub const SENSOR_COUNT: usize = SENSORS.len();

impl Sensor {
    /// Every sensor, in table order.
    pub const ALL: [Sensor; SENSOR_COUNT] = {
        let mut all = [Sensor::Encoder; SENSOR_COUNT];
        let mut i = 0;
        while i < SENSOR_COUNT {
            all[i] = SENSORS[i].sensor;
            i += 1;
        }
        all
    };

    /// Its place in [`SENSORS`] (and in any per-sensor array).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Its row of [`SENSORS`].
    pub const fn spec(self) -> &'static SensorSpec {
        &SENSORS[self as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_in_sensor_order_and_every_sensor_has_columns() {
        for (i, s) in Sensor::ALL.iter().enumerate() {
            assert_eq!(s.index(), i);
            assert_eq!(s.spec().sensor, *s);
            assert!(!s.spec().spatial_columns.is_empty());
        }
        assert_eq!(Sensor::Accel.spec().spatial_columns, ["ax", "ay", "az"]);
    }
}
