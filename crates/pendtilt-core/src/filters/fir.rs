//! Windowed-sinc FIR low-pass: the paper's output filter.
//!
//! The paper smooths every estimate with a 50th-order (51-tap) FIR low-pass at 20 Hz.
//! This module gives
//!
//! - [`design_lowpass`]: the coefficients of a windowed-sinc low-pass, written into a slice
//!   the caller owns. They equal `scipy.signal.firwin(numtaps, cutoff, fs=rate,
//!   window=...)` (with scipy's default `scale=True`: unit gain at DC) to about 1e-16, so
//!   results can be checked against the usual Python tooling;
//! - [`Fir`]: a streaming filter whose length is a compile-time constant (the
//!   microcontroller case: everything lives in the struct, nothing is allocated);
//! - [`FirSlice`]: the same streaming filter over buffers the caller lends, for a length
//!   chosen at run time (the `pendtilt filter` command, or a static buffer on a target);
//! - [`magnitude_response`]: the gain of any coefficient set at one frequency, to predict
//!   what a filter does to a sine without running it.
//!
//! ## Delay
//! A symmetric FIR of `N` taps (every design of this module) has linear phase: every
//! frequency is delayed by exactly `(N - 1) / 2` samples. The paper's filter at 1 kHz
//! delays by 25 ms; for a tilt estimate that is a real, constant lag, which is why the
//! group delay is exposed ([`Fir::GROUP_DELAY`], [`FirSlice::group_delay`]) rather than
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

use crate::Real;
use nalgebra::ComplexField;

/// The paper's FIR order: 50 (so [`PAPER_TAPS`] = 51 taps).
pub const PAPER_ORDER: usize = 50;
/// Number of taps of the paper's FIR: order + 1 = 51.
pub const PAPER_TAPS: usize = PAPER_ORDER + 1;
/// The paper's FIR cut-off frequency \[Hz\].
pub const PAPER_CUTOFF_HZ: f64 = 20.0;

/// The paper's filter type: a 51-tap streaming FIR, built with [`Fir::paper`].
pub type PaperFir<T> = Fir<T, PAPER_TAPS>;

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

/// The window that tapers the ideal (infinite) sinc response to `N` taps.
///
/// The choice trades transition width against stop-band rejection (for the same length):
/// [`Window::Rectangular`] has the narrowest transition but only about -21 dB of
/// rejection and ripple in the pass band; [`Window::Hann`] about -44 dB; [`Window::Hamming`]
/// (scipy's and the usual default) about -53 dB; [`Window::Blackman`] about -74 dB with a
/// transition about 1.7 times wider than Hamming's. All are the symmetric forms of
/// `scipy.signal.get_window(..., fftbins=False)`, as `firwin` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Window {
    /// `0.54 - 0.46 cos(2 pi n / (N - 1))`: scipy's default and the usual choice for the
    /// paper's filter.
    #[default]
    Hamming,
    /// `0.5 - 0.5 cos(2 pi n / (N - 1))` (scipy's `"hann"`).
    Hann,
    /// `0.42 - 0.5 cos(2 pi n / (N - 1)) + 0.08 cos(4 pi n / (N - 1))`.
    Blackman,
    /// All ones: the truncated sinc (scipy's `"boxcar"`).
    Rectangular,
}

impl Window {
    /// Every window, in a fixed order (for help texts and tests).
    pub const ALL: [Window; 4] = [
        Window::Hamming,
        Window::Hann,
        Window::Blackman,
        Window::Rectangular,
    ];

    /// The window's lower-case name, as accepted by [`Window::from_str`](core::str::FromStr).
    pub fn name(self) -> &'static str {
        match self {
            Window::Hamming => "hamming",
            Window::Hann => "hann",
            Window::Blackman => "blackman",
            Window::Rectangular => "rectangular",
        }
    }

    /// The generalised-cosine coefficients `a_k` of `w = sum_k a_k cos(k x)`, `x` from
    /// -pi to pi: the form scipy evaluates, so the values match it to rounding.
    fn cosine_terms(self) -> &'static [f64] {
        match self {
            Window::Hamming => &[0.54, 0.46],
            Window::Hann => &[0.5, 0.5],
            Window::Blackman => &[0.42, 0.5, 0.08],
            Window::Rectangular => &[1.0],
        }
    }

    /// The window's value at tap `n` of `len` taps (symmetric form). Out-of-range `n`
    /// (`n >= len`) gives 0; a one-tap window is 1, as in scipy.
    pub fn value(self, n: usize, len: usize) -> f64 {
        if n >= len {
            return 0.0;
        }
        if len == 1 {
            return 1.0;
        }
        // numpy's linspace(-pi, pi, len), whose last point is exactly pi.
        let pi = core::f64::consts::PI;
        let x = if n == len - 1 {
            pi
        } else {
            -pi + n as f64 * ((2.0 * pi) / (len - 1) as f64)
        };
        let mut w = 0.0;
        for (k, a) in self.cosine_terms().iter().enumerate() {
            w += a * <f64 as ComplexField>::cos(k as f64 * x);
        }
        w
    }
}

