//! # pendtilt-core
//!
//! Tilt estimation of a moving body from a pendulum read by an encoder, after Suresh and
//! Raju, "A Novel Method to Estimate Tilt Angle of a Body using a Pendulum" (the paper).
//! `#![no_std]`, no allocation, generic over `f32` and `f64`, no panic on finite input:
//! the same code runs per sample on a microcontroller and over logs on a PC.
//!
//! ## Layout
//! - [`params`]: the pendulum's physical and normalised parameters (a, b, c).
//! - [`filters`]: the signal processing the estimators stand on: smoothing
//!   differentiators (phi', phi''), a biquad low-pass, the paper's FIR low-pass.
//! - [`estimators`]: one module per estimator of the paper, all with the same streaming
//!   shape (settings with defaults, `new(settings)`, `update(sample) -> estimate`, flags):
//!   [`estimators::accel`] (Eq 1), [`estimators::pendulum`] (raw), [`estimators::alg1`]
//!   (Eq 20), [`estimators::alg2`] (Eqs 21-22), [`estimators::alg3`] (Eq 30).
//! - [`engine`]: one filter engine: process models, measurement models and the EKF and
//!   UKF generic over them, kept apart so that a new sensor is a new measurement model and
//!   a new state (a quaternion) a new process model; corrections go through the state's
//!   `retract`, so a rotation composes instead of adding.
//! - [`kalman`]: the paper's angle+bias filter (Eqs 2-11) as models on the engine;
//!   [`kalman::tilt`] assembles it over any measurement source.
//! - [`adaptation`]: the pendulum's forcing adapted online to the encoders' innovations,
//!   shared by the planar and the spatial filters.
//! - [`ekf`]: the pendulum dynamics and its sensors as models on the engine, and the
//!   model-based estimators `ekf` and `ukf` (the paper's future work).
//! - [`spatial`]: the spatial model (MODEL.md section 7): a two-axis pendulum on a Cardan
//!   joint with a 3-axis gyro and accelerometer; its own sample and attitude types on the
//!   same [`Estimator`] trait, and `pendulum3d`, `accel3d` and the quaternion
//!   `ekf3d`/`ukf3d` on the same filter engine.
//!
//! ## Getting started
//! `use pendtilt_core::prelude::*;` brings in what a firmware or application needs: the
//! [`Estimator`] trait, [`Sample`] in and [`Estimate`] out, [`Flags`], [`StepGate`]
//! (time stamps to steps), [`Real`], the rig's parameters, and every estimator with its
//! settings. The examples, from the simplest up (`cargo run -p pendtilt-core --release
//! --example NAME`):
//! 1. `minimal`: the raw pendulum against the accelerometer;
//! 2. `alg2_kalman`: Algorithm 2, and the angle+bias Kalman filter fed by it;
//! 3. `supervised_alg3`: Algorithm 3 with its gains re-fitted live against the gyro;
//! 4. `ekf`: the model-based extended Kalman filter;
//! 5. `examples/firmware` in the repository: an `f32`, `no_std` loop for a Cortex-M4F.
//!
//! ## Sign convention
//! The paper prints `theta = phi - asin(...)` in Eqs (20), (21) and (30). Solving its own
//! Eq (18) gives `theta = phi + asin(a phi' + b (phi'' - theta''))`; this crate implements
//! the plus sign (MODEL.md section 3).
#![no_std]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod adaptation;
pub mod ekf;
pub mod engine;
pub mod estimators;
pub mod filters;
mod flags;
pub mod kalman;
pub(crate) mod linalg;
pub mod model;
pub mod params;
pub mod prelude;
mod real;
mod sample;
mod sensor;
pub mod spatial;
pub mod step;
pub mod supervision;

pub use flags::{FlagNames, Flags};
pub use params::{PendulumParams, PhysicalParams};
pub use real::Real;
pub use sample::{Estimate, Estimator, Output, PlanarEstimator, Sample};
pub use step::{Micros, StepClock, StepGate};
