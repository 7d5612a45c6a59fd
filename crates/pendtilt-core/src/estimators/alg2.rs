//! Algorithm 2, pendulum and gyro: Eq (21), `theta = phi + asin(a phi' + b (phi'' - G_d))`,
//! with theta'' = `G_d` from the gyro (Eq 22, or the matched differentiator; see
//! [`super::theta_dd`]). Optionally with the pivot-offset term the paper dropped
//! ([`Alg2Settings::pivot_offset`], output `alg2_offset`).
use super::equations::Equation;
use super::front_end::{FrontEnd, FrontEndSettings};
use super::theta_dd::DEFAULT_WINDOW_CAPACITY;
use crate::{Estimate, Estimator, PendulumParams, Real, Sample};

/// Settings of [`Alg2`]: its front end and its own two options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alg2Settings<T> {
    /// The pendulum, the differentiator, phi, theta'' and the gyro. Default:
    /// [`FrontEndSettings::default`].
    pub front_end: FrontEndSettings<T>,
    /// Add `c (theta'' cos phi - theta'^2 sin phi)`, c = l12 / g (MODEL.md section 3).
    /// Default false (the paper's Eq 21).
    pub pivot_offset: bool,
    /// Remove the differentiator's first-order delay from the correction (not in the
    /// paper): `theta -= tau (phi'_f - G_f)`, `tau` the low-pass's DC delay, `G_f` the gyro
    /// through the same low-pass. With the raw phi, Eq (21)'s correction arrives `tau`
    /// late, leaving an error `(1 - H)(phi - theta) ≈ tau (phi - theta)'`; the gyro
    /// measures theta' directly, so this term can be removed, leaving a third-order
    /// error. A constant gyro bias shifts the estimate by `tau * bias`. Default false
    /// (Eq 21 as printed; Algorithm 3's `N G_k` term plays this role when supervised).
    pub delay_compensation: bool,
}

impl<T: Real> Default for Alg2Settings<T> {
    fn default() -> Self {
        Self::from_params(PendulumParams::default())
    }
}

impl<T: Real> Alg2Settings<T> {
    /// The equation these settings describe.
    pub fn equation(&self) -> Equation<T> {
        Equation::Alg2 {
            params: self.front_end.params,
            pivot_offset: self.pivot_offset,
            delay_compensation: self.delay_compensation,
        }
    }

    /// Default settings for a pendulum with parameters `params`.
    pub fn from_params(params: PendulumParams<T>) -> Self {
        Self {
            front_end: FrontEndSettings::from_params(params),
            pivot_offset: false,
            delay_compensation: false,
        }
    }
}

/// Algorithm 2 as a streaming estimator; `W` bounds the Eq (22) window in samples.
#[derive(Debug, Clone)]
pub struct Alg2<T: Real, const W: usize = DEFAULT_WINDOW_CAPACITY> {
    settings: Alg2Settings<T>,
    inv: FrontEnd<T, W>,
}

impl<T: Real, const W: usize> Alg2<T, W> {
    /// A new estimator.
    pub fn new(settings: Alg2Settings<T>) -> Self {
        Self {
            inv: FrontEnd::new(&settings.front_end, true),
            settings,
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &Alg2Settings<T> {
        &self.settings
    }
}

impl<T: Real, const W: usize> Estimator for Alg2<T, W> {
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
