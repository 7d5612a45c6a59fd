//! `pendtilt estimate` on 3-D logs: simulate -> estimate end to end, the
//! columns and rows of MODEL.md 7.6, the inclination error (7.9) against the simulator's
//! truth computed here from the written CSV, and the errors on bad input.
mod bad_rows;
mod columns;
#[path = "../common/mod.rs"]
mod common;
mod end_to_end;
mod gyro_units;
mod kinds;
mod units;
