//! Windowed-sinc FIR low-pass: the paper's output filter.
//!
//! The paper smooths every estimate with a 50th-order (51-tap) FIR low-pass at 20 Hz.
//! This module gives
//!
//! - [`design_lowpass`]: the coefficients of a windowed-sinc low-pass, written into a slice
//!   the caller owns. They equal `scipy.signal.firwin(numtaps, cutoff, fs=rate,
//!   window=...)` (with scipy's default `scale=True`: unit gain at DC) to about 1e-16, so
//!   results can be checked against the usual Python tooling;
//! - [`Fir`]: the streaming filter, over buffers it owns ([`FirArray`]: the length is a
//!   compile-time constant, the microcontroller case: everything lives in the struct) or
//!   that the caller lends ([`FirSlice`]: a length chosen at run time, the `pendtilt
//!   filter` command, or a static buffer on a target); nothing is allocated either way;
//! - [`magnitude_response`]: the gain of any coefficient set at one frequency, to predict
//!   what a filter does to a sine without running it.
//!
//! ## Delay
//! A symmetric FIR of `N` taps (every design of this module) has linear phase: every
//! frequency is delayed by exactly `(N - 1) / 2` samples. The paper's filter at 1 kHz
//! delays by 25 ms; for a tilt estimate that is a real, constant lag, which is why the
//! group delay is exposed ([`Fir::group_delay`], [`FirArray::GROUP_DELAY`]) rather than
//! hidden.
//!
//! ## Start-up
//! A plain FIR starts from a zero history, so a constant input of 10 degrees would read as
//! a ramp from 0 over the first `N` samples. Here the history is filled with the first
//! input instead, so a constant input gives a constant output from the first sample (for
//! a unit-DC-gain design). Until `N` samples have been seen the output still depends on
//! that assumed past; [`Fir::is_filled`] says when it no longer does.
//!
//! ## Missing samples
//! The filter is linear: a `NaN` input makes the next `N` outputs `NaN` (it is in the
//! window for that long), then the output recovers by itself. Callers that want to bridge
//! gaps should substitute a value before calling `update`.
//!
//! ## The paper's filter at 1 kHz
//! `design_lowpass(20.0, 1000.0, Window::Hamming, &mut [0.0; 51])` has its -3 dB point at
//! 16.4 Hz (gain 0.59 at the nominal 20 Hz: the window widens the transition band to about
//! 65 Hz at this length), -40 dB at 50 Hz and below -69 dB everywhere above 80 Hz
//! (computed with `scipy.signal.freqz`).

mod design;
mod stream;

pub use design::{design_lowpass, magnitude_response, UnknownWindow, Window};
pub use stream::{Arrays, Fir, FirArray, FirBuffers, FirSlice, PaperFir, Slices};

/// The paper's FIR order: 50 (so [`PAPER_TAPS`] = 51 taps).
pub const PAPER_ORDER: usize = 50;
/// Number of taps of the paper's FIR: order + 1 = 51.
pub const PAPER_TAPS: usize = PAPER_ORDER + 1;
/// The paper's FIR cut-off frequency \[Hz\].
pub const PAPER_CUTOFF_HZ: f64 = 20.0;

/// Why a filter could not be designed or built. Returned instead of panicking, so that a
/// bad setting read from a file or a command line becomes a message, not a crash.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FirError {
    /// The coefficient slice (or history) is empty: a filter needs at least one tap.
    NoTaps,
    /// The sample rate is not finite and positive \[Hz\].
    InvalidRate {
        /// The rejected rate \[Hz\].
        rate_hz: f64,
    },
    /// The cut-off is not finite and positive \[Hz\] (a low-pass at 0 Hz passes nothing).
    CutoffNotPositive {
        /// The rejected cut-off \[Hz\].
        cutoff_hz: f64,
    },
    /// The cut-off is at or above the Nyquist frequency (half the rate): the design would
    /// not be a low-pass, and scipy's `firwin` rejects it for the same reason.
    CutoffAboveNyquist {
        /// The rejected cut-off \[Hz\].
        cutoff_hz: f64,
        /// Half the sample rate \[Hz\].
        nyquist_hz: f64,
    },
    /// [`FirSlice::new`] was given a history whose length differs from the number of taps.
    LengthMismatch {
        /// Number of coefficients.
        taps: usize,
        /// Length of the history buffer.
        history: usize,
    },
}

impl core::fmt::Display for FirError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            FirError::NoTaps => write!(f, "an FIR filter needs at least one tap"),
            FirError::InvalidRate { rate_hz } => {
                write!(f, "sample rate {rate_hz} Hz is not finite and positive")
            }
            FirError::CutoffNotPositive { cutoff_hz } => {
                write!(f, "cut-off {cutoff_hz} Hz is not finite and positive")
            }
            FirError::CutoffAboveNyquist {
                cutoff_hz,
                nyquist_hz,
            } => write!(
                f,
                "cut-off {cutoff_hz} Hz is not below the Nyquist frequency {nyquist_hz} Hz \
                 (half the sample rate)"
            ),
            FirError::LengthMismatch { taps, history } => write!(
                f,
                "FIR history has {history} samples but the filter has {taps} taps"
            ),
        }
    }
}

impl core::error::Error for FirError {}
