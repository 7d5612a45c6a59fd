//! Designing the coefficients: the windows, the windowed-sinc low-pass (equal to scipy's
//! `firwin`) and the gain of any coefficient set at one frequency.
use super::FirError;
use crate::Real;
use nalgebra::ComplexField;

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
