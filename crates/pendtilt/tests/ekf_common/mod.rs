//! Shared by the ekf_* tests: the scooter ride with a pivot offset, and running estimators
//! over it.
#![allow(dead_code)]
use pendtilt::bank::planar::build;
use pendtilt::core::estimators::{alg1::*, alg2::*, alg3::*};
use pendtilt::core::kalman::{KalmanOn, KalmanSettings};
use pendtilt::core::{PendulumParams, PlanarEstimator, Sample};
use pendtilt::peers::PeerSettings;
use pendtilt::report::metrics::{lag_by_xcorr, ErrorSamples};
use pendtilt::sim::planar::{simulate, Scenario, SimRow};

/// Pivot offset l12 of the test rig [m]: the pendulum 20 cm above the rotation axis.
pub const L12: f64 = 0.2;
/// Samples ignored at the start (2 s at 1 kHz: start-up of every filter).
pub const SKIP: usize = 2000;

/// The `scooter` scenario (vibration on) with l12 = [`L12`], `duration` seconds.
pub fn scooter(duration: f64) -> Scenario {
    let mut sc = Scenario::named("scooter").expect("named scenario");
    sc.pendulum.pivot_offset = L12;
    sc.duration = duration;
    sc
}

/// A simulated log: samples, exact truth, the rig's normalised parameters and gravity.
pub struct Ride {
    /// The sensor samples.
    pub samples: Vec<Sample<f64>>,
    /// The true tilt.
    pub truth: Vec<f64>,
    /// The potentiometer reading (truth with its noise), as a log would have it.
    pub pot: Vec<f64>,
    /// a, b, c.
    pub params: PendulumParams<f64>,
    /// g.
    pub gravity: f64,
}

/// Simulates `scenario` with `seed`.
pub fn ride(scenario: &Scenario, seed: u64) -> Ride {
    let rows: Vec<SimRow> = simulate(scenario, seed).expect("simulation runs");
    let phys = scenario.physical();
    Ride {
        samples: rows.iter().map(|r| r.sample()).collect(),
        truth: rows.iter().map(|r| r.truth.theta).collect(),
        pot: rows.iter().map(|r| r.theta).collect(),
        params: phys.normalised(),
        gravity: phys.gravity,
    }
}

/// RMS error [deg], bias [deg] and lag [ms] of one estimator over a ride.
#[derive(Debug, Clone, Copy)]
pub struct Score {
    /// RMS error [deg].
    pub rms_deg: f64,
    /// Mean error [deg].
    pub bias_deg: f64,
    /// Lag behind the truth by cross-correlation [ms] (positive: late).
    pub lag_ms: f64,
    /// Wall time per sample [ns]: indicative only (a test run, maybe beside other
    /// work); the bench is the reference.
    pub ns_per_sample: f64,
}

/// Runs `e` over the ride and scores it after [`SKIP`] samples.
pub fn score(e: &mut dyn PlanarEstimator<f64>, r: &Ride) -> Score {
    let t0 = std::time::Instant::now();
    let est: Vec<f64> = r.samples.iter().map(|s| e.update(s).theta).collect();
    let ns = t0.elapsed().as_nanos() as f64 / r.samples.len() as f64;
    let es = ErrorSamples::new(&est[SKIP..], &r.truth[SKIP..]).expect("lengths match");
    let lag = lag_by_xcorr(&est[SKIP..], &r.truth[SKIP..], 1000.0, 0.5)
        .map(|l| l.lag_s * 1e3)
        .unwrap_or(f64::NAN);
    Score {
        rms_deg: es.rms().to_degrees(),
        bias_deg: es.bias().to_degrees(),
        lag_ms: lag,
        ns_per_sample: ns,
    }
}

/// The paper's estimators and this issue's, by column name, for the ride's rig.
pub fn estimator(name: &str, r: &Ride) -> Box<dyn PlanarEstimator<f64>> {
    let p = r.params;
    match name {
        "alg1" => Box::new(Alg1::<f64>::new(Alg1Settings::from_params(p))),
        "alg2" => Box::new(Alg2::<f64>::new(Alg2Settings::from_params(p))),
        "alg3" => Box::new(Alg3::<f64>::new(Alg3Settings::from_params(p))),
        "kf_alg2" => {
            let k = KalmanSettings::default();
            Box::new(KalmanOn::new(
                Alg2::<f64>::new(Alg2Settings::from_params(p)),
                k.r_pendulum,
                k,
            ))
        }
        other => build(other, &p, r.gravity, &PeerSettings::default()).expect("known column"),
    }
}
