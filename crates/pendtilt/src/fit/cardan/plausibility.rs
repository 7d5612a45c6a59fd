//! Is a fitted Cardan pendulum plausible for the log it came from?
//!
//! Per axis, the planar rules ([`crate::fit::plausibility`]): damping ratio at most
//! [`MAX_DAMPING_RATIO`], natural frequency inside the log's band. Between the axes, what a
//! Cardan joint allows:
//! - the inner axis cannot swing much slower than the outer: the pendulum's inertias about
//!   its centre of mass obey the triangle inequality, so Iyy <= Ixx + Izz <= Ixx + J_ring +
//!   Izz about the pivot, i.e. f_inner >= f_outer sqrt((b_x + b_ring) / (b_x + b_ring + b_z)).
//!   A fit lower than that by more than [`INNER_SLOWER_TOLERANCE`] is refused;
//! - the outer axis may be slower (the ring adds to its inertia), but not by more than
//!   [`MAX_FREQUENCY_RATIO`]: a ring with three times the pendulum's inertia is no
//!   pendulum sensor, and the usual cause is a fit that took one axis's motion for the other.
use pendtilt_core::spatial::cardan::CardanParams;
use pendtilt_core::PendulumParams;

use super::report::natural_frequencies_hz;
use crate::fit::plausibility::{self as planar, Implausible, LogSpan};

pub use planar::MAX_DAMPING_RATIO;

/// Largest ratio of the inner joint's natural frequency to the outer one's: 2 (the outer
/// axis's inertia b_x + b_ring at most 4 times the inner's b_y).
pub const MAX_FREQUENCY_RATIO: f64 = 2.0;

/// How far the inner joint's frequency may fall below the outer one's bound (the fit's
/// own scatter on a symmetric pendulum): 10 %.
pub const INNER_SLOWER_TOLERANCE: f64 = 0.10;

/// What makes a fitted Cardan pendulum implausible.
#[derive(Debug, Clone, PartialEq)]
pub enum Implausible3d {
    /// A value that is not finite or out of its physical range.
    NotPhysical {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The rule.
        why: &'static str,
    },
    /// One joint breaks a planar rule.
    Axis {
        /// "outer (x)" or "inner (y)".
        axis: &'static str,
        /// The planar rule it breaks.
        why: Implausible,
    },
    /// The two joints' frequencies are further apart than a Cardan rig allows.
    FrequencyRatio {
        /// Outer joint's natural frequency \[Hz\].
        f_outer: f64,
        /// Inner joint's natural frequency \[Hz\].
        f_inner: f64,
        /// The allowed range of f_inner / f_outer.
        range: [f64; 2],
    },
}

impl std::fmt::Display for Implausible3d {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Implausible3d::NotPhysical { name, value, why } => {
                write!(f, "{name} = {value:.4e} {why}")
            }
            Implausible3d::Axis { axis, why } => write!(f, "{axis} joint: {why}"),
            Implausible3d::FrequencyRatio {
                f_outer,
                f_inner,
                range,
            } => write!(
                f,
                "the joints' natural frequencies {f_outer:.4} Hz (outer) and {f_inner:.4} Hz \
                 (inner) are further apart than a Cardan pendulum allows: inner / outer = \
                 {:.3}, allowed {:.3} to {:.3} (the inner axis cannot be slower than the \
                 outer, whose ring only adds inertia; a ring three times the pendulum's is \
                 no sensor)",
                f_inner / f_outer,
                range[0],
                range[1]
            ),
        }
    }
}

