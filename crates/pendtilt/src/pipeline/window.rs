//! Which rows an error table scores: the one rule shared by `estimate`, `report` and
//! `batch`, planar and 3-D.
//!
//! Without `--score-from` the rows from [`DEFAULT_SCORE_FROM`] after the first row's time
//! on are scored, so that the filters' start-up is not read as their accuracy; a log that
//! lasts less than [`SHORT_LOG`] is scored whole instead, since the start-up is then most of
//! what it shows (the paper's 5 s step response, `simulate --scenario sigmoid`). A start the
//! user gives is always kept.

/// Errors are scored from this long after the first row \[s\] when the user does not say
/// (`--score-from`), planar and 3-D alike: the start-up is over by then. The model-based
/// filters settle in about 2 s (the planar ekf's RMS on the 60 s scooter ride is 0.079°
/// from 0 s, 0.035° from 2 s, 0.032° from 5 s), VQF's accelerometer low-pass takes 3 s;
/// Mahony's slow integral still settles (1.51° from 0 s, 0.26° from 5 s, 0.18° from
/// 10 s). See docs/estimators.md#scoring.
pub const DEFAULT_SCORE_FROM: f64 = 5.0;

/// A log that lasts less than this \[s\] ([`duration`]) is scored whole when no start is
/// given: the default window would leave out half of it or more (all of a 5 s step
/// response).
pub const SHORT_LOG: f64 = 2.0 * DEFAULT_SCORE_FROM;

/// Where the scored rows start, as resolved at the end of a log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// Rows from this long after the first row's time on are scored \[s\].
    pub from: f64,
    /// The default start was not applied because the log is short: how long it lasts \[s\].
    pub short_log: Option<f64>,
}

impl Window {
    /// The window of a log that lasts `duration` seconds ([`duration`]), for a start the
    /// user gave (`requested`) or not.
    pub fn resolve(requested: Option<f64>, duration: f64) -> Self {
        match requested {
            Some(from) => Self {
                from,
                short_log: None,
            },
            // A hair of rounding: 10,000 rows at 1 kHz last 10 s.
            None if duration < SHORT_LOG - 1e-9 => Self {
                from: 0.0,
                short_log: Some(duration),
            },
            None => Self {
                from: DEFAULT_SCORE_FROM,
                short_log: None,
            },
        }
    }

    /// The table's heading: the window and the rows scored in it, e.g.
    /// `t >= t0 + 5 s (55001 rows scored)`.
    pub fn heading(&self, rows: u64) -> String {
        match self.short_log {
            Some(span) => format!(
                "t >= t0 + {} s ({rows} rows scored: the whole log, which lasts {span:.1} s, \
                 under the {SHORT_LOG} s from which the first {DEFAULT_SCORE_FROM} s are left \
                 out; --score-from SECONDS sets the start)",
                self.from
            ),
            None => format!("t >= t0 + {} s ({rows} rows scored)", self.from),
        }
    }
}

/// How long a log of `rows` rows with finite times from `first` to `last` lasts \[s\]: its
/// span and one mean step more, so that 10,000 rows at 1 kHz last 10 s.
pub fn duration(first: f64, last: f64, rows: u64) -> f64 {
    if rows < 2 {
        return 0.0;
    }
    (last - first) * rows as f64 / (rows - 1) as f64
}

/// Statistics kept for both candidate windows until the log's span is known: every row
/// and the rows of the requested (or default) window.
#[derive(Debug, Clone, PartialEq)]
pub struct Scorer<S> {
    requested: Option<f64>,
    t0: Option<f64>,
    last: f64,
    /// Rows with a finite time.
    timed: u64,
    /// From the requested start, or from the default one.
    windowed: Vec<S>,
    /// From the first row, kept only when no start was given.
    whole: Vec<S>,
}

impl<S: Clone + Default> Scorer<S> {
    /// Statistics for `n` estimators.
    pub fn new(requested: Option<f64>, n: usize) -> Self {
        Self {
            requested,
            t0: None,
            last: f64::NAN,
            timed: 0,
            windowed: vec![S::default(); n],
            whole: if requested.is_none() {
                vec![S::default(); n]
            } else {
                Vec::new()
            },
        }
    }

    /// Scores one row at time `t`: `add` is called on each estimator's statistics of
    /// every window the row falls in, with the estimator's index.
    pub fn row(&mut self, t: f64, mut add: impl FnMut(usize, &mut S)) {
        if t.is_finite() {
            self.t0.get_or_insert(t);
            self.last = t;
            self.timed += 1;
        }
        let Some(t0) = self.t0 else { return };
        let from = self.requested.unwrap_or(DEFAULT_SCORE_FROM);
        // A NaN time compares false: such a row is in no window.
        if t >= t0 + from {
            self.windowed
                .iter_mut()
                .enumerate()
                .for_each(|(i, s)| add(i, s));
        }
        if t >= t0 {
            self.whole
                .iter_mut()
                .enumerate()
                .for_each(|(i, s)| add(i, s));
        }
    }

    /// The window the log's span resolves to, and its statistics.
    pub fn finish(self) -> (Window, Vec<S>) {
        let lasts = self
            .t0
            .map_or(0.0, |t0| duration(t0, self.last, self.timed));
        let window = Window::resolve(self.requested, lasts);
        let stats = if window.short_log.is_some() {
            self.whole
        } else {
            self.windowed
        };
        (window, stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_log_is_scored_whole_unless_a_start_is_given() {
        let short = Window::resolve(None, 4.999);
        assert_eq!((short.from, short.short_log), (0.0, Some(4.999)));
        assert!(short
            .heading(5000)
            .contains("the whole log, which lasts 5.0 s"));
        let long = Window::resolve(None, SHORT_LOG);
        assert_eq!((long.from, long.short_log), (DEFAULT_SCORE_FROM, None));
        let given = Window::resolve(Some(1.5), 3.0);
        assert_eq!((given.from, given.short_log), (1.5, None));
        assert_eq!(given.heading(7), "t >= t0 + 1.5 s (7 rows scored)");
    }

    #[test]
    fn the_scorer_keeps_the_window_the_span_calls_for() {
        // Rows at 1 Hz from t = 100 s; each adds 1 to a count.
        let run = |requested, rows: usize| {
            let mut s = Scorer::<u32>::new(requested, 2);
            for k in 0..rows {
                s.row(100.0 + k as f64, |i, c| *c += 1 + i as u32 * 10);
            }
            s.finish()
        };
        // 9 rows at 1 Hz last 9 s: short, every row.
        assert_eq!(run(None, 9), (Window::resolve(None, 9.0), vec![9, 99]));
        // 10 rows last 10 s: rows from t0 + 5 on (t = 105..=109: 5 rows).
        assert_eq!(run(None, 10).1, vec![5, 55]);
        // Given 0 s: all rows, whatever the span; nothing kept twice.
        let (w, stats) = run(Some(0.0), 10);
        assert_eq!((w.from, stats), (0.0, vec![10, 110]));
        // A NaN time before the first finite one is not scored and does not set t0.
        let mut s = Scorer::<u32>::new(Some(0.0), 1);
        s.row(f64::NAN, |_, c| *c += 1);
        s.row(3.0, |_, c| *c += 1);
        assert_eq!(s.finish().1, vec![1]);
    }
}
