//! Algorithm 3's estimation equation: Eq (30),
//! `theta = phi + asin(K phi' + L phi'' + M G_d) + N G_k` (sign corrected). With K = a,
//! L = b, M = -b, N = 0 it equals [`super::alg2`]. The gains can be changed between
//! samples with [`Alg3::set_gains`]: that is what live supervision (Eq 29) drives.
use super::equations::{Alg3Gains, Equation};
use super::front_end::{FrontEnd, FrontEndSettings};
use super::theta_dd::DEFAULT_WINDOW_CAPACITY;
use crate::{Estimate, Estimator, PendulumParams, Real, Sample};

/// Settings of [`Alg3`]: its front end and its gains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alg3Settings<T> {
    /// The pendulum (its natural frequency sets a relative differentiator cutoff), the
    /// differentiator, phi, G_d (theta'') and the gyro. Default:
    /// [`FrontEndSettings::default`].
    pub front_end: FrontEndSettings<T>,
    /// K, L, M, N. Default: those that make Eq (30) equal Eq (21) (K = a, L = b, M = -b,
    /// N = 0).
    pub gains: Alg3Gains<T>,
}

impl<T: Real> Default for Alg3Settings<T> {
    fn default() -> Self {
        Self::from_params(PendulumParams::default())
    }
}

impl<T: Real> Alg3Settings<T> {
    /// Default settings for a pendulum with parameters `params` (gains K=a, L=b, M=-b, N=0).
    pub fn from_params(params: PendulumParams<T>) -> Self {
        Self {
            front_end: FrontEndSettings::from_params(params),
            gains: Alg3Gains::from_params(&params),
        }
    }
}

/// Eq (30) as a streaming estimator; `W` bounds the Eq (22) window in samples.
#[derive(Debug, Clone)]
pub struct Alg3<T: Real, const W: usize = DEFAULT_WINDOW_CAPACITY> {
    settings: Alg3Settings<T>,
    inv: FrontEnd<T, W>,
}

/// The signals Eq (30) combines at one sample, for supervisors that refit K, L, M, N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alg3Terms<T> {
    /// phi as used in the equation \[rad\].
    pub phi: T,
    /// phi' [rad/s].
    pub dphi: T,
    /// phi'' [rad/s^2].
    pub ddphi: T,
    /// G_d, theta'' from the gyro [rad/s^2].
    pub gd: T,
    /// G_k, the gyro [rad/s].
    pub gk: T,
    /// The gyro through the phi low-pass (same delay as phi', phi'') [rad/s]: the
    /// supervisor's matched cost uses it instead of running a low-pass of its own.
    pub gk_filtered: T,
    /// Time since the previous accepted sample \[s\] (0 on the first).
    pub dt: T,
}

impl<T: Real, const W: usize> Alg3<T, W> {
    /// A new estimator.
    pub fn new(settings: Alg3Settings<T>) -> Self {
        Self {
            inv: FrontEnd::new(&settings.front_end, true),
            settings,
        }
    }

    /// The gains in use.
    pub fn gains(&self) -> Alg3Gains<T> {
        self.settings.gains
    }

    /// Replaces K, L, M, N from the next sample on. Non-finite gains are refused (returns
    /// false and keeps the old ones).
    pub fn set_gains(&mut self, gains: Alg3Gains<T>) -> bool {
        if gains.is_finite() {
            self.settings.gains = gains;
            true
        } else {
            false
        }
    }

    /// Like [`Estimator::update`], also returning the terms of Eq (30) (None when held).
    #[inline]
    pub fn update_with_terms(&mut self, s: &Sample<T>) -> (Estimate<T>, Option<Alg3Terms<T>>) {
        let (e, k) = self.inv.run(s, &Equation::Alg3(self.settings.gains));
        let terms = k.map(|k| Alg3Terms {
            phi: k.phi,
            dphi: k.dphi,
            ddphi: k.ddphi,
            gd: k.theta_dd,
            gk: k.gyro,
            gk_filtered: k.gyro_filtered,
            dt: k.dt,
        });
        (e, terms)
    }
}

impl<T: Real, const W: usize> Estimator for Alg3<T, W> {
    type Input = Sample<T>;
    type Output = Estimate<T>;

    #[inline]
    fn update(&mut self, s: &Sample<T>) -> Estimate<T> {
        self.inv.run(s, &Equation::Alg3(self.settings.gains)).0
    }

    fn reset(&mut self) {
        self.inv.reset();
    }
}
