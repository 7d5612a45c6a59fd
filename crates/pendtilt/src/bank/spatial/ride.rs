//! What a ride report runs besides the bank: the filter that uses the
//! `speed` column, once more without it, and which estimators are the peers.
use pendtilt_core::spatial::SpatialSample;

use super::RollPitch;
use super::{Bank3d, Settings3d, REGISTRY3D};
use crate::catalogue::Family;

/// The estimator that uses the speed.
pub const COMPENSATED: &str = "ekf3d";

/// The name of its run without the speed.
pub const UNCOMPENSATED: &str = "ekf3d without speed";

/// How that run is made (for the page).
pub const HOW: &str = "the same ekf3d, same settings and samples, with the speed left out \
    (NaN, as a log without a `speed` column gives it): it then takes the vehicle as not \
    accelerating, as every IMU filter does";

/// The peers: the 3-D estimators of the catalogue's peer family (IMU filters from
/// elsewhere; imu3d, ekf3d's own filter on the accelerometer, is not one).
pub fn peers() -> Vec<String> {
    REGISTRY3D
        .iter()
        .filter(|e| e.listing().family == Family::Peers)
        .map(|e| e.name.to_string())
        .collect()
}

/// A vehicle moves when its speed is above this \[m/s\] ...
pub const MOVING_SPEED: f64 = 0.5;

/// ... in at least this fraction of the rows: a standing scooter's noisy speed sensor
/// (0.05 m/s) does not make a ride, a ride that stops at lights does.
pub const MOVING_FRACTION: f64 = 0.01;

/// Whether a log's `speed` (NaN where missing, or without the column) says the vehicle
/// moves: `|speed| > MOVING_SPEED` in at least `MOVING_FRACTION` of the rows.
pub fn moves(speed: &[f64]) -> bool {
    let fast = speed.iter().filter(|v| v.abs() > MOVING_SPEED).count();
    !speed.is_empty() && fast as f64 >= MOVING_FRACTION * speed.len() as f64
}

/// [`COMPENSATED`] run sample by sample with the speed left out.
#[derive(Debug)]
pub struct WithoutSpeed {
    bank: Bank3d,
    out: RollPitch,
}

impl WithoutSpeed {
    /// A run with `settings`.
    pub fn new(settings: &Settings3d) -> Self {
        let bank = Bank3d::new(settings, Some(&[COMPENSATED.to_string()]))
            .expect("COMPENSATED is in the registry");
        Self {
            bank,
            out: RollPitch {
                name: UNCOMPENSATED.into(),
                roll: Vec::new(),
                pitch: Vec::new(),
            },
        }
    }

    /// One sample (its speed ignored).
    pub fn update(&mut self, s: &SpatialSample<f64>) {
        let a = self.bank.update(&SpatialSample {
            speed: f64::NAN,
            ..*s
        })[0];
        self.out.roll.push(a.roll);
        self.out.pitch.push(a.pitch);
    }

    /// The run: [`UNCOMPENSATED`]'s roll and pitch, one per sample given.
    pub fn run(self) -> RollPitch {
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_peers_are_the_imu_filters_and_the_compensated_one_exists() {
        let p = peers();
        assert!(p.contains(&"vqf".to_string()) && p.contains(&"madgwick3d".to_string()));
        assert!(!p
            .iter()
            .any(|n| n == "ekf3d" || n == "accel3d" || n == "pendulum3d"));
        assert!(REGISTRY3D.iter().any(|e| e.name == COMPENSATED));
    }

    #[test]
    fn a_vehicle_moves_when_its_speed_says_so() {
        assert!(!moves(&[]));
        assert!(!moves(&[f64::NAN; 100]));
        let mut v = vec![0.05; 1000];
        assert!(!moves(&v));
        v[..10].fill(3.0);
        assert!(moves(&v));
        v[..10].fill(-3.0); // reversing
        assert!(moves(&v));
    }
}
