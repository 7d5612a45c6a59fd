//! What a 3-D fit returns ([`Fit3dReport`]).
use std::time::Duration;

use pendtilt_core::spatial::cardan::CardanParams;

use super::{Params, NAMES, NP};
use crate::fit::{Iteration, Stop, Target};

/// The result of a 3-D fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit3dReport {
    /// What drove the simulated pendulum.
    pub target: Target,
    /// Which entries of the parameter vector ([`NAMES`]) moved; the others were held.
    pub active: [bool; NP],
    /// The start vector.
    pub start: Params,
    /// The fitted vector.
    pub params: Params,
    /// The fitted pendulum: the fitted values with the held ones of the start rig.
    pub fitted: CardanParams<f64>,
    /// The start rig's pendulum.
    pub start_rig: CardanParams<f64>,
    /// RMS residual over both encoders at the start \[rad\].
    pub start_cost: f64,
    /// RMS residual over both encoders at the fitted values \[rad\].
    pub cost: f64,
    /// RMS residual of phi_x and of phi_y at the fitted values \[rad\].
    pub cost_per_axis: [f64; 2],
    /// Every iteration (0 is the start).
    pub iterations: Vec<Iteration>,
    /// Simulations of the log run, including the identifiability check.
    pub evaluations: usize,
    /// Why the optimiser stopped.
    pub stop: Stop,
    /// Rows compared (two residuals each).
    pub rows: usize,
    /// The identifiability check's sensitivity: the RMS change of the encoders for a 100 %
    /// change of a_x, a_y, b_x + b_ring, b_y along the least sensitive direction \[rad\].
    pub sensitivity: f64,
    /// The RMS change of the encoders for a 1 cm pivot offset along body z, the other
    /// parameters refitted \[rad\]: c_z is fitted when it reaches the threshold.
    pub offset_sensitivity: f64,
    /// Wall time of the fit.
    pub elapsed: Duration,
}

impl Fit3dReport {
    /// The names of the entries that were fitted.
    pub fn fitted_names(&self) -> Vec<&'static str> {
        (0..NP)
            .filter(|&j| self.active[j])
            .map(|j| NAMES[j])
            .collect()
    }

    /// Small-angle natural frequencies (outer, inner) of the fitted pendulum on a level
    /// body \[Hz\] (MODEL.md 7.2).
    pub fn natural_frequencies_hz(&self) -> [f64; 2] {
        natural_frequencies_hz(&self.fitted)
    }

    /// Damping ratios (outer, inner) of the fitted pendulum on a level body (MODEL.md 7.2).
    pub fn damping_ratios(&self) -> [f64; 2] {
        damping_ratios(&self.fitted)
    }
}

/// Natural frequencies (outer, inner) of `c` on a level body \[Hz\]:
/// 1 / (2 pi sqrt(b_x + b_ring)), 1 / (2 pi sqrt(b_y)).
pub fn natural_frequencies_hz(c: &CardanParams<f64>) -> [f64; 2] {
    c.natural_frequencies().map(|w| w / std::f64::consts::TAU)
}

/// Damping ratios (outer, inner) of `c` on a level body: a_x / (2 sqrt(b_x + b_ring)),
/// a_y / (2 sqrt(b_y)).
pub fn damping_ratios(c: &CardanParams<f64>) -> [f64; 2] {
    [
        c.a_x / (2.0 * (c.b_x + c.b_ring).sqrt()),
        c.a_y / (2.0 * c.b_y.sqrt()),
    ]
}
