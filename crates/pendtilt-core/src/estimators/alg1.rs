//! Algorithm 1, pendulum only: Eq (20), `theta = phi + asin(a phi' + b phi'')` (sign
//! corrected; see [`super::equations`]). It neglects the body's angular acceleration, so it
//! errs where theta'' is large (the paper's Fig 5).
use super::equations::Equation;
use super::front_end::{FrontEnd, FrontEndSettings};
use crate::{Estimate, Estimator, PendulumParams, Real, Sample};

/// Settings of [`Alg1`]: its front end, nothing of its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alg1Settings<T> {
    /// The pendulum, the differentiator and which phi enters the equation (the front
    /// end's theta'' and gyro settings are not read by Algorithm 1). Default:
    /// [`FrontEndSettings::default`].
    pub front_end: FrontEndSettings<T>,
}

impl<T: Real> Default for Alg1Settings<T> {
    fn default() -> Self {
        Self::from_params(PendulumParams::default())
    }
}

impl<T: Real> Alg1Settings<T> {
    /// Default settings for a pendulum with parameters `params`.
    pub fn from_params(params: PendulumParams<T>) -> Self {
        Self {
            front_end: FrontEndSettings::from_params(params),
        }
    }

    /// The equation these settings describe.
    pub fn equation(&self) -> Equation<T> {
        Equation::Alg1(self.front_end.params)
    }
}

/// Algorithm 1 as a streaming estimator.
#[derive(Debug, Clone)]
pub struct Alg1<T: Real> {
    settings: Alg1Settings<T>,
    inv: FrontEnd<T, 1, 1>,
}

impl<T: Real> Alg1<T> {
    /// A new estimator.
    pub fn new(settings: Alg1Settings<T>) -> Self {
        Self {
            inv: FrontEnd::new(&settings.front_end, false),
            settings,
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &Alg1Settings<T> {
        &self.settings
    }
}

impl<T: Real> Estimator for Alg1<T> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        self.inv.run(s, &self.settings.equation()).0
    }

    fn reset(&mut self) {
        self.inv.reset();
    }
}
