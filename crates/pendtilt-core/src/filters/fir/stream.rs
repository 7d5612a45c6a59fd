//! The streaming filter: one type, [`Fir`], over its taps and history, which it either
//! owns ([`Arrays`]: length fixed at compile time, the microcontroller case) or borrows
//! from the caller ([`Slices`]: length chosen at run time, still no allocation).
use super::{design_lowpass, FirError, Window, PAPER_CUTOFF_HZ, PAPER_TAPS};
use crate::Real;

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

/// One step of the streaming FIR, whatever owns its buffers.
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

mod sealed {
    /// Keeps [`super::FirBuffers`] to this module's types, which guarantee equal lengths.
    pub trait Sealed {}
}

/// Where an [`Fir`] keeps its coefficients and history: [`Arrays`] or [`Slices`]. Both
/// hold the same number of taps and history samples, at least one.
pub trait FirBuffers: sealed::Sealed {
    /// The sample type.
    type Sample: Real;
    /// The coefficients, `taps[0]` weighing the newest sample.
    fn taps(&self) -> &[Self::Sample];
    /// The coefficients and the history, of equal lengths.
    fn split(&mut self) -> (&[Self::Sample], &mut [Self::Sample]);
}

/// Taps and history owned by the filter: `N` fixed at compile time, nothing lent.
#[derive(Debug, Clone)]
pub struct Arrays<T, const N: usize> {
    taps: [T; N],
    hist: [T; N],
}

impl<T, const N: usize> sealed::Sealed for Arrays<T, N> {}

impl<T: Real, const N: usize> FirBuffers for Arrays<T, N> {
    type Sample = T;
    #[inline(always)]
    fn taps(&self) -> &[T] {
        &self.taps
    }
    #[inline(always)]
    fn split(&mut self) -> (&[T], &mut [T]) {
        (&self.taps, &mut self.hist)
    }
}

/// Taps and history lent by the caller: the length is chosen at run time (a command-line
/// `--order`) while the filter itself still never allocates.
#[derive(Debug)]
pub struct Slices<'a, T> {
    taps: &'a [T],
    hist: &'a mut [T],
}

impl<T> sealed::Sealed for Slices<'_, T> {}

impl<T: Real> FirBuffers for Slices<'_, T> {
    type Sample = T;
    #[inline(always)]
    fn taps(&self) -> &[T] {
        self.taps
    }
    #[inline(always)]
    fn split(&mut self) -> (&[T], &mut [T]) {
        (self.taps, self.hist)
    }
}

/// A streaming FIR filter: one multiply-add per tap per sample, no allocation, over
/// buffers `B` ([`Arrays`] or [`Slices`]; the same arithmetic, so the same outputs bit
/// for bit for the same taps).
///
/// Output at step `k`: `y[k] = sum_i taps[i] x[k - i]`. Before the first sample the history
/// is taken to be the first input (see the [module docs](super)); [`Fir::is_filled`] turns
/// true once as many real samples as there are taps are in the window.
///
/// ```
/// use pendtilt_core::filters::fir::PaperFir;
/// let mut fir = PaperFir::<f32>::paper(1000.0).unwrap();
/// let y = fir.update(0.1); // a constant input...
/// assert!((y - 0.1).abs() < 1e-6); // ...gives the same constant from the first sample
/// ```
#[derive(Debug, Clone)]
pub struct Fir<B> {
    buffers: B,
    pos: usize,
    count: usize,
}

/// An [`Fir`] of `N` taps owning its buffers (the microcontroller case: everything lives
/// in the struct). `N = 0` is rejected at compile time:
///
/// ```compile_fail
/// let _ = pendtilt_core::filters::fir::FirArray::<f64, 0>::new([]);
/// ```
pub type FirArray<T, const N: usize> = Fir<Arrays<T, N>>;

/// An [`Fir`] over buffers the caller lends, for a length chosen at run time (the
/// `pendtilt filter` command, or a static buffer on a target).
///
/// ```
/// use pendtilt_core::filters::fir::{design_lowpass, FirSlice, Window};
/// let mut taps = [0.0f64; 31];
/// design_lowpass(20.0, 500.0, Window::Hann, &mut taps).unwrap();
/// let mut history = [0.0f64; 31];
/// let mut fir = FirSlice::new(&taps, &mut history).unwrap();
/// assert!((fir.update(2.0) - 2.0).abs() < 1e-12);
/// ```
pub type FirSlice<'a, T> = Fir<Slices<'a, T>>;

/// The paper's filter type: a 51-tap streaming FIR, built with [`Fir::paper`].
pub type PaperFir<T> = FirArray<T, PAPER_TAPS>;

impl<B: FirBuffers> Fir<B> {
    /// Filters one sample and returns the output for the same instant (delayed by
    /// [`Fir::group_delay`] samples, as every causal linear-phase filter is).
    #[inline]
    pub fn update(&mut self, x: B::Sample) -> B::Sample {
        let (taps, hist) = self.buffers.split();
        step(taps, hist, &mut self.pos, &mut self.count, x)
    }

    /// Forgets the history: the next sample is treated as the first (and pre-fills it).
    pub fn reset(&mut self) {
        self.pos = 0;
        self.count = 0;
    }

    /// `true` once as many samples as there are taps have been filtered since construction
    /// or [`Fir::reset`]: from then on the output depends only on real inputs, not on the
    /// pre-filled history.
    pub fn is_filled(&self) -> bool {
        self.count >= self.len()
    }

    /// Number of taps (order + 1).
    pub fn len(&self) -> usize {
        self.buffers.taps().len()
    }

    /// Always `false`: every constructor refuses empty taps. Present because a `len`
    /// without it reads as an oversight.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Group delay in samples, `(len - 1) / 2`, for symmetric taps (every
    /// [`design_lowpass`] design). Divide by the sample rate for seconds: 25 ms for the
    /// paper's filter at 1 kHz.
    pub fn group_delay(&self) -> f64 {
        (self.len() as f64 - 1.0) / 2.0
    }

    /// The coefficients, `taps[0]` weighing the newest sample.
    pub fn taps(&self) -> &[B::Sample] {
        self.buffers.taps()
    }
}

impl<T: Real, const N: usize> FirArray<T, N> {
    /// Group delay of a symmetric (linear-phase) `N`-tap filter, in samples: `(N - 1) / 2`.
    /// Every design of [`design_lowpass`] is symmetric; for other coefficients given to
    /// [`FirArray::new`] this is only the delay if they are symmetric too.
    pub const GROUP_DELAY: f64 = (N as f64 - 1.0) / 2.0;

    /// A filter with the given coefficients (`taps[0]` weighs the newest sample). Use it
    /// for coefficients designed elsewhere; [`FirArray::lowpass`] designs them here.
    pub fn new(taps: [T; N]) -> Self {
        const { assert!(N > 0, "an FIR filter needs at least one tap") };
        Self {
            buffers: Arrays {
                taps,
                hist: [T::zero(); N],
            },
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
}

impl<T: Real> PaperFir<T> {
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
            buffers: Slices {
                taps,
                hist: history,
            },
            pos: 0,
            count: 0,
        })
    }
}
