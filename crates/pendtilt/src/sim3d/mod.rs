//! The 3-D simulator core: a two-axis pendulum on a Cardan joint on a body in prescribed
//! 6-DOF motion (MODEL.md section 7).
//!
//! - [`params`]: the pendulum's constants, the normalised form (7.3), natural frequencies
//!   and damping ratios (7.2).
//! - [`dynamics`]: the exact joint equations (7.3) and the specific force at a body point
//!   (7.1).
//! - [`motion`]: prescribed roll, pitch, yaw and P1 acceleration with analytic derivatives
//!   (7.1, 7.7).
//! - [`simulator`]: RK4 on u = (a + roll, b + pitch), starting hanging still (7.3).
//! - [`sensors`]: encoders, 3-axis gyro and accelerometer (7.5); the log row of 7.6.
//!
//! ```
//! use pendtilt::sim3d::{motion::SineMotion, Pendulum3d, Simulator3d};
//! // A body at rest, rolled 10 deg and pitched -5 deg: the encoders read roll and pitch.
//! let (r, p) = (10f64.to_radians(), -5f64.to_radians());
//! let sim = Simulator3d::new(Pendulum3d::default(), SineMotion::at_rest(r, p, 0.3), 1000.0, 2, 0.1)
//!     .unwrap();
//! for row in sim {
//!     let [phi_x, phi_y] = row.encoders();
//!     assert!((phi_x - r).abs() < 1e-12 && (phi_y - p).abs() < 1e-12);
//! }
//! ```

pub mod dynamics;
pub mod motion;
pub mod params;
pub mod sensors;
pub mod simulator;

pub use dynamics::{specific_force_at, JointState};
pub use motion::{BodyKinematics, BodyMotion, SineMotion};
pub use params::{Normalised3d, Pendulum3d};
pub use sensors::{LogRow3d, SensorBank3d, Sensors3d};
pub use simulator::{Simulator3d, Truth3d};
