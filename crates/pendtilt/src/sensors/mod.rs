//! The sensor sets ([`Inputs`]): which sensors of the core's table
//! ([`pendtilt_core::model::SENSORS`]: the encoders, the gyro, the accelerometer) a log
//! provides or an estimator reads, planar and 3-D alike, and the gap rule
//! ([`RESTART_GAP`], [`GapWatch`]). The ground floor: the catalogue of estimators, the banks, the readers
//! and the unit checks all use it. A set names no sensor itself, so a sensor added to the
//! table needs no change here.
pub use pendtilt_core::model::{Sensor, SensorSpec, SENSORS};

mod gaps;
pub use gaps::{GapEnd, GapWatch};

/// A sensor whose readings are all missing for longer than this \[s\] restarts the
/// estimators that read it (the banks' default `restart_gap`); the readers take a time step
/// this long as a new time base. Shorter gaps are bridged: each estimator holds its input
/// (or predicts) and resumes; longer ones restart it, because after them a held gyro rate
/// has been integrated for too long (Madgwick and Mahony were left 180 and 110 deg off
/// after a 10 s gap and never came back).
pub const RESTART_GAP: f64 = 0.5;

/// A set of sensors: those a log provides, an estimator reads, or a row has gaps,
/// clips or impossible readings in. A bit per row of [`SENSORS`], as
/// [`pendtilt_core::Flags`] is a bit per event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Inputs(u32);

impl Inputs {
    /// No sensor.
    pub const NONE: Inputs = Inputs(0);
    /// The encoders alone.
    pub const PHI: Inputs = Inputs::of(Sensor::Encoder);
    /// The gyro alone.
    pub const GYRO: Inputs = Inputs::of(Sensor::Gyro);
    /// The accelerometer alone.
    pub const ACCEL: Inputs = Inputs::of(Sensor::Accel);
    /// The encoders and the gyro.
    pub const PHI_GYRO: Inputs = Inputs::PHI.with(Sensor::Gyro);
    /// The gyro and the accelerometer: an IMU.
    pub const IMU: Inputs = Inputs::GYRO.with(Sensor::Accel);
    /// Every sensor of the table.
    pub const ALL: Inputs = Inputs((1 << SENSORS.len()) - 1);

    /// The set of one sensor.
    pub const fn of(sensor: Sensor) -> Inputs {
        Inputs(1 << sensor.index())
    }

    /// This set and `sensor`.
    pub const fn with(self, sensor: Sensor) -> Inputs {
        Inputs(self.0 | Inputs::of(sensor).0)
    }

    /// This set without `sensor`.
    pub const fn without(self, sensor: Sensor) -> Inputs {
        Inputs(self.0 & !Inputs::of(sensor).0)
    }

    /// The sensors for which `pick` is true.
    pub fn from_fn(mut pick: impl FnMut(Sensor) -> bool) -> Inputs {
        Sensor::ALL
            .into_iter()
            .filter(|s| pick(*s))
            .fold(Inputs::NONE, Inputs::with)
    }

    /// True when `sensor` is in the set.
    pub const fn has(self, sensor: Sensor) -> bool {
        self.0 & Inputs::of(sensor).0 != 0
    }

    /// The sensors of the set, in table order.
    pub fn iter(self) -> impl Iterator<Item = Sensor> {
        Sensor::ALL.into_iter().filter(move |s| self.has(*s))
    }

    /// True when the two sets share a sensor.
    pub const fn intersects(self, other: Inputs) -> bool {
        self.0 & other.0 != 0
    }

    /// True when no sensor is in the set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// True when this set has every sensor of `need`.
    pub const fn covers(self, need: Inputs) -> bool {
        need.0 & !self.0 == 0
    }

    /// The sensors in either set.
    pub const fn union(self, other: Inputs) -> Inputs {
        Inputs(self.0 | other.0)
    }

    /// The sensor names of the set, as a planar log names them (`phi`, `gyro`, `ax/ay`).
    pub fn names(self) -> Vec<&'static str> {
        Inputs::NONE.lacking(self)
    }

    /// Names of the sensors of `need` this set lacks, as a planar log names them.
    pub fn lacking(self, need: Inputs) -> Vec<&'static str> {
        need.iter()
            .filter(|s| !self.has(*s))
            .map(|s| s.spec().planar_label)
            .collect()
    }

    /// The 3-D log's columns of the set, for messages (`phi_x/phi_y, gyro_x/y/z`).
    pub fn spatial_names(self) -> String {
        self.iter()
            .map(|s| s.spec().spatial_label)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl std::ops::BitOr for Inputs {
    type Output = Inputs;
    fn bitor(self, other: Inputs) -> Inputs {
        self.union(other)
    }
}

impl std::ops::BitOrAssign for Inputs {
    fn bitor_assign(&mut self, other: Inputs) {
        *self = self.union(other);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_hold_the_sensors_put_in_them() {
        let s = Inputs::of(Sensor::Gyro).with(Sensor::Accel);
        assert_eq!(s, Inputs::IMU);
        assert!(s.has(Sensor::Gyro) && !s.has(Sensor::Encoder));
        assert_eq!(s.without(Sensor::Gyro), Inputs::ACCEL);
        assert!(Inputs::ALL.covers(s) && !s.covers(Inputs::ALL));
        assert!(Inputs::NONE.is_empty() && Inputs::NONE.covers(Inputs::NONE));
        assert!(s.intersects(Inputs::GYRO) && !s.intersects(Inputs::PHI));
        assert_eq!(Inputs::from_fn(|x| x != Sensor::Encoder), Inputs::IMU);
        assert_eq!(Inputs::PHI | Inputs::GYRO, Inputs::PHI_GYRO);
        assert_eq!(Inputs::ALL.iter().count(), SENSORS.len());
    }

    #[test]
    fn names_follow_the_table() {
        let planar = Inputs::PHI | Inputs::GYRO | Inputs::ACCEL;
        assert_eq!(planar.names(), ["phi", "gyro", "ax/ay"]);
        assert_eq!(Inputs::PHI.lacking(planar), ["gyro", "ax/ay"]);
        assert_eq!(Inputs::PHI_GYRO.spatial_names(), "phi_x/phi_y, gyro_x/y/z");
    }
}
