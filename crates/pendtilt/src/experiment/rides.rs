//! The built-in data: simulated rides held in memory as sensor samples and the true angle.
use pendtilt_core::Sample;

use crate::sensors::Inputs;

use crate::sim::planar::{Scenario, SimError, Simulator};

use super::progress::{Progress, CHUNK};

/// One simulated (or read) record: time, sensor samples, the true angle and its second
/// derivative when known.
#[derive(Debug, Clone, PartialEq)]
pub struct Ride {
    /// What it is, in words ("scooter test ride, seed 1").
    pub label: String,
    /// Time of each sample \[s\].
    pub t: Vec<f64>,
    /// Sensor readings.
    pub samples: Vec<Sample<f64>>,
    /// The true tilt as the rig measures it (the potentiometer reading) \[rad\].
    pub theta: Vec<f64>,
    /// The exact theta'' \[rad/s^2\] (simulated rides only; empty for logs).
    pub theta_dd: Vec<f64>,
    /// The sensors read at a clip found in the log itself, per sample
    /// ([`crate::io::plateau`]; empty: none).
    pub clipped: Vec<Inputs>,
}

impl Ride {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether the ride has no sample.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Duration \[s\] (last time minus first, 0 for fewer than two samples).
    pub fn duration(&self) -> f64 {
        match (self.t.first(), self.t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }
}

/// Simulates `scenario` with `seed`, reporting progress per chunk of rows.
pub fn simulate_ride(
    label: &str,
    scenario: &Scenario,
    seed: u64,
    progress: &dyn Progress,
) -> Result<Ride, SimError> {
    let sim = Simulator::new(scenario, seed)?;
    let n = usize::try_from(sim.total_rows()).unwrap_or(0);
    progress.stage(&format!("simulating {label}"), n as u64);
    let mut ride = Ride {
        label: label.to_string(),
        t: Vec::with_capacity(n),
        samples: Vec::with_capacity(n),
        theta: Vec::with_capacity(n),
        theta_dd: Vec::with_capacity(n),
        clipped: Vec::new(),
    };
    for (k, row) in sim.enumerate() {
        ride.t.push(row.t);
        ride.samples.push(row.sample());
        ride.theta.push(row.theta);
        ride.theta_dd.push(row.truth.alpha);
        if (k as u64 + 1) % CHUNK == 0 {
            progress.advance(CHUNK);
        }
    }
    progress.advance(ride.len() as u64 % CHUNK);
    Ok(ride)
}
