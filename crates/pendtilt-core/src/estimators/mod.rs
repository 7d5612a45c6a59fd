//! The paper's estimators, one per module, all implementing [`crate::Estimator`]:
//! a settings struct with documented defaults, `new(settings)`, `update(sample)` and
//! per-sample [`crate::Flags`]. As VQF does, each keeps its settings, the coefficients
//! it derives from them once and its running state apart: `reset` and `resume` touch the
//! state alone.
//!
//! | module | output | equation | inputs |
//! |---|---|---|---|
//! | [`accel`] | `accel` | Eq (1) | ax, ay |
//! | [`pendulum`] | `pendulum` | theta = phi | phi |
//! | [`alg1`] | `alg1` | Eq (20), sign corrected | phi |
//! | [`alg2`] | `alg2`, `alg2_offset` | Eqs (21)-(22), sign corrected | phi, gyro |
//! | [`alg3`] | `alg3` | Eq (30), sign corrected | phi, gyro |
//!
//! The equations themselves, free of any state, are in [`equations`] so that they can be
//! checked against hand computations and reused by fitting code. Algorithms 1-3 are each
//! "front end + equation" ([`front_end`]), and one front end can run several equations.
//!
//! Common behaviour: a sample whose time does not increase is flagged
//! [`crate::Flags::BAD_TIME_STEP`] and the previous estimate is returned; a sample whose
//! required input is missing (`NaN`) is flagged [`crate::Flags::SAMPLE_MISSING`] and the
//! previous estimate is held; the next good sample resumes, its time step spanning the gap.
pub mod accel;
pub mod alg1;
pub mod alg2;
pub mod alg3;
pub mod clip_gate;
pub mod complementary;
pub(crate) mod encoder;
pub mod equations;
pub mod front_end;
pub mod gap_fit;
pub mod input_hold;
pub mod pendulum;
pub mod theta_dd;

pub use encoder::PHI_LIMIT;
pub use front_end::PhiSource;
