//! The spatial estimators' output ([`Attitude`]) and their trait; the input,
//! [`SpatialSample`], is the model's ([`crate::model`]).
use super::attitude::up_from_roll_pitch;
pub use crate::model::SpatialSample;
use crate::{Estimator, Flags, Output, Real};

/// Roll and pitch of the body \[rad\] (ZYX, MODEL.md 7.1) with the sample's flags.
/// `NaN` only before the estimator has seen a usable input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attitude<T> {
    /// Roll \[rad\]: positive lowers the right side.
    pub roll: T,
    /// Pitch \[rad\]: positive lowers the nose.
    pub pitch: T,
    /// What happened on this sample.
    pub flags: Flags,
}

impl<T: Real> Attitude<T> {
    /// Before any usable input: roll and pitch `NaN`, no flags.
    pub fn unknown() -> Self {
        Self {
            roll: T::nan(),
            pitch: T::nan(),
            flags: Flags::empty(),
        }
    }

    /// The world's up direction in body axes, `u = R^T e_z` (MODEL.md 7.1).
    pub fn up(&self) -> [T; 3] {
        up_from_roll_pitch(self.roll, self.pitch)
    }
}

impl<T> Output for Attitude<T> {
    #[inline]
    fn flags(&self) -> Flags {
        self.flags
    }
}

/// An [`Estimator`] of the spatial model: [`SpatialSample`] in, [`Attitude`] out
/// (implemented for every such estimator; usable as `dyn SpatialEstimator<f64>`).
pub trait SpatialEstimator<T>: Estimator<Input = SpatialSample<T>, Output = Attitude<T>> {}

impl<T, E: Estimator<Input = SpatialSample<T>, Output = Attitude<T>> + ?Sized> SpatialEstimator<T>
    for E
{
}
