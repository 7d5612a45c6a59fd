//! Body angular acceleration theta'' from the gyro, for Algorithms 2 and 3.
//!
//! Two sources:
//! - [`ThetaDdSource::Window`]: the paper's Eq (22), `G_d = (G_k - G_{k-w}) / (w dt)`. It lags
//!   by half its window, while phi'' lags by the differentiator's delay: the two sides of
//!   Eq (21) are then out of step.
//! - [`ThetaDdSource::Matched`] (default): the gyro through the same smoothing differentiator
//!   as phi, so theta'' carries exactly the delay of phi''. On simulated scooter rides with
//!   engine angular vibration this measured about half the error of the best Eq (22)
//!   window (MODEL.md section 3).
use super::equations::windowed_rate;
use crate::filters::diff::Derivatives;
use crate::Real;

/// Where theta'' comes from.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ThetaDdSource<T> {
    /// Eq (22) over a window of about `span` seconds (rounded to whole samples at the
    /// first time step, at least 1, at most the buffer capacity minus one).
    Window {
        /// Window length \[s\].
        span: T,
    },
    /// The derivative of the gyro through the phi differentiator (same delay as phi'').
    /// The default.
    #[default]
    Matched,
}

/// The window's clock is rebased (every stored time shifted) once it passes this \[s\].
const REBASE_S: f64 = 1.0;

/// Capacity of the Eq (22) history: 256 samples, a 0.256 s window at 1 kHz.
pub const DEFAULT_WINDOW_CAPACITY: usize = 256;

/// Streaming theta'' from gyro samples. `W` bounds the Eq (22) window (no allocation).
///
/// The matched source needs no state of its own: it is the derivative output of the gyro
/// signal of the front end's two-signal differentiator, handed in on
/// each update. The window source keeps the gyro history.
#[derive(Debug, Clone)]
pub(crate) struct ThetaDd<T: Real, const W: usize = DEFAULT_WINDOW_CAPACITY> {
    source: ThetaDdSource<T>,
    // Eq (22) history ring: times (on `now`'s clock) and gyro values.
    times: [T; W],
    // Time since the clock's last rebase [s]; kept below REBASE_S so that time differences
    // keep the precision of the step in f32 whatever the log's length.
    now: T,
    rates: [T; W],
    head: usize,
    len: usize,
    w: usize,
    t_prev: Option<T>,
    last: T,
}

impl<T: Real, const W: usize> ThetaDd<T, W> {
    /// A new source.
    pub fn new(source: ThetaDdSource<T>) -> Self {
        Self {
            source,
            times: [T::zero(); W],
            now: T::zero(),
            rates: [T::zero(); W],
            head: 0,
            len: 0,
            w: 0,
            t_prev: None,
            last: T::zero(),
        }
    }

    /// Forgets all history.
    pub fn reset(&mut self) {
        self.len = 0;
        self.head = 0;
        self.w = 0;
        self.t_prev = None;
        self.now = T::zero();
        self.last = T::zero();
    }

    /// Advances the window's clock by the front end's step (every accepted sample, gyro or
    /// not, so that a missing gyro sample leaves its gap in the window's times).
    #[inline]
    pub fn advance(&mut self, dt: T) {
        if !matches!(self.source, ThetaDdSource::Window { .. }) {
            return;
        }
        self.now += dt;
        if self.now > T::lit(REBASE_S) {
            for t in self.times.iter_mut().take(self.len) {
                *t -= self.now;
            }
            if let Some(tp) = self.t_prev.as_mut() {
                *tp -= self.now;
            }
            self.now = T::zero();
        }
    }

    /// The last theta'' [rad/s^2] (held when the gyro is missing).
    pub fn last(&self) -> T {
        self.last
    }

    /// Takes the gyro sample `g` (finite) at the clock's time ([`Self::advance`]) and the
    /// gyro through the phi differentiator, `matched`, and returns
    /// `(theta'', still_initialising)`.
    #[inline]
    pub fn update(&mut self, g: T, matched: &Derivatives<T>) -> (T, bool) {
        match self.source {
            ThetaDdSource::Matched => {
                self.last = matched.d1;
                (self.last, false)
            }
            ThetaDdSource::Window { span } => self.window(self.now, g, span),
        }
    }

    fn window(&mut self, t: T, g: T, span: T) -> (T, bool) {
        let dt = match self.t_prev {
            Some(tp) => t - tp,
            None => T::zero(),
        };
        self.t_prev = Some(t);
        if W < 2 {
            return (T::zero(), true);
        }
        if self.w == 0 && dt > T::zero() {
            let n = (span / dt).round().to_f64();
            self.w = if n.is_finite() && n >= 1.0 {
                (n as usize).min(W - 1)
            } else {
                1
            };
        }
        // Push (t, g).
        self.times[self.head] = t;
        self.rates[self.head] = g;
        self.head = (self.head + 1) % W;
        if self.len < W {
            self.len += 1;
        }
        let want = self.w.max(1);
        let back = want.min(self.len - 1);
        if back == 0 {
            self.last = T::zero();
            return (self.last, true);
        }
        let old = (self.head + W - 1 - back) % W;
        self.last = windowed_rate(g, t, self.rates[old], self.times[old]);
        (self.last, back < want || self.w == 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filters::diff::{Response, SmoothingDifferentiator};

    #[test]
    fn window_gives_eq22_on_a_ramp_of_rate() {
        // G = 2 t → theta'' = 2 once the window (10 samples at 1 kHz) has filled.
        let mut s = ThetaDd::<f64, 32>::new(ThetaDdSource::Window { span: 0.010 });
        let mut init_count = 0;
        let mut last = 0.0;
        for k in 0..100 {
            let t = k as f64 * 1e-3;
            s.advance(if k == 0 { 0.0 } else { 1e-3 });
            let (v, init) = s.update(2.0 * t + 0.5, &Derivatives::default());
            if init {
                init_count += 1;
            }
            last = v;
        }
        assert_eq!(init_count, 10, "first sample plus nine filling samples");
        assert!((last - 2.0).abs() < 1e-9);
    }

    #[test]
    fn matched_differentiates_the_gyro() {
        let mut d = SmoothingDifferentiator::<f64>::new(Response::Butterworth, 3.0);
        let mut s = ThetaDd::<f64, 4>::new(ThetaDdSource::Matched);
        let mut last = 0.0;
        for k in 0..10_000 {
            let t = k as f64 * 1e-3;
            let g = -0.7 * t;
            last = s.update(g, &d.update(g, 1e-3)).0;
        }
        assert!((last + 0.7).abs() < 1e-9);
    }

    #[test]
    fn window_in_f32_after_two_hours_is_as_exact_as_at_the_start() {
        // The clock rebases, so an f32 window over a 2-hour log still divides by 10 ms.
        let mut s = ThetaDd::<f32, 32>::new(ThetaDdSource::Window { span: 0.010 });
        let mut last = 0.0;
        for k in 0..7_200_000u32 {
            s.advance(if k == 0 { 0.0 } else { 1e-3 });
            // G ramps at 2 rad/s^2 within each second (restarting keeps G small in f32).
            let t = (k % 1000) as f32 * 1e-3;
            last = s.update(2.0 * t, &Derivatives::default()).0;
        }
        assert!((last - 2.0).abs() < 2e-3, "{last}");
    }
}