/// Every reason why the fitted `c` is implausible for a log spanning `span`; empty when
/// it is plausible.
pub fn check(c: &CardanParams<f64>, span: &LogSpan) -> Vec<Implausible3d> {
    let mut out = Vec::new();
    for (name, value, positive) in [
        ("a_x", c.a_x, false),
        ("a_y", c.a_y, false),
        ("b_x", c.b_x, true),
        ("b_y", c.b_y, true),
        ("b_z", c.b_z, true),
        ("b_ring", c.b_ring, false),
        ("c_z", c.c[2], false),
    ] {
        let ok = value.is_finite()
            && if positive {
                value > 0.0
            } else {
                name == "c_z" || value >= 0.0
            };
        if !ok {
            let why = if positive {
                "is no pendulum (must be finite and > 0)"
            } else {
                "is no pendulum (must be finite and >= 0)"
            };
            out.push(Implausible3d::NotPhysical { name, value, why });
        }
    }
    if !out.is_empty() {
        return out;
    }
    let axes = [
        ("outer (x)", c.a_x, c.b_x + c.b_ring),
        ("inner (y)", c.a_y, c.b_y),
    ];
    for (axis, a, b) in axes {
        for why in planar::check(&PendulumParams { a, b, c: 0.0 }, span) {
            out.push(Implausible3d::Axis { axis, why });
        }
    }
    let [fo, fi] = natural_frequencies_hz(c);
    let bo = c.b_x + c.b_ring;
    let low = (bo / (bo + c.b_z)).sqrt() * (1.0 - INNER_SLOWER_TOLERANCE);
    let ratio = fi / fo;
    if !(ratio >= low && ratio <= MAX_FREQUENCY_RATIO) {
        out.push(Implausible3d::FrequencyRatio {
            f_outer: fo,
            f_inner: fi,
            range: [low, MAX_FREQUENCY_RATIO],
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span() -> LogSpan {
        LogSpan::of((0..30_001).map(|k| k as f64 * 1e-3)).unwrap()
    }

    /// MODEL.md 7.6's rig is plausible; by hand f = 2.19 Hz, zeta 0.30 on each axis.
    #[test]
    fn the_model_rig_is_plausible() {
        assert!(check(&CardanParams::default(), &span()).is_empty());
    }

    /// Each rule fires on its own, with its numbers.
    #[test]
    fn each_rule_fires_with_its_numbers() {
        let d = CardanParams::<f64>::default();
        // zeta_x = 0.6 / (2 sqrt(0.0053)) = 4.1 > 2.
        let r = check(&CardanParams { a_x: 0.6, ..d }, &span());
        assert!(
            matches!(&r[..], [Implausible3d::Axis { axis: "outer (x)", why: Implausible::Overdamped { zeta } }] if (zeta - 4.12).abs() < 0.01),
            "{r:?}"
        );
        // A ring of 8 times the pendulum's inertia: f_outer = f / 3, ratio 3 > 2.
        let r = check(
            &CardanParams {
                b_ring: 8.0 * d.b_x,
                ..d
            },
            &span(),
        );
        assert!(
            matches!(&r[..], [Implausible3d::FrequencyRatio { f_outer, f_inner, .. }] if (f_inner / f_outer - 3.0).abs() < 1e-9),
            "{r:?}"
        );
        assert!(
            r[0].to_string().contains("inner / outer = 3.000"),
            "{}",
            r[0]
        );
        // The inner axis 20 % slower than the outer: b_y 1.5625 b_x.
        let r = check(
            &CardanParams {
                b_y: 1.5625 * d.b_x,
                ..d
            },
            &span(),
        );
        assert!(
            matches!(&r[..], [Implausible3d::FrequencyRatio { .. }]),
            "{r:?}"
        );
        // A slightly slower inner axis (5 %) is within the fit's scatter.
        assert!(check(
            &CardanParams {
                b_y: 1.1025 * d.b_x,
                ..d
            },
            &span()
        )
        .is_empty());
        let r = check(&CardanParams { b_y: f64::NAN, ..d }, &span());
        assert!(
            matches!(&r[..], [Implausible3d::NotPhysical { name: "b_y", .. }]),
            "{r:?}"
        );
        let r = check(&CardanParams { a_y: -0.01, ..d }, &span());
        assert!(
            matches!(&r[..], [Implausible3d::NotPhysical { name: "a_y", .. }]),
            "{r:?}"
        );
    }
}
