//! Progress reporting for long runs, independent of how it is shown.
//!
//! The library reports stages and counts through [`Progress`]; the command line shows them
//! with `indicatif` ([`crate::cli::reproduce`]), tests pass [`NoProgress`].

/// Receives the progress of a long computation.
pub trait Progress {
    /// A new stage starts: `what` in words, `total` units of work (0 when unknown).
    fn stage(&self, what: &str, total: u64);
    /// `n` more units of the current stage are done.
    fn advance(&self, n: u64);
    /// A line of information for the user (fitted values, choices made).
    fn message(&self, text: &str);
}

/// Shows nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn stage(&self, _what: &str, _total: u64) {}
    fn advance(&self, _n: u64) {}
    fn message(&self, _text: &str) {}
}

/// Units between two [`Progress::advance`] calls in sample loops.
pub const CHUNK: u64 = 8192;
