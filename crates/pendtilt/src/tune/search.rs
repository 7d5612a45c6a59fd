//! The derivative-free search the likelihood fits use, and the budget (time limit and
//! progress) it runs under.
//!
//! Coordinate search on the logarithm of each parameter (noise variances span decades):
//! each pass runs a golden-section search ([`crate::peers::tune::golden_log`]) on one
//! parameter at a time within `decades` either side of the start, keeping a move only if
//! it lowers the cost. Robust (no gradient, no step size to pick), deterministic, and a
//! few passes suffice for three or four nearly separable parameters.
use crate::peers::tune::golden_log;
use std::time::Instant;

/// How long the fits may run and whom to tell how far they are.
pub struct Budget<'a> {
    /// Stop evaluating at this instant (the best found so far is kept).
    pub deadline: Option<Instant>,
    /// Cost evaluations made.
    pub evaluations: u64,
    /// True once the deadline stopped a search.
    pub stopped: bool,
    /// Called after each evaluation with the count so far.
    pub progress: Option<&'a dyn Fn(u64)>,
}

impl<'a> Budget<'a> {
    /// No time limit, no progress report.
    pub fn unlimited() -> Self {
        Self {
            deadline: None,
            evaluations: 0,
            stopped: false,
            progress: None,
        }
    }

    /// Counts one evaluation; `false` (and [`Self::stopped`] set) once past the deadline.
    pub fn tick(&mut self) -> bool {
        if self.stopped || self.deadline.is_some_and(|d| Instant::now() >= d) {
            self.stopped = true;
            return false;
        }
        self.evaluations += 1;
        if let Some(p) = self.progress {
            p(self.evaluations);
        }
        true
    }
}

/// Golden-section steps per parameter per pass.
pub const ITERATIONS: usize = 16;
/// Cost evaluations one parameter's golden search takes ([`golden_log`] evaluates the two
/// inner points, one per step, and both ends).
pub const EVALS_PER_PARAMETER: u64 = ITERATIONS as u64 + 4;

/// Minimises `cost` over positive parameters from `x0`, `rounds` passes, each parameter
/// within `decades` decades of its start. Returns the best parameters and their cost; the
/// cost at `x0` is evaluated first (it is what a move must beat).
pub fn coordinate_log(
    mut cost: impl FnMut(&[f64]) -> f64,
    x0: &[f64],
    decades: f64,
    rounds: usize,
    budget: &mut Budget,
) -> (Vec<f64>, f64) {
    let mut x = x0.to_vec();
    let mut best = if budget.tick() {
        cost(&x)
    } else {
        f64::INFINITY
    };
    let span = 10f64.powf(decades);
    for _ in 0..rounds {
        for i in 0..x.len() {
            let x_i = x0[i];
            let (v, c) = golden_log(
                |v| {
                    if !budget.tick() {
                        return f64::INFINITY;
                    }
                    let mut t = x.clone();
                    t[i] = v;
                    cost(&t)
                },
                x_i / span,
                x_i * span,
                ITERATIONS,
            );
            if c < best {
                best = c;
                x[i] = v;
            }
        }
    }
    (x, best)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_separable_minimum_in_log_space() {
        let target: [f64; 3] = [3e-4, 20.0, 0.5];
        let (x, c) = coordinate_log(
            |x| {
                x.iter()
                    .zip(target)
                    .map(|(v, t): (&f64, f64)| (v.ln() - t.ln()).powi(2))
                    .sum()
            },
            &[1.0, 1.0, 1.0],
            4.0,
            2,
            &mut Budget::unlimited(),
        );
        for (v, t) in x.iter().zip(target) {
            assert!((v / t - 1.0).abs() < 0.01, "{v} vs {t}");
        }
        assert!(c < 1e-4);
    }

    #[test]
    fn a_past_deadline_keeps_the_start() {
        let mut b = Budget {
            deadline: Some(Instant::now()),
            ..Budget::unlimited()
        };
        let (x, _) = coordinate_log(|x| x[0], &[1.0], 2.0, 2, &mut b);
        assert_eq!(x, vec![1.0]);
        assert!(b.stopped);
    }
}