impl core::fmt::Display for Window {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`Window`] from an unknown name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnknownWindow;

impl core::fmt::Display for UnknownWindow {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("unknown window (expected hamming, hann, blackman or rectangular)")
    }
}

impl core::error::Error for UnknownWindow {}

impl core::str::FromStr for Window {
    type Err = UnknownWindow;

    /// Accepts the names of [`Window::name`] and scipy's aliases (`hanning`, `boxcar`,
    /// `rect`, `rectangle`), ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        let is = |name: &str| s.eq_ignore_ascii_case(name);
        if is("hamming") {
            Ok(Window::Hamming)
        } else if is("hann") || is("hanning") {
            Ok(Window::Hann)
        } else if is("blackman") {
            Ok(Window::Blackman)
        } else if is("rectangular") || is("rectangle") || is("rect") || is("boxcar") {
            Ok(Window::Rectangular)
        } else {
            Err(UnknownWindow)
        }
    }
}

/// Checks rate and cut-off the way scipy's `firwin` does (0 < cutoff < rate / 2).
fn check_design(cutoff_hz: f64, rate_hz: f64, taps: usize) -> Result<(), FirError> {
    if taps == 0 {
        return Err(FirError::NoTaps);
    }
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(FirError::InvalidRate { rate_hz });
    }
    if cutoff_hz.is_nan() || cutoff_hz <= 0.0 {
        return Err(FirError::CutoffNotPositive { cutoff_hz });
    }
    let nyquist_hz = 0.5 * rate_hz;
    if cutoff_hz.is_infinite() || cutoff_hz / nyquist_hz >= 1.0 {
        return Err(FirError::CutoffAboveNyquist {
            cutoff_hz,
            nyquist_hz,
        });
    }
    Ok(())
}

/// Tap `n` of `len` before normalisation: windowed ideal low-pass `c sinc(c m)`, with `c` the
/// cut-off as a fraction of Nyquist and `m` the distance from the centre tap.
fn raw_tap(c: f64, window: Window, n: usize, len: usize) -> f64 {
    let m = n as f64 - 0.5 * (len - 1) as f64;
    // numpy's sinc(x) = sin(pi x) / (pi x), with x = 0 mapped to 1.
    let x = c * m;
    let sinc = if x == 0.0 {
        1.0
    } else {
        let y = core::f64::consts::PI * x;
        <f64 as ComplexField>::sin(y) / y
    };
    c * sinc * window.value(n, len)
}

/// Designs a windowed-sinc low-pass into `out`, one coefficient per tap (`out.len()` taps,
/// order `out.len() - 1`).
///
/// The result equals `scipy.signal.firwin(out.len(), cutoff_hz, fs=rate_hz,
/// window=window)` with its default `scale=True`: the taps are normalised to sum to 1, so
/// a constant passes unchanged. The computation runs in `f64` whatever `T` is and is
/// rounded once at the end, so an `f32` design is the correctly rounded `f64` one (the
/// design runs once, at start-up, so its cost does not matter even on a target without a
/// double-precision FPU).
///
/// Any length works; an odd length (even order, as the paper's 50) puts a tap at the
/// centre and delays by a whole number of samples.
///
/// # Errors
/// [`FirError::NoTaps`] for an empty slice, [`FirError::InvalidRate`],
/// [`FirError::CutoffNotPositive`] and [`FirError::CutoffAboveNyquist`] for settings
/// outside `0 < cutoff_hz < rate_hz / 2`. On error `out` is left untouched.
///
/// ```
/// use pendtilt_core::filters::fir::{design_lowpass, Window};
/// let mut taps = [0.0f64; 51];
/// design_lowpass(20.0, 1000.0, Window::Hamming, &mut taps).unwrap();
/// assert!((taps.iter().sum::<f64>() - 1.0).abs() < 1e-12);
/// ```
pub fn design_lowpass<T: Real>(
    cutoff_hz: f64,
    rate_hz: f64,
    window: Window,
    out: &mut [T],
) -> Result<(), FirError> {
    let len = out.len();
    check_design(cutoff_hz, rate_hz, len)?;
    let c = cutoff_hz / (0.5 * rate_hz);
    // Two passes instead of a scratch buffer (no allocation, and `out` may be f32): the
    // first finds the DC gain, the second writes the normalised taps.
    let mut dc = 0.0;
    for n in 0..len {
        dc += raw_tap(c, window, n, len);
    }
    // dc > 0 always: the centre taps dominate for any 0 < c < 1. Guard anyway so that a
    // pathological rounding can never produce inf or NaN.
    if !(dc.is_finite() && dc > 0.0) {
        return Err(FirError::CutoffNotPositive { cutoff_hz });
    }
    for (n, o) in out.iter_mut().enumerate() {
        *o = T::lit(raw_tap(c, window, n, len) / dc);
    }
    Ok(())
}

