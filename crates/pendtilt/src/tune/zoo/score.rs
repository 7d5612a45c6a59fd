//! One zoo ride scored: the RMS error against the true tilt of `ekf`, `kf_alg2`, `alg1`
//! and `alg2` with the rig's defaults, self-tuned on the log alone ([`crate::tune::tune`],
//! no true angle), and tuned by a brute-force grid against the true angle (the oracle).
//!
//! Every figure comes from the estimators as `pendtilt estimate` builds them from a rig
//! file ([`crate::bank::planar::Bank`]); the grids search with the same filters run directly
//! (the Kalman filter's arithmetic through [`crate::tune::kalman::innovation_pass`]) and
//! the best point found is then run through the bank. The oracle's grids:
//! - alg1, alg2: the differentiator cutoff, 0.4-10 times the natural frequency (17
//!   points, log-spaced) and the default, each estimator on its own;
//! - kf_alg2: Algorithm 2's cutoff (the default, the self-tuned, alg2's oracle) x q_angle
//!   1e-9..10 (a point per decade) x q_bias {1e-9, 1e-7, 1e-5, 1e-3, 3e-3} x R 1e-8..1
//!   (two points per decade);
//! - ekf: the sensor figures (the defaults, or the simulator's true ones) x the tilt-jerk
//!   and pendulum-forcing densities at 1e-3..1e3 times their defaults (a point per
//!   decade), the adaptation off (fixed figures, as the self-tuned).
use super::Ride;
use crate::bank::planar::{build_alone, Bank, BankSettings, Inputs};
use crate::config::{EkfConfig, RigConfig};
use crate::peers::{self, PeerSettings};
use crate::sim::planar::{simulate, Scenario};
use crate::tune::kalman::{innovation_pass, KalmanData};
use crate::tune::{rig_file, tune, Options, Start};
use pendtilt_core::ekf::{Ekf, ModelSettings, SensorNoise};
use pendtilt_core::estimators::alg2::Alg2;
use pendtilt_core::filters::diff::{Cutoff, DiffSettings};
use pendtilt_core::kalman::tilt::UNUSABLE;
use pendtilt_core::{Estimator, Sample};
use std::time::Instant;

/// The estimators scored, in table order.
pub const ESTIMATORS: [&str; 4] = ["ekf", "kf_alg2", "alg1", "alg2"];

/// Seconds at the start of a ride left out of every RMS (the filters settle).
pub const SKIP_SECONDS: f64 = 2.0;

/// A ride's log: samples and the true tilt per row.
pub struct RideLog {
    /// The sensor samples.
    pub samples: Vec<Sample<f64>>,
    /// The true tilt \[rad\].
    pub truth: Vec<f64>,
    /// Rows left out of the RMS.
    pub skip: usize,
}

impl RideLog {
    /// Simulates `scenario` with `seed`.
    pub fn simulate(scenario: &Scenario, seed: u64) -> Self {
        // The zoo's scenarios are checked by its tests; an error here is a bug in it.
        let rows = simulate(scenario, seed).expect("a zoo scenario simulates");
        Self {
            samples: rows.iter().map(|r| r.sample()).collect(),
            truth: rows.iter().map(|r| r.truth.theta).collect(),
            skip: (SKIP_SECONDS * scenario.rate).round() as usize,
        }
    }

    /// RMS \[rad\] of `est` (one angle per row) against the truth after `skip`.
    fn rms(&self, est: impl Iterator<Item = f64>) -> f64 {
        let (mut sum, mut n) = (0.0, 0usize);
        for (k, (e, t)) in est.zip(&self.truth).enumerate() {
            if k >= self.skip && e.is_finite() && t.is_finite() {
                sum += (e - t).powi(2);
                n += 1;
            }
        }
        if n == 0 {
            f64::INFINITY
        } else {
            (sum / n as f64).sqrt()
        }
    }
}

