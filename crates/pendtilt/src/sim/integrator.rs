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
