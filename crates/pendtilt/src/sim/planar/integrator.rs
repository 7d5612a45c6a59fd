//! Classical fixed-step Runge-Kutta (RK4).
//!
//! The forcing (body motion, vibration) depends only on time, so the caller evaluates it
//! once at the start, middle and end of each step and the right-hand side is told which
//! of the three [`Node`]s a stage sits on; the middle value serves both middle stages.
//! The step is `1 / (rate * substeps)`: a fixed multiple of the sample rate, so every sample
//! time is a step boundary and the error falls 16-fold per halving of the step
//! (`tests/sim_integrator.rs`).

/// Where in the step a stage is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Node {
    /// t.
    Start,
    /// t + h/2.
    Mid,
    /// t + h.
    End,
}

/// One RK4 step of length `h` from `y`, with `f(node, y)` the right-hand side.
#[inline]
pub fn rk4_step<const N: usize>(
    y: [f64; N],
    h: f64,
    mut f: impl FnMut(Node, [f64; N]) -> [f64; N],
) -> [f64; N] {
    let axpy = |a: f64, x: &[f64; N], y: &[f64; N]| -> [f64; N] {
        core::array::from_fn(|i| y[i] + a * x[i])
    };
    let k1 = f(Node::Start, y);
    let k2 = f(Node::Mid, axpy(0.5 * h, &k1, &y));
    let k3 = f(Node::Mid, axpy(0.5 * h, &k2, &y));
    let k4 = f(Node::End, axpy(h, &k3, &y));
    core::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]))
}

/// The largest `|lambda| h` a run may take: RK4 diverges beyond 2.8 and at 0.5 its
/// amplitude and phase errors per step are below 1e-4, far under any physical damping.
pub const MAX_LAMBDA_STEP: f64 = 0.5;

/// The magnitude \[1/s\] of the fastest root of `s^2 + c s + k` (a joint with stiffness
/// and damping per unit inertia `k`, `c`): the rate RK4's step must resolve.
pub fn fastest_mode(k: f64, c: f64) -> f64 {
    let d = c * c - 4.0 * k;
    if d < 0.0 {
        k.sqrt()
    } else {
        0.5 * (c + d.sqrt())
    }
}

/// `x` with 3 decimals, or in exponent form when large (a gravity of 1e300 gave 150 digits).
fn short(x: f64) -> String {
    if x.abs() < 1e6 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

/// Refuses a step `1 / (rate substeps)` too long for a pendulum whose fastest mode is
/// `lambda` \[1/s\]: such a run diverged (`--rate 1`: phi -25040 rad, exit 0) or drifted
/// without a word. The error names the substeps that would do.
pub fn check_step(lambda: f64, rate: f64, substeps: u32) -> Result<(), super::SimError> {
    let h = 1.0 / (rate * f64::from(substeps));
    if lambda * h <= MAX_LAMBDA_STEP {
        return Ok(());
    }
    let need = (lambda / (MAX_LAMBDA_STEP * rate)).ceil();
    let fix = if need <= 10_000.0 {
        format!("raise substeps to {need} (--substeps {need}) or the rate")
    } else {
        "raise the rate".to_string()
    };
    Err(super::SimError::invalid(
        "substeps",
        format!(
            "an integration step of {h:.3e} s (1 / (rate {rate} Hz x substeps {substeps})) is \
             too long for the pendulum, whose fastest mode is {} rad/s ({} Hz): the \
             integrator would drift or diverge (step x mode {}, at most {MAX_LAMBDA_STEP}); \
             {fix}",
            short(lambda),
            short(lambda / std::f64::consts::TAU),
            short(lambda * h)
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = -y + t: fourth-order convergence against the exact solution.
    #[test]
    fn fourth_order_on_a_linear_ode() {
        let exact = |t: f64| t - 1.0 + 2.0 * (-t).exp();
        let err = |n: usize| {
            let h = 1.0 / n as f64;
            let mut y = [1.0];
            for k in 0..n {
                let t0 = k as f64 * h;
                y = rk4_step(y, h, |node, y| {
                    let t = match node {
                        Node::Start => t0,
                        Node::Mid => t0 + 0.5 * h,
                        Node::End => t0 + h,
                    };
                    [-y[0] + t]
                });
            }
            (y[0] - exact(1.0)).abs()
        };
        let ratio = err(10) / err(20);
        assert!((14.0..18.0).contains(&ratio), "ratio {ratio}");
    }
}
