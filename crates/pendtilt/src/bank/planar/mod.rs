//! The estimator bank: every estimator `pendtilt estimate` can run, built from the rig
//! settings and the columns a log has, run side by side one sample at a time.
//!
//! Each entry of [`REGISTRY`] names an output column and how to build it (the inputs it
//! needs and its description are its row of [`crate::catalogue`]); Kalman outputs name
//! the estimators whose angles they take as measurements. Adding an estimator is a
//! catalogue row and an entry here. An entry whose inputs the log lacks is skipped and
//! reported ([`Bank::skipped`]), never a failure.
//!
//! A configurable estimator is, beside its core module: a field of
//! [`RigConfig`](crate::config::RigConfig) whose type is its core settings (its `[table]`
//! is then read, written, checked for unknown keys and listed in errors), a comment for
//! each key in `config.rs`'s `key_comment`, and its entry in `registry.rs`, which builds
//! it from [`BankSettings::rig`]. A table whose keys are not its settings' fields one for
//! one adds a serde `with` module in `config/tables.rs`.
//!
//! Files: `settings.rs` the settings built
//! from a rig ([`BankSettings`]); `registry.rs` the table of estimators ([`REGISTRY`],
//! [`build_alone`]); `running.rs` the running bank ([`Bank`]).

mod by_name;
mod registry;
mod running;
mod settings;

pub use crate::sensors::Inputs;
pub use by_name::{build, build_physical};
pub use registry::{
    build_alone, BoxedEstimator, Entry, InversionSpec, KalmanSource, Kind, RSelector, REGISTRY,
};
pub use running::{any_flag, Bank, Restart, Skipped};
pub use settings::{check_settings_against_rate, BankSettings, RESTART_GAP};
