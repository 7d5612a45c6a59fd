//! Plausibility at the edge and unit checks.
//!
//! Item 2: an impossible reading (beyond the rig's full scale, or absurd) is missing for
//! every estimator, flagged `implausible` on the estimators that read it, reported once
//! with its line; a long sensor gap restarts the estimators that read the sensor. Each
//! case runs a simulated ride through the log reader and the bank (as `estimate` does),
//! clean and faulty, and measures per estimator when it is back within 0.05 deg of the
//! clean run. Item 3: time in ms or us, degrees read as radians (found from the physics,
//! with the factor), cutoffs above Nyquist or below the floor; each detector also runs on
//! correct logs that must not trigger it. Figures: docs/reliability.md section 7b.
#[path = "../common/mod.rs"]
mod common;
mod gaps;
mod impossible_cells;
mod units;
