//! Is a fitted pendulum plausible for the log it came from?
//!
//! An optimiser that stops on its tolerances has found a minimum of the cost, not
//! necessarily a pendulum. A wrong unit is the usual cause: time in milliseconds makes the
//! log 1000 times slower, and the fit then "converges" to a damping ratio near 90. These
//! checks compare the fitted a, b with the log itself, so that such a result is named
//! instead of printed as converged.
use pendtilt_core::PendulumParams;

/// Largest plausible damping ratio a / (2 sqrt b). A pendulum damped more than twice
/// critically barely swings: its a and b are then not told apart by any log, and the
/// usual cause is a unit mistake (time in ms gives about 90).
pub const MAX_DAMPING_RATIO: f64 = 2.0;

/// What makes a fitted pendulum implausible.
#[derive(Debug, Clone, PartialEq)]
pub enum Implausible {
    /// a < 0 or b <= 0, or either not finite: no pendulum.
    NotPhysical {
        /// Fitted a \[s\].
        a: f64,
        /// Fitted b \[s^2\].
        b: f64,
    },
    /// The damping ratio is above [`MAX_DAMPING_RATIO`].
    Overdamped {
        /// a / (2 sqrt b).
        zeta: f64,
    },
    /// The natural frequency lies outside what the log can show: below one period in the
    /// log's duration, or above its Nyquist frequency.
    OutsideBand {
        /// Fitted natural frequency \[Hz\].
        f_n: f64,
        /// 1 / duration \[Hz\].
        low: f64,
        /// Half the median sample rate \[Hz\].
        high: f64,
    },
}

impl std::fmt::Display for Implausible {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Implausible::NotPhysical { a, b } => write!(
                f,
                "a = {a:.4e} s, b = {b:.4e} s^2 is no pendulum (a must be >= 0, b > 0)"
            ),
            Implausible::Overdamped { zeta } => write!(
                f,
                "damping ratio {zeta:.3} is above {MAX_DAMPING_RATIO} (a pendulum that barely \
                 swings; time in ms instead of s gives about 90)"
            ),
            Implausible::OutsideBand { f_n, low, high } => write!(
                f,
                "natural frequency {f_n:.4} Hz is outside the log's band {low:.4}-{high:.1} Hz \
                 (one period in the log's duration to half its sample rate)"
            ),
        }
    }
}

/// The time span of a log: duration and median step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogSpan {
    /// Last minus first time \[s\].
    pub duration: f64,
    /// Median time step \[s\].
    pub median_step: f64,
}

impl LogSpan {
    /// From the log's time stamps (non-finite ones ignored). None for fewer than two.
    pub fn of(times: impl IntoIterator<Item = f64>) -> Option<Self> {
        let t: Vec<f64> = times.into_iter().filter(|v| v.is_finite()).collect();
        if t.len() < 2 {
            return None;
        }
        let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        steps.sort_by(f64::total_cmp);
        Some(Self {
            duration: t[t.len() - 1] - t[0],
            median_step: steps[steps.len() / 2],
        })
    }
}

/// Every reason why `p` (a fitted a, b) is implausible for a log spanning `span`; empty
/// when it is plausible.
pub fn check(p: &PendulumParams<f64>, span: &LogSpan) -> Vec<Implausible> {
    if !(p.a.is_finite() && p.b.is_finite() && p.a >= 0.0 && p.b > 0.0) {
        return vec![Implausible::NotPhysical { a: p.a, b: p.b }];
    }
    let mut out = Vec::new();
    let zeta = p.a / (2.0 * p.b.sqrt());
    if zeta > MAX_DAMPING_RATIO {
        out.push(Implausible::Overdamped { zeta });
    }
    let f_n = 1.0 / (2.0 * std::f64::consts::PI * p.b.sqrt());
    let low = 1.0 / span.duration;
    let high = 0.5 / span.median_step;
    if span.duration > 0.0 && span.median_step > 0.0 && !(f_n >= low && f_n <= high) {
        out.push(Implausible::OutsideBand { f_n, low, high });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(a: f64, b: f64) -> PendulumParams<f64> {
        PendulumParams { a, b, c: 0.0 }
    }

    /// The MODEL.md rig (f_n 2.19 Hz, zeta 0.30) on a 60 s, 1 kHz log is plausible; by
    /// hand: zeta = 0.0436 / (2 sqrt 0.0053) = 0.30.
    #[test]
    fn the_model_rig_is_plausible() {
        let span = LogSpan::of((0..60_001).map(|k| k as f64 * 1e-3)).unwrap();
        assert!((span.duration - 60.0).abs() < 1e-9);
        assert!(check(&p(0.043644, 0.0053024), &span).is_empty());
    }

    /// zeta = 0.9 / (2 sqrt 0.0001) = 45: over the bound; f_n = 15.9 Hz is inside the
    /// band of a 1 kHz log. b = 1 (f_n 0.159 Hz) on a 5 s log (low 0.2 Hz) is outside;
    /// b = 1e-8 (f_n 1592 Hz) above the 500 Hz Nyquist. Negative a: not physical.
    #[test]
    fn each_rule_fires_on_its_own() {
        let span = LogSpan::of((0..5001).map(|k| k as f64 * 1e-3)).unwrap();
        let r = check(&p(0.9, 1e-4), &span);
        assert!(
            matches!(r[..], [Implausible::Overdamped { zeta }] if (zeta - 45.0).abs() < 1e-9),
            "{r:?}"
        );
        let r = check(&p(0.1, 1.0), &span);
        assert!(
            matches!(r[..], [Implausible::OutsideBand { low, .. }] if (low - 0.2).abs() < 1e-9),
            "{r:?}"
        );
        let r = check(&p(1e-6, 1e-8), &span);
        assert!(
            matches!(r[..], [Implausible::OutsideBand { high, .. }] if (high - 500.0).abs() < 1e-6),
            "{r:?}"
        );
        assert!(matches!(
            check(&p(-0.01, 0.005), &span)[..],
            [Implausible::NotPhysical { .. }]
        ));
        assert!(check(&p(0.04, 0.005), &span).is_empty());
    }
}
