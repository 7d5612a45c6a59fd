//! Live supervision (paper section IV-C/D): re-fitting the estimator's parameters while it
//! runs, against the gyro, with no true angle.
//!
//! Eq (29): `F(P) = RMS(d/dt theta_est(P) - G)`. For Algorithm 3 (Eq 30),
//! `theta_est = phi + asin(K phi' + L phi'' + M G_d) + N G_k`, so for consecutive samples
//! `d/dt theta_est ~ (theta_k - theta_(k-1)) / (t_k - t_(k-1))`, compared with the mean of
//! the two gyro samples (the rate at the middle of the interval).
//!
//! - [`newton`]: the paper's Newton's method, Eqs (24)-(28), one iteration at a time, on the
//!   stack (also used by the offline fit in the `pendtilt` crate).
//! - [`rls`]: recursive least squares with forgetting (beyond the paper), the cheap
//!   alternative: the asin argument is linear in K, L, M.
//! - [`supervised`]: [`SupervisedAlg3`], Algorithm 3 whose K, L, M, N are supervised live
//!   by either method, with fixed-capacity buffers and no allocation.
//!
//! Why this is cheap enough to run live: for a fixed differentiator, the per-sample
//! kinematics (phi, phi', phi'', G_d, G_k) do not depend on K, L, M, N. They are computed
//! once per sample by the running estimator and kept in a ring buffer; each evaluation
//! of the cost for new gains is then one pass of Eq (30) over the buffer.
pub mod newton;
pub mod rls;
pub mod supervised;

pub use newton::{NewtonError, NewtonIteration, NewtonSettings};
pub use rls::{Rls, RlsSettings};
pub use supervised::{
    Method, SettingsError, SupervisedAlg3, SupervisedAlg3Settings, SupervisedEstimate,
    SupervisionFlags, SupervisorSettings,
};

/// What Newton's method minimises: the paper's RMS (Eqs 23 and 29) or its square.
///
/// Both have the same minimiser. The RMS is the paper's; far from its minimum it is
/// nearly a cone, where Newton's step overshoots and must be halved (see [`newton`]). The
/// mean square is close to a quadratic in the parameters (the asin argument is linear in
/// them), so Newton converges on it in very few iterations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objective {
    /// `sqrt(mean(r^2))`, Eqs (23), (29) as printed (default).
    #[default]
    Rms,
    /// `mean(r^2)`.
    MeanSquare,
}

impl Objective {
    /// The objective from a sum of squared residuals over `n` samples (NaN when `n` = 0).
    #[inline]
    pub fn from_sum<T: crate::Real>(self, sum_sq: T, n: usize) -> T {
        if n == 0 {
            return T::nan();
        }
        let ms = sum_sq / T::lit(n as f64);
        match self {
            Objective::Rms => ms.sqrt(),
            Objective::MeanSquare => ms,
        }
    }
}