/// Gain `|H(f)|` of the FIR with coefficients `taps` at frequency `freq_hz`, for a signal
/// sampled at `rate_hz` (the value `scipy.signal.freqz(taps, worN=[freq_hz], fs=rate_hz)`
/// returns in magnitude). Computed in `f64`.
///
/// Use it to predict what the filter does to a sine of that frequency: its amplitude is
/// multiplied by this gain (and, for a symmetric design, it is delayed by `(N - 1) / 2`
/// samples). An empty slice gives 0; a non-finite or non-positive rate gives `NaN`.
pub fn magnitude_response<T: Real>(taps: &[T], freq_hz: f64, rate_hz: f64) -> f64 {
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return f64::NAN;
    }
    let w = 2.0 * core::f64::consts::PI * freq_hz / rate_hz;
    let (mut re, mut im) = (0.0f64, 0.0f64);
    for (k, h) in taps.iter().enumerate() {
        let h = h.to_f64();
        re += h * <f64 as ComplexField>::cos(w * k as f64);
        im -= h * <f64 as ComplexField>::sin(w * k as f64);
    }
    <f64 as ComplexField>::sqrt(re * re + im * im)
}

/// `sum a[i] b[i]` over the common length, with four partial sums: a single running sum is
/// one long chain of multiply-adds, each waiting for the previous result; four independent
/// chains let the CPU overlap them. The summation order differs from the textbook one only
/// by rounding (about 1e-16 relative for these taps).
#[inline(always)]
fn dot<T: Real>(a: &[T], b: &[T]) -> T {
    let mut acc = [T::zero(); 4];
    let mut ca = a.chunks_exact(4);
    let mut cb = b.chunks_exact(4);
    for (x, y) in (&mut ca).zip(&mut cb) {
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ca.remainder().iter().zip(cb.remainder()) {
        s += *x * *y;
    }
    s
}

/// One step of the streaming FIR shared by [`Fir`] and [`FirSlice`].
///
/// `hist` is a ring buffer written backwards: the newest sample is at `pos`, the one before
/// at `pos + 1` (wrapping). So newest-to-oldest is `hist[pos..]` then `hist[..pos]`, which
/// lines up with `taps[0..]` in two contiguous dot products: no modulo in the inner loop
/// and no reversed copy of the taps. Requires `taps.len() == hist.len() > 0` and
/// `pos < hist.len()`; both owners guarantee it.
#[inline(always)]
fn step<T: Real>(taps: &[T], hist: &mut [T], pos: &mut usize, count: &mut usize, x: T) -> T {
    let n = hist.len();
    if n == 0 || taps.len() != n {
        return T::zero();
    }
    if *count == 0 {
        // First sample since new/reset: pretend the signal has always been x.
        hist.fill(x);
    }
    *pos = if *pos == 0 || *pos >= n {
        n - 1
    } else {
        *pos - 1
    };
    let (older, newer) = hist.split_at_mut(*pos);
    if let Some(slot) = newer.first_mut() {
        *slot = x;
    }
    if *count < n {
        *count += 1;
    }
    let (t_new, t_old) = taps.split_at(n - *pos);
    dot(newer, t_new) + dot(older, t_old)
}

/// A streaming FIR filter of `N` taps: coefficients and history inside the struct, no
/// allocation, one multiply-add per tap per sample.
///
/// Output at step `k`: `y[k] = sum_i taps[i] x[k - i]`. Before the first sample the history
/// is taken to be the first input (see the [module docs](self)); [`Fir::is_filled`] turns
/// true once `N` real samples are in the window.
///
/// `N = 0` is rejected at compile time:
///
/// ```compile_fail
/// let _ = pendtilt_core::filters::fir::Fir::<f64, 0>::new([]);
/// ```
///
/// ```
/// use pendtilt_core::filters::fir::PaperFir;
/// let mut fir = PaperFir::<f32>::paper(1000.0).unwrap();
/// let y = fir.update(0.1); // a constant input...
/// assert!((y - 0.1).abs() < 1e-6); // ...gives the same constant from the first sample
/// ```
#[derive(Debug, Clone)]
pub struct Fir<T, const N: usize> {
    taps: [T; N],
    hist: [T; N],
    pos: usize,
    count: usize,
}

impl<T: Real, const N: usize> Fir<T, N> {
    /// Group delay of a symmetric (linear-phase) `N`-tap filter, in samples: `(N - 1) / 2`.
    /// Every design of [`design_lowpass`] is symmetric; for other coefficients given to
    /// [`Fir::new`] this is only the delay if they are symmetric too.
    pub const GROUP_DELAY: f64 = (N as f64 - 1.0) / 2.0;

    /// A filter with the given coefficients (`taps[0]` weighs the newest sample). Use it
    /// for coefficients designed elsewhere; [`Fir::lowpass`] designs them here.
    pub fn new(taps: [T; N]) -> Self {
        const { assert!(N > 0, "an FIR filter needs at least one tap") };
        Self {
            taps,
            hist: [T::zero(); N],
            pos: 0,
            count: 0,
        }
    }

    /// A windowed-sinc low-pass of `N` taps ([`design_lowpass`]).
    ///
    /// # Errors
    /// As [`design_lowpass`]: the cut-off must satisfy `0 < cutoff_hz < rate_hz / 2`.
    pub fn lowpass(cutoff_hz: f64, rate_hz: f64, window: Window) -> Result<Self, FirError> {
        let mut taps = [T::zero(); N];
        design_lowpass(cutoff_hz, rate_hz, window, &mut taps)?;
        Ok(Self::new(taps))
    }

    /// Filters one sample and returns the output for the same instant (delayed by
    /// [`Fir::GROUP_DELAY`] samples, as every causal linear-phase filter is).
    #[inline]
    pub fn update(&mut self, x: T) -> T {
        step(
            &self.taps,
            &mut self.hist,
            &mut self.pos,
            &mut self.count,
            x,
        )
    }

    /// Forgets the history: the next sample is treated as the first (and pre-fills it).
    pub fn reset(&mut self) {
        self.hist = [T::zero(); N];
        self.pos = 0;
        self.count = 0;
    }

    /// `true` once `N` samples have been filtered since construction or [`Fir::reset`]:
    /// from then on the output depends only on real inputs, not on the pre-filled history.
    pub fn is_filled(&self) -> bool {
        self.count >= N
    }

    /// Group delay in samples, `(N - 1) / 2` (see [`Fir::GROUP_DELAY`]). Divide by the
    /// sample rate for seconds: 25 ms for the paper's filter at 1 kHz.
    pub fn group_delay(&self) -> f64 {
        Self::GROUP_DELAY
    }

    /// The coefficients, `taps[0]` weighing the newest sample.
    pub fn taps(&self) -> &[T; N] {
        &self.taps
    }
}

impl<T: Real> Fir<T, PAPER_TAPS> {
    /// The paper's filter: 50th order (51 taps), 20 Hz cut-off, Hamming window, for data
    /// sampled at `rate_hz`.
    ///
    /// # Errors
    /// [`FirError::InvalidRate`] for a non-finite or non-positive rate, and
    /// [`FirError::CutoffAboveNyquist`] below 40 Hz, where 20 Hz is not a low-pass.
    pub fn paper(rate_hz: f64) -> Result<Self, FirError> {
        Self::lowpass(PAPER_CUTOFF_HZ, rate_hz, Window::Hamming)
    }
}

/// A streaming FIR filter over buffers lent by the caller: the length is chosen at run time
/// (a command-line `--order`) while the filter itself still never allocates.
///
/// Behaves exactly like [`Fir`] (same pre-fill, same arithmetic, so the same outputs bit for
/// bit for the same taps).
///
/// ```
/// use pendtilt_core::filters::fir::{design_lowpass, FirSlice, Window};
/// let mut taps = [0.0f64; 31];
/// design_lowpass(20.0, 500.0, Window::Hann, &mut taps).unwrap();
/// let mut history = [0.0f64; 31];
/// let mut fir = FirSlice::new(&taps, &mut history).unwrap();
/// assert!((fir.update(2.0) - 2.0).abs() < 1e-12);
/// ```
#[derive(Debug)]
pub struct FirSlice<'a, T> {
    taps: &'a [T],
    hist: &'a mut [T],
    pos: usize,
    count: usize,
}

