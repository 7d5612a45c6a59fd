//! The sensor sets ([`Inputs`]): which of the encoders, the gyro and the accelerometer a
//! log provides or an estimator reads, planar (`phi`, `gyro`, `ax/ay`) and 3-D (`phi_x/y`,
//! `gyro_x/y/z`, `ax/ay/az`) alike, and the gap rule ([`RESTART_GAP`]). The ground floor:
//! the catalogue of estimators, the banks, the reader and the unit checks all use it.

/// A sensor whose readings are all missing for longer than this \[s\] restarts the
/// estimators that read it (the banks' default `restart_gap`); the readers take a time step
/// this long as a new time base. Shorter gaps are bridged: each estimator holds its input
/// (or predicts) and resumes; longer ones restart it, because after them a held gyro rate
/// has been integrated for too long (Madgwick and Mahony were left 180 and 110 deg off
/// after a 10 s gap and never came back).
pub const RESTART_GAP: f64 = 0.5;

/// The sensors a log provides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Inputs {
    /// `phi` (encoder).
    pub phi: bool,
    /// `gyro`.
    pub gyro: bool,
    /// `ax` and `ay` (accelerometer).
    pub accel: bool,
}

impl Inputs {
    /// All sensors present.
    pub const ALL: Inputs = Inputs {
        phi: true,
        gyro: true,
        accel: true,
    };
    /// The encoders alone.
    pub const PHI: Inputs = Inputs {
        phi: true,
        gyro: false,
        accel: false,
    };
    /// The accelerometer alone.
    pub const ACCEL: Inputs = Inputs {
        phi: false,
        gyro: false,
        accel: true,
    };
    /// The encoders and the gyro.
    pub const PHI_GYRO: Inputs = Inputs {
        phi: true,
        gyro: true,
        accel: false,
    };
    /// The gyro and the accelerometer: an IMU.
    pub const IMU: Inputs = Inputs {
        phi: false,
        gyro: true,
        accel: true,
    };

    /// True when the two sets share a sensor.
    pub fn intersects(self, other: Inputs) -> bool {
        (self.phi && other.phi) || (self.gyro && other.gyro) || (self.accel && other.accel)
    }

    /// True when no sensor is in the set.
    pub fn is_empty(self) -> bool {
        !(self.phi || self.gyro || self.accel)
    }

    /// The sensor names of the set (`phi`, `gyro`, `ax/ay`).
    pub fn names(self) -> Vec<&'static str> {
        Inputs::default().lacking(self)
    }

    /// True when this set has every sensor of `need`.
    pub fn covers(self, need: Inputs) -> bool {
        (self.phi || !need.phi) && (self.gyro || !need.gyro) && (self.accel || !need.accel)
    }

    /// Names of the sensors of `need` this set lacks.
    pub fn lacking(self, need: Inputs) -> Vec<&'static str> {
        let mut v = Vec::new();
        if need.phi && !self.phi {
            v.push("phi");
        }
        if need.gyro && !self.gyro {
            v.push("gyro");
        }
        if need.accel && !self.accel {
            v.push("ax/ay");
        }
        v
    }
}

/// The sensors in either set.
pub fn union(a: Inputs, b: Inputs) -> Inputs {
    Inputs {
        phi: a.phi || b.phi,
        gyro: a.gyro || b.gyro,
        accel: a.accel || b.accel,
    }
}
