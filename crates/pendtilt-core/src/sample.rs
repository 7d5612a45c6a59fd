//! The streaming interface: an [`Estimator`] takes one input per sample and returns one
//! output, typed per model: the planar model's [`Sample`] in, [`Estimate`] (a tilt) out.
//! Time enters as a step `dt` (see [`crate::step`]), never as an absolute stamp, so an
//! `f32` build is as accurate after hours as after seconds.

use crate::{Flags, Real};

/// One row of planar sensor data, SI units (MODEL.md section 5). A sensor that is absent
/// or failed on this sample is `NaN`; each estimator reads only the fields it needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample<T> {
    /// Time since the previous sample \[s\], from a [`crate::StepGate`]: finite and
    /// positive; `NaN` marks a sample whose time stamp was refused (not finite, or not
    /// after the previous one). Ignored on an estimator's first sample.
    pub dt: T,
    /// Encoder: pendulum angle relative to the body, clockwise positive \[rad\].
    pub phi: T,
    /// Gyro: body rate about the tilt axis, CCW positive [rad/s].
    pub gyro: T,
    /// Accelerometer specific force along the body x axis [m/s^2].
    pub ax: T,
    /// Accelerometer specific force along the body y (up) axis [m/s^2].
    pub ay: T,
}

impl<T: Real> Sample<T> {
    /// A sample `dt` seconds after the previous one with every sensor missing; fill the
    /// fields you have.
    pub fn after(dt: T) -> Self {
        Self {
            dt,
            phi: T::nan(),
            gyro: T::nan(),
            ax: T::nan(),
            ay: T::nan(),
        }
    }

    /// True when `sensor` gave a finite reading on every axis; a sensor a planar log does
    /// not carry (no planar columns in [`crate::model::SENSORS`]) is never complete.
    pub fn complete(&self, sensor: crate::sensor::Sensor) -> bool {
        use crate::sensor::Sensor;
        // Not a `match`: a sensor added to the table for 3-D logs only needs no arm here.
        if sensor == Sensor::Encoder {
            self.phi.is_finite()
        } else if sensor == Sensor::Gyro {
            self.gyro.is_finite()
        } else if sensor == Sensor::Accel {
            self.ax.is_finite() && self.ay.is_finite()
        } else {
            false
        }
    }

    /// The same readings in another scalar type (`f64` logs into an `f32` estimator).
    pub fn cast<U: Real>(&self) -> Sample<U> {
        let c = |x: T| U::lit(x.to_f64());
        Sample {
            dt: c(self.dt),
            phi: c(self.phi),
            gyro: c(self.gyro),
            ax: c(self.ax),
            ay: c(self.ay),
        }
    }
}

/// One tilt estimate with its diagnostics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate<T> {
    /// Estimated body tilt theta \[rad\], CCW positive. `NaN` only before the estimator has
    /// seen any usable input (then [`Flags::SAMPLE_MISSING`] is set).
    pub theta: T,
    /// What happened on this sample.
    pub flags: Flags,
}

/// What every estimator output carries: the sample's [`Flags`].
pub trait Output {
    /// What happened on this sample.
    fn flags(&self) -> Flags;
}

impl<T> Output for Estimate<T> {
    #[inline]
    fn flags(&self) -> Flags {
        self.flags
    }
}

/// The shape every estimator shares: feed inputs in time order, get one output each.
/// The planar estimators take a [`Sample`] and return an [`Estimate`]
/// ([`PlanarEstimator`]); a spatial model brings its own input and output types.
pub trait Estimator {
    /// One sample of what the estimator reads.
    type Input;
    /// What it returns per sample.
    type Output: Output;
    /// Processes one input and returns the output for its time.
    fn update(&mut self, input: &Self::Input) -> Self::Output;
    /// Forgets all history, as if newly constructed with the same settings.
    fn reset(&mut self);
    /// Prepares to go on after a long gap in the input (a caller's restart, e.g. the std
    /// crate's bank after a sensor was missing for longer than its restart gap): forgets
    /// what the gap made stale but may keep what a gap cannot change (a sensor's bias,
    /// with its uncertainty grown over the gap). Default: [`Estimator::reset`].
    fn resume(&mut self) {
        self.reset();
    }
}

/// An [`Estimator`] of the planar model: [`Sample`] in, [`Estimate`] out (implemented for
/// every such estimator; usable as `dyn PlanarEstimator<f64>`).
pub trait PlanarEstimator<T>: Estimator<Input = Sample<T>, Output = Estimate<T>> {}

impl<T, E: Estimator<Input = Sample<T>, Output = Estimate<T>> + ?Sized> PlanarEstimator<T> for E {}