impl<'a, T: Real> FirSlice<'a, T> {
    /// A filter with coefficients `taps` (`taps[0]` weighs the newest sample) keeping its
    /// past inputs in `history`, which must have the same length. The history's content is
    /// irrelevant: it is overwritten by the first sample.
    ///
    /// # Errors
    /// [`FirError::NoTaps`] for empty taps, [`FirError::LengthMismatch`] if the lengths
    /// differ.
    pub fn new(taps: &'a [T], history: &'a mut [T]) -> Result<Self, FirError> {
        if taps.is_empty() {
            return Err(FirError::NoTaps);
        }
        if history.len() != taps.len() {
            return Err(FirError::LengthMismatch {
                taps: taps.len(),
                history: history.len(),
            });
        }
        Ok(Self {
            taps,
            hist: history,
            pos: 0,
            count: 0,
        })
    }

    /// Filters one sample (see [`Fir::update`]).
    #[inline]
    pub fn update(&mut self, x: T) -> T {
        step(self.taps, self.hist, &mut self.pos, &mut self.count, x)
    }

    /// Forgets the history: the next sample is treated as the first.
    pub fn reset(&mut self) {
        self.pos = 0;
        self.count = 0;
    }

    /// `true` once as many samples as there are taps have been filtered since construction
    /// or [`FirSlice::reset`] (see [`Fir::is_filled`]).
    pub fn is_filled(&self) -> bool {
        self.count >= self.taps.len()
    }

    /// Number of taps (order + 1).
    pub fn len(&self) -> usize {
        self.taps.len()
    }

    /// Always `false`: [`FirSlice::new`] refuses empty taps. Present because a `len`
    /// without it reads as an oversight.
    pub fn is_empty(&self) -> bool {
        self.taps.is_empty()
    }

    /// Group delay in samples, `(len - 1) / 2`, for symmetric taps (every
    /// [`design_lowpass`] design).
    pub fn group_delay(&self) -> f64 {
        (self.taps.len() as f64 - 1.0) / 2.0
    }

