//! # pendtilt
//!
//! The std side of pendtilt: rig configuration, CSV logs, the simulator, parameter
//! fitting, reports, and the `pendtilt` command. The per-sample algorithms live in
//! [`pendtilt_core`], re-exported here as [`core`].
pub use pendtilt_core as core;

pub mod bank;
pub mod catalogue;
pub mod cli;
pub mod config;
pub mod experiment;
pub mod fit;
pub mod io;
pub mod peers;
pub mod pipeline;
pub mod replay;
pub mod report;
pub mod sensors;
pub mod sim;
pub mod tune;
pub mod units;
