//! One filter engine: Gaussian filters generic over a process model and measurement
//! models, kept apart the way kfilter keeps system and measurement apart, so that a new
//! state (a quaternion attitude) or a new sensor is a new model, never a new filter.
//!
//! - [`state`]: [`ErrorState`], how a state is corrected: `x ⊞ dx` ([`ErrorState::retract`])
//!   and its inverse. Addition for vector states (implemented for every nalgebra
//!   `SVector`); composition for a rotation, whose error has fewer dimensions than its
//!   storage (a unit quaternion: 4 stored, 3 in the error).
//! - [`process`]: [`ProcessModel`]: the step `x -> f(x, u, dt)`, its Jacobian in error
//!   coordinates and the process noise `Q(dt)`.
//! - [`measurement`]: [`Measurement`]: the prediction `h(x)`, its Jacobian `H(x)`, the
//!   (diagonal) noise `R`, for scalar and small-vector readings.
//! - [`gate`]: the innovation gate ([`Gate`]) and why an update was not applied
//!   ([`Rejected`]).
//! - `update`: the scalar measurement update in symmetric rank-one form, shared by both
//!   filters.
//! - [`filter`]: the [`GaussianFilter`] interface; [`extended`] ([`ExtendedKalman`]) and
//!   [`unscented`] ([`UnscentedKalman`]) implement it.
//!
//! The filters never add a correction to the state: they call [`ErrorState::retract`].
//! The paper's angle + bias filter ([`crate::kalman`]) and the pendulum EKF/UKF
//! ([`crate::ekf`]) are models on this engine. Everything is `no_std`, allocation-free,
//! fixed-size (nalgebra `SMatrix`) and generic over `f32`/`f64`.
pub mod extended;
pub mod filter;
pub mod gate;
pub mod measurement;
pub mod process;
pub mod state;
pub mod unscented;
pub(crate) mod update;

pub use extended::ExtendedKalman;
pub use filter::GaussianFilter;
pub use gate::{Gate, Rejected};
pub use measurement::Measurement;
pub use process::ProcessModel;
pub use state::ErrorState;
pub use unscented::UnscentedKalman;

use crate::Real;
use nalgebra::{SMatrix, SVector};

/// Upper bound on the integration steps one sample interval is split into.
pub const MAX_SUBSTEPS: usize = 10_000;

/// How a sample interval `dt` is split for prediction: `n` equal steps of `h` no longer than
/// `max_step` (at least 1, at most [`MAX_SUBSTEPS`]; 1 for a `dt` that is not finite).
#[inline]
pub fn substeps<T: Real>(dt: T, max_step: T) -> (usize, T) {
    let ratio = (dt / max_step).ceil().to_f64();
    let n = if ratio.is_finite() && ratio >= 1.0 {
        (ratio as usize).min(MAX_SUBSTEPS)
    } else {
        1
    };
    (n, dt / T::lit(n as f64))
}

/// An error-state vector of dimension `N` (what the filter estimates the covariance of).
pub type Error<T, const N: usize> = SVector<T, N>;
/// An `N x N` covariance (or Jacobian) in error coordinates.
pub type Cov<T, const N: usize> = SMatrix<T, N, N>;

#[cfg(test)]
mod tests;
