//! The estimator banks, planar and 3-D side by side: every estimator `pendtilt estimate`
//! can run, built from the rig settings and the sensors a log has, run side by side one
//! sample at a time, each named by its row of [`crate::catalogue`].
//!
//! - [`planar`]: the planar bank ([`planar::Bank`], [`planar::REGISTRY`]);
//! - [`spatial`]: the 3-D bank ([`spatial::Bank3d`], [`spatial::REGISTRY3D`]), the 3-D rig
//!   file and the inclination score.
//!
//! Both apply the same gap rule ([`crate::sensors::GapWatch`]) and flag the estimators
//! reading a sensor that is clipped, implausible or missing.
pub mod planar;
pub mod spatial;
