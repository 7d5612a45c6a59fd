//! CSV input and output (MODEL.md section 5): the streaming sensor-log reader (on the one
//! CSV line reader, `csv_lines`, which `pendtilt filter` reads through too), the 3-D log
//! reader of MODEL.md 7.6 ([`Log3dReader`]) and the streaming estimates writer. The library never prints: warnings are queued for the
//! caller ([`LogReader::drain_warnings`]) and counted ([`LogReader::summary`]).
//!
//! ```no_run
//! use pendtilt::io::{LogReader, ReaderOptions};
//! let options = ReaderOptions {
//!     map: "phi=enc_angle".parse()?,
//!     degrees: "phi".parse()?,
//!     ..ReaderOptions::default()
//! };
//! let mut log = LogReader::open("log.csv", options)?;
//! eprintln!("{}", log.columns());
//! while let Some(record) = log.next_record()? {
//!     for w in log.drain_warnings() {
//!         eprintln!("warning: {w}");
//!     }
//!     let _ = (record.line, record.sample, record.theta);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
mod columns;
pub(crate) mod csv_lines;
mod diagnostics;
mod estimates3d_writer;
mod estimates_writer;
pub mod input;
mod log3d;
mod log_reader;
pub mod mat;
pub mod output;
pub mod plateau;
pub mod plausibility;
mod split;

pub use columns::{
    header_unit_warning, unit_in_name, unit_named_3d_hint, Column, ColumnMap, ColumnReport,
    ColumnStatus, DegreeColumns, NamedUnit, NegatedColumns, OptionError,
};
pub use diagnostics::{LogSummary, LogWarning, WarningKind};
pub use estimates3d_writer::{Column3d, Estimates3dWriter};
pub use estimates_writer::{EstimatesWriter, WriterOptions};
pub use log3d::{
    is_3d_header, read_log3d, Log3dReader, Log3dRecord, Row3dIssues, LOG3D_COLUMNS, LOG3D_REQUIRED,
};
pub use log_reader::{
    decimal_comma_hint, nul_message, CellRef, LogError, LogErrorKind, LogReader, LogRecord,
    ReaderOptions, RowIssues, ANGLE_LOOKS_LIKE_DEGREES, DECIMAL_COMMA_FIX, RATE_LOOKS_LIKE_DEGREES,
};
pub use plausibility::{AccelUnit, SensorLimits, TimeUnit, STANDARD_GRAVITY};
