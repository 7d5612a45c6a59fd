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
//!   by either method, with fixed-capacity buffers and no allocation; its settings in
//!   [`settings`].
//! - Private to the supervisor: `ring` (the window of Eq (29) terms and the passes Newton
//!   takes over it), `asin` (changes of asin without cancellation), `compensated` (its
//!   sums, compensated), `objective` (what Newton minimises, [`Objective`], and its
//!   differences).
//!
//! Why this is cheap enough to run live: for a fixed differentiator, the per-sample
//! kinematics (phi, phi', phi'', G_d, G_k) do not depend on K, L, M, N. They are computed
//! once per sample by the running estimator and kept in a ring buffer; each evaluation
//! of the cost for new gains is then one pass of Eq (30) over the buffer.
mod asin;
mod compensated;
pub mod newton;
mod objective;
mod ring;
pub mod rls;
pub mod settings;
pub mod supervised;

pub use newton::{NewtonError, NewtonIteration, NewtonSettings};
pub use objective::Objective;
pub use rls::{Rls, RlsSettings};
pub use settings::{Method, SettingsError, SupervisedAlg3Settings, SupervisorSettings};
pub use supervised::{SupervisedAlg3, SupervisedEstimate, SupervisionFlags};
