//! The 3-D fit: the Cardan pendulum's normalised parameters (MODEL.md 7.3) from a 3-D log
//! (MODEL.md 7.6), by the output error, as the planar [`super::output`] fit does.
//!
//! # What is fitted and what is held
//! The joint equations divided by m g l leave a_x, a_y, b_x, b_y, b_z, b_ring, c (= r12 / g)
//! and g. Not all of them show in a log:
//! - **a_x, a_y** (damping) and **b_y** (inner inertia): each sets its own joint's decay
//!   and frequency. Fitted.
//! - **b_x + b_ring** (the outer axis's inertia): at small inner angle b the outer joint's
//!   inertia is J_ring + Ixx cos^2 b + Izz sin^2 b; the split between b_x and b_ring shows
//!   only in terms of order b^2 and in the gyroscopic terms, far below the noise. The sum
//!   is fitted; b_ring is held at the start rig's value and b_x = sum - b_ring.
//! - **b_z**: enters only through sin^2 b and the gyroscopic terms. Held.
//! - **c_z** (the pivot's height over the IMU, over g): the pivot's motion under roll and
//!   pitch acceleration, wd x r12, forces the pendulum directly (the planar c). Fitted when
//!   the log's angular motion shows it ([`Fit3dSettings::min_offset_sensitivity`]), else
//!   held and said so.
//! - **c_x, c_y**: enter only through yaw acceleration and the centripetal terms. Held.
//! - **gravity**: the force enters as f / g, so g only scales a, b and c together with it;
//!   it is the normalisation, not a parameter of the log. Held.
//! - **Encoder offsets** (one constant per axis, phi_measured = phi + offset): fitted. A
//!   mounting offset is common, and on the gyro target an accelerometer bias tilts the
//!   simulated equilibrium by bias / g (0.02 m/s^2 is 0.12 deg), which the offsets take up.
//!   They are reported, not written: the rig file has no key for them.
//!
//! # Targets
//! [`super::Target::Gyro`] (no truth needed) drives the simulated pendulum with the log's IMU,
//! as a replay does (MODEL.md 7.10); [`super::Target::Truth`] with the true roll and pitch and
//! the accelerometer's fast part ([`drive`]).
//!
//! Minimised by the planar fit's Levenberg-Marquardt loop ([`super::lm::minimise`]) with a
//! finite-difference Jacobian ([`problem`]); the result is checked against the log
//! ([`plausibility`]).
pub mod drive;
pub mod plausibility;
pub mod problem;
mod report;
pub mod rig;
mod run;
pub mod steps;

pub use drive::Log3dColumns;
pub use plausibility::{check, Implausible3d};
pub use problem::{CardanProblem, Params};
pub use report::{damping_ratios, natural_frequencies_hz, Fit3dReport};
pub use run::fit_cardan;

use super::{LmSettings, Target};

/// Number of entries of the parameter vector ([`Params`]).
pub const NP: usize = 7;

/// The names of the parameter vector's entries, in order.
pub const NAMES: [&str; NP] = [
    "a_x",
    "a_y",
    "b_x + b_ring",
    "b_y",
    "c_z",
    "offset_x",
    "offset_y",
];

/// The units of [`NAMES`].
pub const UNITS: [&str; NP] = ["s", "s", "s^2", "s^2", "s^2", "rad", "rad"];

/// The size of c_z the identifiability check moves it by \[s^2\]: a 1 cm pivot offset
/// over g (the start's c_z is usually 0, so no relative size exists).
pub const C_SCALE: f64 = 0.01 / 9.80665;

/// Everything a 3-D fit is told.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit3dSettings {
    /// What drives the simulated pendulum. Default [`Target::Truth`].
    pub target: Target,
    /// Seconds at the start left out of the cost while the simulated pendulum forgets its
    /// start state. Default 1 s.
    pub skip: f64,
    /// Truth target: cutoff of the zero-phase low-pass on the true roll and pitch before
    /// they are differentiated \[Hz\]. Default 20 Hz (the planar output cost's).
    pub smoothing_hz: f64,
    /// Truth target: the accelerometer adds its part above this to the true gravity
    /// direction \[Hz\] (0: all of it; infinite: none). Default 0.02 Hz: its bias and drift
    /// go, the lever arm's motion stays (see docs/fitting-and-tuning.md, "3-D fit").
    pub truth_accel_hz: f64,
    /// Fit the constant encoder offsets. Default true.
    pub encoder_offsets: bool,
    /// Fit c_z when its sensitivity (the RMS change of the encoders for a 1 cm pivot
    /// offset, the other parameters refitted) is at least this \[rad\]; else hold it.
    /// Default 1e-4 rad.
    pub min_offset_sensitivity: f64,
    /// The RMS change of the simulated encoders for a 100 % change of a_x, a_y,
    /// b_x + b_ring, b_y along the least sensitive direction below which the log is
    /// unidentifiable \[rad\]. Default 1e-4 rad (the planar output cost's).
    pub min_sensitivity: f64,
    /// The sensors' white-noise densities, whose effect on the simulated encoders the cost
    /// takes out ([`problem::noise_power`]). Default None: no correction (the CLI takes
    /// them from the log's initial rest, or from its options).
    pub noise: Option<NoiseDensities>,
    /// The optimiser's settings.
    pub lm: LmSettings,
}

/// White-noise densities of the IMU (MODEL.md 7.5's `d`: per-sample sigma d sqrt(fs)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseDensities {
    /// Accelerometer along body (x, y) \[m/s^2/sqrt(Hz)\].
    pub accel: [f64; 2],
    /// Gyro about body (x, y) \[rad/s/sqrt(Hz)\].
    pub gyro: [f64; 2],
}

impl Default for Fit3dSettings {
    fn default() -> Self {
        Self {
            target: Target::Truth,
            skip: 1.0,
            smoothing_hz: 20.0,
            truth_accel_hz: 0.02,
            encoder_offsets: true,
            min_offset_sensitivity: 1e-3,
            min_sensitivity: 1e-4,
            noise: None,
            lm: LmSettings::default(),
        }
    }
}

impl NoiseDensities {
    /// The densities measured over the log's initial rest (the replay's rest: MODEL.md
    /// 7.10, at least [`crate::replay::drive::MIN_REST_S`]): each axis's standard deviation
    /// over it divided by sqrt(fs). None when the log does not start at rest.
    pub fn from_initial_rest(log: &Log3dColumns) -> Option<Self> {
        let n = log.usable_rows();
        if n < 3 {
            return None;
        }
        let t = &log.t[..n];
        let rest = crate::replay::Rest::find(t, &log.gyro[..n], &log.accel[..n], None)?;
        let m = rest.end;
        let fs = (m - 1) as f64 / (t[m - 1] - t[0]);
        let density = |get: &dyn Fn(usize) -> f64| {
            let mean = (0..m).map(get).sum::<f64>() / m as f64;
            let var = (0..m).map(|k| (get(k) - mean).powi(2)).sum::<f64>() / (m - 1) as f64;
            (var / fs).sqrt()
        };
        let d = Self {
            accel: [density(&|k| log.accel[k][0]), density(&|k| log.accel[k][1])],
            gyro: [density(&|k| log.gyro[k][0]), density(&|k| log.gyro[k][1])],
        };
        (d.accel.iter().chain(&d.gyro).all(|v| v.is_finite())).then_some(d)
    }
}