/// The RMS error \[rad\] of each of [`ESTIMATORS`] as the bank builds them from `rig`.
pub fn bank_rms(rig: &RigConfig, log: &RideLog) -> [f64; 4] {
    let only: Vec<String> = ESTIMATORS.iter().map(|s| s.to_string()).collect();
    let settings = BankSettings::from_rig(rig.clone());
    let Ok(mut bank) = Bank::new(&settings, Inputs::ALL, Some(&only)) else {
        return [f64::INFINITY; 4];
    };
    let names: Vec<&str> = bank.names().to_vec();
    let mut cols = vec![Vec::with_capacity(log.samples.len()); names.len()];
    let mut out = Vec::new();
    for s in &log.samples {
        bank.update(s, &mut out);
        for (c, e) in cols.iter_mut().zip(&out) {
            c.push(e.theta);
        }
    }
    ESTIMATORS.map(|name| {
        names
            .iter()
            .position(|n| *n == name)
            .map_or(f64::INFINITY, |i| log.rms(cols[i].iter().copied()))
    })
}

/// `rig` with the differentiator's cutoff at `x` times the natural frequency.
fn with_cutoff(rig: &RigConfig, x: f64) -> RigConfig {
    let mut r = rig.clone();
    r.differentiator = DiffSettings {
        cutoff: Cutoff::TimesNatural(x),
        ..r.differentiator
    };
    r
}

/// The oracle cutoff multiple of `name` (alg1 or alg2) and its RMS \[rad\].
fn oracle_cutoff(name: &str, rig: &RigConfig, log: &RideLog) -> (f64, f64) {
    let default = match DiffSettings::<f64>::default().cutoff {
        Cutoff::TimesNatural(x) => x,
        Cutoff::Hz(f) => f / rig.params().natural_frequency_hz(),
    };
    let grid = (0..17).map(|k| 0.4 * 25f64.powf(k as f64 / 16.0));
    let mut best = (default, f64::INFINITY);
    for x in std::iter::once(default).chain(grid) {
        let settings = BankSettings::from_rig(with_cutoff(rig, x));
        let Some(mut e) = build_alone(name, &settings) else {
            continue;
        };
        let r = log.rms(log.samples.iter().map(|s| e.update(s).theta));
        if r < best.1 {
            best = (x, r);
        }
    }
    best
}

/// The oracle Kalman settings: `rig` with the grid's best cutoff, q_angle, q_bias and R.
fn oracle_kalman(rig: &RigConfig, cutoffs: &[f64], log: &RideLog) -> RigConfig {
    let dt: Vec<f64> = log.samples.iter().map(|s| s.dt).collect();
    let gyro: Vec<f64> = log.samples.iter().map(|s| s.gyro).collect();
    let mut best = (f64::INFINITY, rig.clone());
    for &x in cutoffs {
        let r = with_cutoff(rig, x);
        let mut alg2 = Alg2::<f64>::new(r.alg2_settings());
        let z: Vec<f64> = log
            .samples
            .iter()
            .map(|s| {
                let m = alg2.update(s);
                if m.flags.intersects(UNUSABLE) {
                    f64::NAN
                } else {
                    m.theta
                }
            })
            .collect();
        let d = KalmanData {
            dt: &dt,
            gyro: &gyro,
            z: &z,
        };
        for qa in (0..=10).map(|k| 10f64.powi(k - 9)) {
            for qb in [1e-9, 1e-7, 1e-5, 1e-3, 3e-3] {
                for rp in (0..=16).map(|k| 10f64.powf(-8.0 + 0.5 * k as f64)) {
                    let mut s = r.kalman_settings();
                    s.q_angle = qa;
                    s.q_bias = qb;
                    let mut th = Vec::with_capacity(z.len());
                    innovation_pass(&s, rp, &d, |_, t, _, _| th.push(t));
                    let e = log.rms(th.into_iter());
                    if e < best.0 {
                        let mut rr = r.clone();
                        rr.kalman.q_angle = qa;
                        rr.kalman.q_bias = qb;
                        rr.kalman.r_pendulum = rp;
                        best = (e, rr);
                    }
                }
            }
        }
    }
    best.1
}

