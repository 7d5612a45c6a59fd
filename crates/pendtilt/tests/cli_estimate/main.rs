//! `pendtilt estimate` end to end: a small simulated log, the same log with other column
//! names and in degrees, a log missing the gyro, and bad input.
#[path = "../common/mod.rs"]
mod common;
mod end_to_end;
mod units;
