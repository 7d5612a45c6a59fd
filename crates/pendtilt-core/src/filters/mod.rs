//! Signal processing the estimators stand on.
//!
//! - [`diff`]: smoothing differentiators giving a low-passed signal with its first and
//!   second derivatives (phi, phi', phi'' for Eqs 20, 21, 30).
//! - [`biquad`]: a second-order low-pass (for the accelerometer before atan2).
//! - [`fir`]: the paper's windowed-sinc FIR low-pass (50th order, 20 Hz).
//! - [`one_pole`]: the one-pole low-pass with its gain cached per step (the spatial
//!   estimators' gyro and speed smoothing).
pub mod biquad;
pub mod diff;
pub mod fir;
pub mod one_pole;
