//! Offline parameter fitting (paper section IV-B, C): the paper's Newton's method on the
//! Eq (23) / Eq (29) cost, and Levenberg-Marquardt with an analytic Jacobian.
//!
//! - Eq (23): `F(P) = RMS(theta_est(P) - theta_true)`, with a true angle
//!   ([`Target::Truth`]).
//! - Eq (29): `F(P) = RMS(d/dt theta_est(P) - G)`, against the gyro ([`Target::Gyro`]);
//!   `d/dt theta_est` is the difference of consecutive estimates over their time step,
//!   compared with the mean of the two gyro samples.
//! - Parameters: a, b for alg1 (Eq 20) and alg2 (Eq 21); K, L, M, N for alg3 (Eq 30).
//!
//! Methods:
//! - [`Method::Newton`]: Eqs (24)-(28) with the finite differences of MODEL.md section 3
//!   (step h, difference dp, tolerances and iteration limit in
//!   [`pendtilt_core::supervision::NewtonSettings`]), one logged [`Iteration`] per step; the
//!   iteration itself is [`pendtilt_core::supervision::newton::newton_iteration`], the same
//!   code the live supervisor runs.
//! - [`Method::Lm`]: Levenberg-Marquardt (beyond the paper) on the sum of squared
//!   residuals, with the analytic Jacobian of Eq (20)/(21)/(30), normal equations
//!   accumulated in one pass into nalgebra 4x4 fixed matrices ([`lm`]). The
//!   `levenberg-marquardt` crate was not used: its current release depends on nalgebra
//!   0.34 (we are on 0.35), and it wants the whole residual vector and Jacobian (100,000 x 4)
//!   materialised and QR-factorised every iteration.
//!
//! Costs ([`Cost`]): the output error of [`output`] (the pendulum simulated from the true
//! angle against the measured phi; the default, [`Cost::Auto`], for a, b against the true
//! angle), or the paper's inverse cost above (`--cost inverse`; the only one for the gyro
//! target and alg3). The output error is not biased by vibration: on a chirp with the full `scooter` vibration it recovers a
//! and b within 2 % where Eq (23) is 4-6 % off; on the 60 s `scooter` ride b within 8-13 %
//! where Eq (23) is 53-57 % low, and within 1 % when the simulation is driven by the
//! accelerometer ([`output::OutputSettings::accel`]) (docs/fitting-and-tuning.md, "Parameter fitting").
//!
//! Fitting is fast because the kinematics are cached: see [`problem`]. The live
//! counterparts (sliding window Newton, RLS) are in [`pendtilt_core::supervision`].
//!
//! # Newton vs Levenberg-Marquardt vs RLS (measured)
//!
//! `cargo bench -p pendtilt --bench fit` on a 100,000-sample log (a 10 s chirp 0.2-3 Hz with
//! the default noisy sensors, repeated to 100 s), alg2, Eq (23), start a x 1.5, b x 0.5, on
//! the 2-core development machine (shared, so +-15 %):
//!
//! | method | iterations | passes over the log | time (fit / with the 14 ms kinematics pass) | final RMS | a error | b error |
//! |---|---|---|---|---|---|---|
//! | Newton (Eqs 24-28, RMS) | 7 | 87 | 171 ms / 188 ms | 3.797e-3 rad | +0.70 % | -1.07 % |
//! | Levenberg-Marquardt | 3 | 6 | 28 ms / 46 ms | 3.797e-3 rad | +0.72 % | -1.07 % |
//!
//! Both reach the same minimum (the 1 % is the log's, whose repeats restart the pendulum
//! every 10 s); LM needs 15 times fewer passes. Live ([`pendtilt_core::supervision`],
//! `SupervisedAlg3`, 1 kHz, bench group `live_supervisor`, thread CPU time on the shared
//! machine): RLS costs 123 ns per sample including the estimator (47 ns alone), the
//! windowed Newton with the defaults (RMS, window 1000, refit every 2000) 113 ns, with a
//! refit every 250 samples 424 ns. With the settings of test `fit_live` (mean square,
//! refit every 250) both converge from 50 % off to within 5 % (RLS) or 10 % (Newton) of a, b, -b in 9.5 s of a
//! chirp and follow a doubling of the damping to within 10 % (Newton in 6.5 s, RLS 9 s).
//!
//! Before fitting, the cost's sensitivity is checked ([`sensitivity`]): a log in which a
//! 100 % change of the parameters (along the least sensitive direction) changes the
//! estimate by less than [`FitSettings::min_sensitivity`] is reported as
//! [`FitError::Unidentifiable`] instead of returning a number.
pub mod cardan;
pub mod lm;
pub mod output;
pub mod plausibility;
pub mod problem;
mod report;
mod run;
mod settings;
pub mod steps;

pub use lm::LmSettings;
pub use problem::{fixed_cutoff, KinematicsSettings, Problem};
pub use report::{FitReport, Iteration, Stop};
pub(crate) use run::solve_active;
pub use run::{fit, fit_log, fit_output_log, prepare, sensitivity};
pub use settings::{Algorithm, Cost, FitError, FitSettings, Method, Target};
