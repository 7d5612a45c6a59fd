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
//! - [`sensors`]: encoders, 3-axis gyro and accelerometer, speed (7.5); the log row of 7.6.
//! - [`timefn`]: the time-function components of 7.7 with exact derivatives.
//! - [`vehicle`]: the vehicle motion of 7.7 (travel, braking, turns, heave, engine,
//!   vibration) and the true forward speed.
//! - [`scenario`]: the named scenarios of 7.8, the rig file of 7.6 and the scenario file.
//! - [`output`]: the CSV log of 7.6 (read back by [`crate::io::Log3dReader`]).
//!
//! ```
//! use pendtilt::sim::spatial::Scenario3d;
//! // A named scenario (random parts from the seed), shortened; rows of truth and readings.
//! let mut s = Scenario3d::named("ride3d", 7).unwrap();
//! s.duration = 0.05;
//! let rows: Vec<_> = s.run(7).unwrap().collect();
//! assert_eq!(rows.len(), 50);
//! ```
//!
//! ```
//! use pendtilt::sim::spatial::{motion::SineMotion, Pendulum3d, Simulator3d};
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
pub mod output;
pub mod params;
pub mod scenario;
pub mod sensors;
pub mod simulator;
pub mod timefn;
pub mod vehicle;

pub use dynamics::{specific_force_at, JointState};
pub use motion::{BodyKinematics, BodyMotion, SineMotion};
pub use params::Pendulum3d;
pub use scenario::{Mounting, Rig3d, Run3d, Scenario3d, SCENARIO3D_NAMES};
pub use sensors::{LogRow3d, SensorBank3d, Sensors3d, SpeedFault};
pub use simulator::{Simulator3d, Truth3d};
pub use vehicle::{MotionSpec, VehicleMotion};