/// The simulator's true sensor figures as the EKF takes them.
fn true_sensors(s: &Scenario) -> SensorNoise<f64> {
    let g = &s.sensors;
    SensorNoise {
        encoder_bits: g.encoder.bits,
        encoder_noise: g.encoder.noise,
        gyro_density: g.gyro.noise_density,
        gyro_bias_walk: g.gyro.bias_walk,
        gyro_bias: g.gyro.bias.abs().max(1e-4),
        accel_density: g.accel.noise_density,
    }
}

/// The oracle EKF settings as an `[ekf]` table.
fn oracle_ekf(rig: &RigConfig, scenario: &Scenario, log: &RideLog) -> EkfConfig {
    let base = peers::model_settings(&rig.params(), rig.gravity(), &PeerSettings::default());
    let truth_sensors = ModelSettings::derived(
        rig.params(),
        rig.gravity(),
        true_sensors(scenario),
        &PeerSettings::default().environment,
    );
    // Fixed figures: the best the log's own noise can be set to.
    let (base, truth_sensors) = (base.fixed(), truth_sensors.fixed());
    let mut best = (f64::INFINITY, EkfConfig::from_settings(&base));
    for start in [base, truth_sensors] {
        for j in (-3..=3).map(|k| 10f64.powi(k)) {
            for p in (-3..=3).map(|k| 10f64.powi(k)) {
                let mut s = start;
                s.process.jerk *= j;
                s.process.pendulum *= p;
                let mut e = Ekf::new(s);
                let r = log.rms(log.samples.iter().map(|x| e.update(x).theta));
                if r < best.0 {
                    best = (r, EkfConfig::from_settings(&s));
                }
            }
        }
    }
    best.1
}

/// A ride's scores: RMS \[rad\] per estimator of [`ESTIMATORS`].
#[derive(Debug, Clone)]
pub struct RideScore {
    /// The ride.
    pub ride: Ride,
    /// With the rig's defaults.
    pub defaults: [f64; 4],
    /// With the rig's defaults, the ekf's adaptation off (`[ekf] adapt = false`): the
    /// defaults as they were before it.
    pub defaults_fixed: [f64; 4],
    /// Self-tuned (no true angle).
    pub tuned: [f64; 4],
    /// Tuned by the grid against the true angle.
    pub oracle: [f64; 4],
    /// Wall time of the self-tuning \[s\].
    pub tune_seconds: f64,
}

/// Simulates `ride` and scores it (module documentation).
pub fn score(ride: &Ride) -> RideScore {
    let log = RideLog::simulate(&ride.scenario, ride.index);
    // The user knows their pendulum (`pendtilt fit`): the rig is the simulator's.
    let rig = ride.scenario.rig().unwrap_or_else(|_| RigConfig::default());
    let defaults = bank_rms(&rig, &log);
    let mut fixed_rig = rig.clone();
    fixed_rig.ekf.adapt = Some(false);
    let defaults_fixed = bank_rms(&fixed_rig, &log);
    let t0 = Instant::now();
    let t = tune(&log.samples, &Start::from_rig(&rig), &Options::default());
    let tune_seconds = t0.elapsed().as_secs_f64();
    let tuned_rig = rig_file::tuned_rig(&rig, &t);
    let tuned = bank_rms(&tuned_rig, &log);
    let (_, e1) = oracle_cutoff("alg1", &rig, &log);
    let (x2, e2) = oracle_cutoff("alg2", &rig, &log);
    let tuned_x = match t.differentiator.cutoff {
        Cutoff::TimesNatural(x) => x,
        Cutoff::Hz(f) => f / rig.params().natural_frequency_hz(),
    };
    let default_x = match rig.differentiator.cutoff {
        Cutoff::TimesNatural(x) => x,
        Cutoff::Hz(f) => f / rig.params().natural_frequency_hz(),
    };
    let mut oracle_rig = oracle_kalman(&rig, &[default_x, tuned_x, x2], &log);
    oracle_rig.ekf = oracle_ekf(&rig, &ride.scenario, &log);
    let o = bank_rms(&oracle_rig, &log);
    RideScore {
        ride: ride.clone(),
        defaults,
        defaults_fixed,
        tuned,
        oracle: [o[0], o[1], e1, e2],
        tune_seconds,
    }
}
