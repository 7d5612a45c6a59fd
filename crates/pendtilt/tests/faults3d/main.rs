//! Sensor faults and bad readings on 3-D logs (every 3-D estimator survives the
//! bad-input and fault tests the planar ones pass; docs/reliability.md section 8).
//!
//! One simulated `scooter3d` ride (seed 3, 30 s, 1 kHz) is written by `pendtilt simulate`;
//! each fault is injected into a copy of its CSV from t = 8 s (`gyro_range`: a gyro of a
//! smaller range, clipping the whole log, with the rig saying so), and `pendtilt estimate
//! --flags` runs every estimator of the 3-D registry on the clean and on the faulty log,
//! as a user would. For every fault and estimator the test checks: one output row per
//! input row; every output finite or flagged; the flag on the fault's first row for every
//! estimator reading the faulty sensor; and recovery: the time after the fault's end
//! from which the output stays within 0.05 deg (inclination, MODEL.md 7.9) of the
//! fault-free run to the end of the log, and the largest difference from 2 s after the end;
//! and against the simulator's truth (the log's `roll`, `pitch`): the inclination RMS error
//! from 2 s after the fault's end to the log's end is no worse than the fault-free run's
//! over the same rows by more than 10 % + 0.01 deg (no bad reading poisons a run, also for
//! a peer that cannot meet its own fault-free run within 0.05 deg). The faults include a
//! burst of 100 rows of an impossible gyro, accelerometer and encoder cell.
//!
//! The table of docs/reliability.md section 8 is printed by
//! `cargo test --release -p pendtilt --test faults3d -- --nocapture`.
mod clipping;
#[path = "../common/mod.rs"]
mod common;
mod faults;
mod restarts;
