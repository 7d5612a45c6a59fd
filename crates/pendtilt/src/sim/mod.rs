//! The simulators, planar and 3-D side by side: each an exact model of its pendulum rig
//! on a moving, vibrating body, with realistic sensors, built on the core's model types
//! alone ([`pendtilt_core::model`]).
//!
//! - [`planar`]: one pendulum axis on a tilting body (MODEL.md sections 1, 2, 5 and 6);
//! - [`spatial`]: the two-axis Cardan pendulum on a body in 6-DOF motion (MODEL.md 7).
//!
//! Both write logs in the contract's formats (MODEL.md 5 and 7.6), from named scenarios
//! ([`planar::SCENARIO_NAMES`], [`SCENARIO3D_NAMES`]) or scenario files; the same scenario
//! and seed give the same rows, bit for bit.
pub mod planar;
pub mod spatial;

/// The names the 3-D simulator's `Scenario3d::named` knows (its scenarios of MODEL.md
/// 7.8), here in the front beside the planar ones: each simulator's errors name both.
pub const SCENARIO3D_NAMES: &[&str] = &[
    "still3d",
    "scooter3d",
    "ship3d",
    "ride3d",
    "ride3d_yawbias",
    "ride3d_slip",
];
