//! What a firmware or application needs, in one import: `use pendtilt_core::prelude::*;`.
//!
//! The streaming interface ([`Estimator`], [`Sample`] in, [`Estimate`] out, [`Flags`]),
//! time stamps turned into steps ([`StepGate`], [`Micros`]), the scalar type ([`Real`]),
//! the rig's parameters, and every estimator with its settings. Internals (the filter
//! engine, differentiators, the supervisors' kernels) stay in their modules.
//!
//! ```
//! use pendtilt_core::prelude::*;
//!
//! // Algorithm 2 in f32 for the default rig; a StepGate turns time stamps into steps.
//! let mut alg2 = Alg2::<f32>::new(Alg2Settings::from_params(PendulumParams::default()));
//! let mut gate = StepGate::<f64>::new();
//! for k in 0..100 {
//!     let t = 1e-3 * k as f64; // the logger's stamp [s]
//!     let s = Sample { dt: gate.step(t), phi: 0.1, gyro: 0.0, ax: f32::NAN, ay: f32::NAN };
//!     let e = alg2.update(&s);
//!     // A pendulum at rest at 0.1 rad on a body at rest: the tilt is 0.1 rad.
//!     assert!((e.theta - 0.1).abs() < 1e-6 && !e.flags.contains(Flags::SAMPLE_MISSING));
//! }
//! ```
pub use crate::ekf::{Ekf, ModelSettings, SensorNoise, Ukf};
pub use crate::estimators::accel::{Accel, AccelSettings};
pub use crate::estimators::alg1::{Alg1, Alg1Settings};
pub use crate::estimators::alg2::{Alg2, Alg2Settings};
pub use crate::estimators::alg3::{Alg3, Alg3Settings};
pub use crate::estimators::complementary::{Complementary, ComplementarySettings};
pub use crate::estimators::pendulum::{Pendulum, PendulumSettings};
pub use crate::kalman::{KalmanOn, KalmanSettings, TiltKalman};
pub use crate::supervision::{
    Method, Objective, SupervisedAlg3, SupervisedAlg3Settings, SupervisorSettings,
};
pub use crate::{
    Estimate, Estimator, Flags, Micros, Output, PendulumParams, PhysicalParams, PlanarEstimator,
    Real, Sample, StepGate,
};