    /// The coefficients, `taps[0]` weighing the newest sample.
    pub fn taps(&self) -> &[T] {
        self.taps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `scipy.signal.firwin(51, 20.0, fs=1000.0)` (scipy 1.17.1: default window "hamming",
    /// scale=True): the paper's filter at 1 kHz.
    const SCIPY_HAMMING_51_20HZ_1KHZ: [f64; 51] = [
        1.4774945964864944e-19,
        0.0001646523085414019,
        0.0003850395583006714,
        0.0007084803722596073,
        0.0011840522208800808,
        0.0018598621388835348,
        0.002780215123996375,
        0.003982826337513613,
        0.005496225214400497,
        0.007337493763950544,
        0.009510467868063326,
        0.01200450984533788,
        0.01479393391635053,
        0.017838134790252373,
        0.021082434980186665,
        0.02445963042069151,
        0.02789217837669805,
        0.031294938370208226,
        0.03457834767261706,
        0.037651889383699816,
        0.04042769452309299,
        0.04282411082142091,
        0.04476907053321852,
        0.046203097682085505,
        0.0470818113256786,
        0.04737780490334341,
        0.047081811325678596,
        0.0462030976820855,
        0.04476907053321852,
        0.04282411082142091,
        0.04042769452309299,
        0.03765188938369981,
        0.034578347672617055,
        0.03129493837020821,
        0.02789217837669804,
        0.024459630420691506,
        0.02108243498018666,
        0.017838134790252362,
        0.014793933916350525,
        0.012004509845337871,
        0.009510467868063326,
        0.007337493763950544,
        0.0054962252144004934,
        0.003982826337513608,
        0.002780215123996371,
        0.0018598621388835322,
        0.0011840522208800808,
        0.0007084803722596071,
        0.00038503955830067115,
        0.0001646523085414018,
        1.4774945964864944e-19,
    ];

    /// `scipy.signal.firwin(16, 100.0, fs=500.0, window="hann")` (scipy 1.17.1): an even
    /// length, so a half-sample group delay, and a different window.
    const SCIPY_HANN_16_100HZ_500HZ: [f64; 16] = [
        0.0,
        0.002020684536236436,
        0.005648463466704576,
        -0.014417543505539978,
        -0.04794385221097309,
        1.1737614313420131e-17,
        0.18322108307408375,
        0.3714711646394883,
        0.3714711646394883,
        0.18322108307408375,
        1.1737614313420136e-17,
        -0.047943852210973116,
        -0.014417543505539978,
        0.0056484634667045815,
        0.0020206845362364385,
        0.0,
    ];

    /// `scipy.signal.firwin(21, 60.0, fs=200.0, window="blackman")` (scipy 1.17.1).
    const SCIPY_BLACKMAN_21_60HZ_200HZ: [f64; 21] = [
        3.2454584958964907e-34,
        -0.0003091858295249753,
        0.0009403453912548369,
        0.0027095203073162133,
        -0.010128564981150914,
        7.951237645984621e-18,
        0.038577041881404255,
        -0.042975239679067946,
        -0.07943422427380759,
        0.2906592731248099,
        0.5999220681175325,
        0.2906592731248099,
        -0.07943422427380759,
        -0.042975239679067946,
        0.038577041881404255,
        7.951237645984621e-18,
        -0.010128564981150914,
        0.0027095203073162133,
        0.0009403453912548369,
        -0.0003091858295249753,
        3.2454584958964907e-34,
    ];

    /// `scipy.signal.firwin(9, 10.0, fs=100.0, window="boxcar")` (scipy 1.17.1).
    const SCIPY_BOXCAR_9_10HZ_100HZ: [f64; 9] = [
        0.039899882278863805,
        0.08607915423242829,
        0.1291187313486425,
        0.1595995291154552,
        0.17060540604922045,
        0.1595995291154552,
        0.1291187313486425,
        0.08607915423242829,
        0.039899882278863805,
    ];

    /// `abs(scipy.signal.freqz(firwin(51, 20.0, fs=1000.0), worN=[f], fs=1000.0)[1][0])`
    /// for f = 1, 2, 5, 20, 100, 150 Hz (scipy 1.17.1).
    const SCIPY_GAIN_HAMMING_51: [(f64, f64); 6] = [
        (1.0, 0.9987425318854064),
        (2.0, 0.9949784498394143),
        (5.0, 0.9689765744811609),
        (20.0, 0.5945650033554324),
        (100.0, 0.00020501267793793362),
        (150.0, 1.0004196540636921e-05),
    ];

    /// `abs(freqz(firwin(16, 100.0, fs=500.0, window="hann"), worN=[f], fs=500.0))` for
    /// f = 20 and 200 Hz (scipy 1.17.1).
    const SCIPY_GAIN_HANN_16: [(f64, f64); 2] =
        [(20.0, 1.006257883944632), (200.0, 0.002009522372992189)];

    fn sin(x: f64) -> f64 {
        <f64 as ComplexField>::sin(x)
    }

    fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
        assert_eq!(a.len(), b.len());
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    /// Deterministic pseudo-random numbers in [-1, 1) (no rand in a no_std crate's tests).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    #[test]
    fn hamming_51_matches_scipy_firwin() {
        let mut taps = [0.0f64; 51];
        design_lowpass(20.0, 1000.0, Window::Hamming, &mut taps).unwrap();
        let err = max_abs_diff(&taps, &SCIPY_HAMMING_51_20HZ_1KHZ);
        assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
        // The paper's constructor designs the same thing.
        let paper = PaperFir::<f64>::paper(1000.0).unwrap();
        assert_eq!(paper.taps(), &taps);
    }

    #[test]
    fn hann_16_matches_scipy_firwin() {
        let mut taps = [0.0f64; 16];
        design_lowpass(100.0, 500.0, Window::Hann, &mut taps).unwrap();
        let err = max_abs_diff(&taps, &SCIPY_HANN_16_100HZ_500HZ);
        assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
    }

    #[test]
    fn blackman_21_matches_scipy_firwin() {
        let mut taps = [0.0f64; 21];
        design_lowpass(60.0, 200.0, Window::Blackman, &mut taps).unwrap();
        let err = max_abs_diff(&taps, &SCIPY_BLACKMAN_21_60HZ_200HZ);
        assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
    }

    #[test]
    fn rectangular_9_matches_scipy_firwin() {
        let mut taps = [0.0f64; 9];
        design_lowpass(10.0, 100.0, Window::Rectangular, &mut taps).unwrap();
        let err = max_abs_diff(&taps, &SCIPY_BOXCAR_9_10HZ_100HZ);
        assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
    }

    #[test]
    fn one_tap_design_is_identity() {
        let mut taps = [0.0f64; 1];
        design_lowpass(20.0, 1000.0, Window::Hamming, &mut taps).unwrap();
        assert_eq!(taps, [1.0]);
    }

    #[test]
    fn dc_gain_is_one_and_constant_in_gives_constant_out() {
        for window in Window::ALL {
            let mut fir = Fir::<f64, 33>::lowpass(45.0, 400.0, window).unwrap();
            let sum: f64 = fir.taps().iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "{window}: DC gain {sum}");
            assert!((magnitude_response(fir.taps(), 0.0, 400.0) - 1.0).abs() < 1e-12);
            for k in 0..100 {
                let y = fir.update(0.25);
                assert!((y - 0.25).abs() < 1e-12, "{window}: sample {k} gave {y}");
            }
        }
    }

    #[test]
    fn designs_are_symmetric() {
        let mut taps = [0.0f64; 40];
        for window in Window::ALL {
            design_lowpass(7.0, 90.0, window, &mut taps).unwrap();
            for i in 0..taps.len() {
                let j = taps.len() - 1 - i;
                assert!(
                    (taps[i] - taps[j]).abs() < 1e-15,
                    "{window}: tap {i} vs {j}"
                );
            }
        }
    }

    #[test]
    fn magnitude_response_matches_scipy_freqz() {
        for (f, g) in SCIPY_GAIN_HAMMING_51 {
            let ours = magnitude_response(&SCIPY_HAMMING_51_20HZ_1KHZ, f, 1000.0);
            assert!((ours - g).abs() < 1e-12, "{f} Hz: {ours} vs scipy {g}");
        }
        for (f, g) in SCIPY_GAIN_HANN_16 {
            let ours = magnitude_response(&SCIPY_HANN_16_100HZ_500HZ, f, 500.0);
            assert!((ours - g).abs() < 1e-12, "{f} Hz: {ours} vs scipy {g}");
        }
        assert!(magnitude_response(&[1.0f64], 1.0, 0.0).is_nan());
    }

    /// Runs `fir` over a sine of `freq` Hz at `rate` Hz and returns the largest deviation,
    /// once the window holds only real samples, from `gain * sin(w (k - delay))`.
    fn sine_error<const N: usize>(fir: &mut Fir<f64, N>, freq: f64, rate: f64, gain: f64) -> f64 {
        let w = 2.0 * core::f64::consts::PI * freq / rate;
        let delay = fir.group_delay();
        let mut worst = 0.0f64;
        for k in 0..2000 {
            let y = fir.update(sin(w * k as f64));
            if fir.is_filled() {
                let expected = gain * sin(w * (k as f64 - delay));
                worst = worst.max((y - expected).abs());
            }
        }
        worst
    }

    #[test]
    fn passband_sine_keeps_its_amplitude_and_is_delayed_by_half_the_order() {
        // 2 Hz through the paper's filter at 1 kHz: scipy's gain 0.99498, 25 samples late.
        let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
        assert_eq!(fir.group_delay(), 25.0);
        let (f, g) = SCIPY_GAIN_HAMMING_51[1];
        assert!(g > 0.99);
        let err = sine_error(&mut fir, f, 1000.0, g);
        assert!(err < 1e-12, "deviation from 0.995 sin(w (k - 25)): {err:e}");
        // The same delay is wrong by one sample: the test can tell.
        let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
        let w = 2.0 * core::f64::consts::PI * f / 1000.0;
        let mut off = 0.0f64;
        for k in 0..2000 {
            let y = fir.update(sin(w * k as f64));
            if fir.is_filled() {
                off = off.max((y - g * sin(w * (k as f64 - 24.0))).abs());
            }
        }
        assert!(off > 1e-3);
    }

    #[test]
    fn even_length_delays_by_a_half_sample() {
        let mut taps = [0.0f64; 16];
        design_lowpass(100.0, 500.0, Window::Hann, &mut taps).unwrap();
        let mut fir = Fir::new(taps);
        assert_eq!(Fir::<f64, 16>::GROUP_DELAY, 7.5);
        let (f, g) = SCIPY_GAIN_HANN_16[0];
        let err = sine_error(&mut fir, f, 500.0, g);
        assert!(err < 1e-12, "deviation from g sin(w (k - 7.5)): {err:e}");
    }

    #[test]
    fn stopband_sine_is_attenuated_as_predicted() {
        for (f, g) in [SCIPY_GAIN_HAMMING_51[4], SCIPY_GAIN_HAMMING_51[5]] {
            assert!(g < 3e-4, "{f} Hz should be at least 70 dB down");
            let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
            let w = 2.0 * core::f64::consts::PI * f / 1000.0;
            // Amplitude from the RMS over 3000 filled samples: a whole number of periods of
            // both 100 Hz (10 samples) and 150 Hz (20 samples for 3 periods), where the
            // RMS of a sampled sine is exactly amplitude / sqrt(2).
            let (mut sum_sq, mut n) = (0.0f64, 0usize);
            for k in 0..(PAPER_TAPS + 3000) {
                let y = fir.update(sin(w * k as f64));
                if k >= PAPER_TAPS {
                    sum_sq += y * y;
                    n += 1;
                }
            }
            assert_eq!(n, 3000);
            let amplitude = <f64 as ComplexField>::sqrt(2.0 * sum_sq / n as f64);
            assert!(
                (amplitude - g).abs() < 1e-6 * g,
                "{f} Hz: amplitude {amplitude} vs {g}"
            );
            let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
            assert!(sine_error(&mut fir, f, 1000.0, g) < 1e-13);
        }
    }

    /// Direct convolution with the pre-fill convention: x[k] = x[0] for k < 0.
    fn direct(taps: &[f64], x: &[f64], k: usize) -> f64 {
        taps.iter()
            .enumerate()
            .map(|(i, h)| h * if i <= k { x[k - i] } else { x[0] })
            .sum()
    }

    fn check_streaming_equals_direct<const N: usize>(seed: u64) {
        let mut rng = Lcg(seed);
        let mut taps = [0.0f64; N];
        // Arbitrary, asymmetric taps: the tap order must be right, not just the symmetry.
        for t in taps.iter_mut() {
            *t = rng.next();
        }
        let mut x = [0.0f64; 300];
        for v in x.iter_mut() {
            *v = rng.next() * 5.0;
        }
        let mut fir = Fir::new(taps);
        let mut hist = [9.0f64; N];
        let mut slice = FirSlice::new(&taps, &mut hist).unwrap();
        for k in 0..x.len() {
            let want = direct(&taps, &x, k);
            let y = fir.update(x[k]);
            let ys = slice.update(x[k]);
            assert!((y - want).abs() < 1e-12, "N={N} k={k}: {y} vs {want}");
            assert_eq!(y.to_bits(), ys.to_bits(), "Fir and FirSlice differ");
            assert_eq!(fir.is_filled(), k + 1 >= N);
            assert_eq!(slice.is_filled(), k + 1 >= N);
        }
    }

    #[test]
    fn streaming_equals_direct_convolution() {
        check_streaming_equals_direct::<1>(1);
        check_streaming_equals_direct::<2>(2);
        check_streaming_equals_direct::<3>(3);
        check_streaming_equals_direct::<4>(4);
        check_streaming_equals_direct::<7>(5);
        check_streaming_equals_direct::<51>(6);
        check_streaming_equals_direct::<64>(7);
    }

    #[test]
    fn f32_and_f64_agree() {
        let mut t64 = [0.0f64; 51];
        let mut t32 = [0.0f32; 51];
        design_lowpass(20.0, 1000.0, Window::Hamming, &mut t64).unwrap();
        design_lowpass(20.0, 1000.0, Window::Hamming, &mut t32).unwrap();
        for (a, b) in t64.iter().zip(&t32) {
            // The f32 design is the f64 one, correctly rounded.
            assert_eq!(*b, *a as f32);
        }
        let mut f64_fir = Fir::new(t64);
        let mut f32_fir = Fir::new(t32);
        let mut rng = Lcg(42);
        let mut worst = 0.0f64;
        for k in 0..5000 {
            // A tilt-like signal in radians: slow swing plus vibration and noise.
            let t = k as f64 / 1000.0;
            let x = 0.2 * sin(2.0 * t)
                + 0.05 * sin(2.0 * core::f64::consts::PI * 80.0 * t)
                + 0.01 * rng.next();
            let y64 = f64_fir.update(x);
            let y32 = f32_fir.update(x as f32);
            worst = worst.max((y64 - y32 as f64).abs());
        }
        assert!(worst < 1e-6, "f32 vs f64: {worst:e}");
    }

    #[test]
    fn reset_restarts_like_new() {
        let mut fir = PaperFir::<f64>::paper(500.0).unwrap();
        for k in 0..100 {
            fir.update(k as f64);
        }
        assert!(fir.is_filled());
        fir.reset();
        assert!(!fir.is_filled());
        let mut fresh = PaperFir::<f64>::paper(500.0).unwrap();
        for k in 0..60 {
            let x = sin(k as f64 * 0.3);
            assert_eq!(fir.update(x).to_bits(), fresh.update(x).to_bits());
        }
        let taps = *fresh.taps();
        let mut hist = [0.0; PAPER_TAPS];
        let mut slice = FirSlice::new(&taps, &mut hist).unwrap();
        for k in 0..80 {
            slice.update(k as f64);
        }
        slice.reset();
        assert!(!slice.is_filled());
        assert_eq!(slice.update(3.0), fresh_constant(&taps, 3.0));
    }

    fn fresh_constant(taps: &[f64; PAPER_TAPS], x: f64) -> f64 {
        let mut fir = Fir::new(*taps);
        fir.update(x)
    }

    #[test]
    fn nan_input_spoils_one_window_then_recovers() {
        let mut fir = Fir::<f64, 11>::lowpass(10.0, 100.0, Window::Hamming).unwrap();
        for _ in 0..20 {
            fir.update(1.0);
        }
        assert!(fir.update(f64::NAN).is_nan());
        for _ in 0..10 {
            assert!(fir.update(1.0).is_nan());
        }
        let y = fir.update(1.0);
        assert!((y - 1.0).abs() < 1e-12, "after the window: {y}");
    }

    #[test]
    fn bad_settings_are_errors_not_panics() {
        let mut taps = [7.0f64; 5];
        let cases = [
            (20.0, 1000.0, FirError::NoTaps),
            (0.0, 1000.0, FirError::CutoffNotPositive { cutoff_hz: 0.0 }),
            (
                -1.0,
                1000.0,
                FirError::CutoffNotPositive { cutoff_hz: -1.0 },
            ),
            (
                500.0,
                1000.0,
                FirError::CutoffAboveNyquist {
                    cutoff_hz: 500.0,
                    nyquist_hz: 500.0,
                },
            ),
            (
                f64::INFINITY,
                1000.0,
                FirError::CutoffAboveNyquist {
                    cutoff_hz: f64::INFINITY,
                    nyquist_hz: 500.0,
                },
            ),
            (20.0, 0.0, FirError::InvalidRate { rate_hz: 0.0 }),
            (20.0, -5.0, FirError::InvalidRate { rate_hz: -5.0 }),
            (
                20.0,
                f64::INFINITY,
                FirError::InvalidRate {
                    rate_hz: f64::INFINITY,
                },
            ),
        ];
        for (i, (cutoff, rate, want)) in cases.into_iter().enumerate() {
            let out: &mut [f64] = if i == 0 { &mut [] } else { &mut taps };
            assert_eq!(
                design_lowpass(cutoff, rate, Window::Hamming, out),
                Err(want)
            );
        }
        // NaN settings are rejected too (compared by variant: NaN != NaN).
        assert!(matches!(
            design_lowpass(f64::NAN, 1000.0, Window::Hann, &mut taps),
            Err(FirError::CutoffNotPositive { .. })
        ));
        assert!(matches!(
            design_lowpass(20.0, f64::NAN, Window::Hann, &mut taps),
            Err(FirError::InvalidRate { .. })
        ));
        // The output is untouched on error.
        assert_eq!(taps, [7.0; 5]);
        // 20 Hz is not a low-pass at 40 Hz.
        assert!(matches!(
            PaperFir::<f32>::paper(40.0),
            Err(FirError::CutoffAboveNyquist { .. })
        ));
        assert!(PaperFir::<f32>::paper(40.001).is_ok());
        let mut hist = [0.0f64; 4];
        assert_eq!(
            FirSlice::new(&taps, &mut hist).err(),
            Some(FirError::LengthMismatch {
                taps: 5,
                history: 4
            })
        );
        assert_eq!(
            FirSlice::<f64>::new(&[], &mut []).err(),
            Some(FirError::NoTaps)
        );
    }

    #[test]
    fn window_names_round_trip() {
        for w in Window::ALL {
            assert_eq!(w.name().parse::<Window>(), Ok(w));
        }
        assert_eq!("Hanning".parse::<Window>(), Ok(Window::Hann));
        assert_eq!("boxcar".parse::<Window>(), Ok(Window::Rectangular));
        assert_eq!("kaiser".parse::<Window>(), Err(UnknownWindow));
        assert_eq!(Window::default(), Window::Hamming);
        // Hamming ends at 0.08 and peaks at 1; out of range is 0.
        assert!((Window::Hamming.value(0, 51) - 0.08).abs() < 1e-15);
        assert!((Window::Hamming.value(25, 51) - 1.0).abs() < 1e-15);
        assert_eq!(Window::Hamming.value(51, 51), 0.0);
    }
}
