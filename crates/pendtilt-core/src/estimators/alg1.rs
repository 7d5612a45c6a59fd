//! Algorithm 1, pendulum only: Eq (20), `theta = phi + asin(a phi' + b phi'')` (sign
//! corrected; see [`super::equations`]). It neglects the body's angular acceleration, so it
//! errs where theta'' is large (the paper's Fig 5).
use super::inverter::{Inverter, PhiSource};
use super::shared::{Equation, FrontEndSettings};
use super::theta_dd::ThetaDdSource;
use crate::filters::diff::DiffSettings;
use crate::{Estimate, Estimator, PendulumParams, Real, Sample};

/// Settings of [`Alg1`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alg1Settings<T> {
    /// The pendulum's normalised parameters a, b. Default: the MODEL.md rig.
    pub params: PendulumParams<T>,
    /// Differentiator for phi' and phi''. Default: Butterworth at 1.3 f_n.
    pub differentiator: DiffSettings<T>,
    /// Which phi enters the equation. Default [`PhiSource::Raw`].
    pub phi: PhiSource,
}

impl<T: Real> Default for Alg1Settings<T> {
    fn default() -> Self {
        Self::from_params(PendulumParams::default())
    }
}

impl<T: Real> Alg1Settings<T> {
    /// The front end these settings describe (theta'' unused by Algorithm 1: default).
    pub fn front_end(&self) -> FrontEndSettings<T> {
        FrontEndSettings {
            params: self.params,
            differentiator: self.differentiator,
            phi: self.phi,
            theta_dd: ThetaDdSource::default(),
            gyro_full_scale: None,
        }
    }

    /// Default settings for a pendulum with parameters `params`.
    pub fn from_params(params: PendulumParams<T>) -> Self {
        Self {
            params,
            differentiator: DiffSettings::default(),
            phi: PhiSource::default(),
        }
    }
}

/// Algorithm 1 as a streaming estimator.
#[derive(Debug, Clone)]
pub struct Alg1<T: Real> {
    settings: Alg1Settings<T>,
    inv: Inverter<T, 1, 1>,
}

impl<T: Real> Alg1<T> {
    /// A new estimator.
    pub fn new(settings: Alg1Settings<T>) -> Self {
        Self {
            inv: Inverter::new(&settings.front_end(), false),
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
        self.inv.run(s, &Equation::Alg1(self.settings.params)).0
    }

    fn reset(&mut self) {
        self.inv.reset();
    }
}
