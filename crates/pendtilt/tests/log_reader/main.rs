//! The sensor-log reader on good and bad files: each case gives an
//! error naming file, line and column, or a kept (flagged / NaN) sample with a warning;
//! never a panic, never a dropped row. The cases and outcomes are tabled in
//! docs/bad-input.md.
mod cells;
#[path = "../common/mod.rs"]
mod common;
mod files;
mod header;
mod time;
