//! What a firmware or application needs, in one import: `use pendtilt_core::prelude::*;`.
//!
//! The streaming interface ([`Estimator`], [`Sample`] in, [`Estimate`] out, [`Flags`]),
//! time stamps turned into steps ([`StepGate`], [`Micros`]), the scalar type ([`Real`]),
//! the rig's parameters, and every estimator with its settings, planar and 3-D. The 3-D
//! estimators take a [`SpatialSample`] and give an [`Attitude`] ([`SpatialEstimator`]);
//! their names carry `3d` where a planar one has the same: [`Ekf3d`] and [`Ukf3d`] with
//! [`Ekf3dSettings`] (`imu3d` is [`Ekf3d`] on [`Ekf3dSettings::imu_only`]), [`Inv3d`],
//! [`Pendulum3d`] and [`Accel3d`] (on the planar [`AccelSettings`]). Internals (the filter
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
//!
//! The 3-D filter the same way, on a body resting level:
//!
//! ```
//! use pendtilt_core::prelude::*;
//!
//! let mut ekf3d = Ekf3d::<f64>::new(Ekf3dSettings::default());
//! let mut imu3d = Ekf3d::<f64>::new(Ekf3dSettings::default().imu_only());
//! for k in 0..100 {
//!     let dt = if k == 0 { 0.0 } else { 1e-3 };
//!     let s = SpatialSample::new(dt, [0.0, 0.0], [0.0; 3], [0.0, 0.0, 9.81]);
//!     let (a, b) = (ekf3d.update(&s), imu3d.update(&s));
//!     assert!(a.roll.abs() < 1e-6 && a.pitch.abs() < 1e-6);
//!     assert!(b.roll.abs() < 1e-6 && b.pitch.abs() < 1e-6);
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
pub use crate::spatial::accel::Accel as Accel3d;
pub use crate::spatial::cardan::CardanParams;
pub use crate::spatial::ekf::{
    Adaptation as Ekf3dAdaptation, Ekf as Ekf3d, Settings as Ekf3dSettings, SpeedSettings,
    Ukf as Ukf3d,
};
pub use crate::spatial::inv::{Inv3d, Inv3dSettings};
pub use crate::spatial::pendulum::{
    Pendulum as Pendulum3d, PendulumSettings as Pendulum3dSettings,
};
pub use crate::spatial::{Attitude, Mounting, SpatialEstimator, SpatialSample};
pub use crate::supervision::{
    Method, Objective, SupervisedAlg3, SupervisedAlg3Settings, SupervisorSettings,
};
pub use crate::{
    Estimate, Estimator, Flags, Micros, Output, PendulumParams, PhysicalParams, PlanarEstimator,
    Real, Sample, StepGate,
};
