//! Online adaptation of the pendulum's forcing to the motion the log shows, shared by the
//! planar filter ([`crate::ekf`]) and the spatial one ([`crate::spatial::ekf`]): one set of
//! defaults for a standing scooter, a ride, a ship and a hand-held device.
//!
//! The forcing's density (the vibration's, [`crate::ekf::Environment::vibration_density`])
//! is the starting point; a factor on its variance follows the encoders' normalised
//! innovation squared (NIS: the squared innovation over the variance the filter predicts
//! for it, per axis, before the update), low-passed over [`Adaptation::window`]. While the
//! mean is above [`Adaptation::threshold`] the pendulum swings more than the model expects
//! and the factor grows (time constant [`Adaptation::rise`]); below
//! [`Adaptation::fall_below`] it swings less and the factor falls ([`Adaptation::fall`]).
//! This is covariance matching (Mehra 1972). The design and the measurements are in
//! docs/adaptation.md.
use crate::Real;

/// How long after a start \[s\] the adaptation waits: the start's own transient (the tilt
/// known to 2 deg) is the filter's, not the motion's. Both filters use it.
pub const SETTLE_SECONDS: f64 = 2.0;

/// Settings of the forcing's adaptation ([`ForcingAdaptation`]). The planar and the
/// spatial filter differ only in the values: [`Adaptation::planar`], [`Adaptation::spatial`]
/// (the [`Default`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Adaptation<T> {
    /// Adapt. Default true (`[ekf] adapt`, `[ekf3d] adapt` in a rig file).
    pub enabled: bool,
    /// Time constant \[s\] of the low-pass of the normalised innovations. Default 0.5 s:
    /// see [`defaults::WINDOW`].
    pub window: T,
    /// Time \[s\] for the factor to grow by e while the mean normalised innovation is e
    /// times [`Self::threshold`]. Default 0.2 s: see [`defaults::RISE`].
    pub rise: T,
    /// Time \[s\] for the factor to fall by e while the mean normalised innovation is
    /// [`Self::fall_below`] over e. Default: see [`defaults::SPATIAL_FALL`],
    /// [`defaults::PLANAR_FALL`].
    pub fall: T,
    /// The mean normalised innovation above which the factor grows. Default: see
    /// [`defaults::SPATIAL_THRESHOLD`], [`defaults::PLANAR_THRESHOLD`].
    pub threshold: T,
    /// The mean normalised innovation below which the factor falls (between it and
    /// [`Self::threshold`] the factor stays). Default: see
    /// [`defaults::SPATIAL_FALL_BELOW`], [`defaults::PLANAR_FALL_BELOW`].
    pub fall_below: T,
    /// Smallest factor. Default: see [`defaults::SPATIAL_MIN_FACTOR`],
    /// [`defaults::PLANAR_MIN_FACTOR`].
    pub min_factor: T,
    /// Largest factor. Default 1e5: see [`defaults::MAX_FACTOR`].
    pub max_factor: T,
}

/// The defaults of [`Adaptation`], each with why (docs/adaptation.md has the
/// measurements).
pub mod defaults {
    /// [`super::Adaptation::window`] \[s\]: several of the pendulum's periods (0.46 s at
    /// 2.19 Hz), so that one swing's innovations are averaged (docs/adaptation.md).
    pub const WINDOW: f64 = 0.5;
    /// [`super::Adaptation::rise`] \[s\]: a hand-held body's acceleration lasts about a
    /// second, and the factor must follow it within it (docs/adaptation.md).
    pub const RISE: f64 = 0.2;
    /// [`super::Adaptation::max_factor`]: the density times 316 (0.02 -> 6.3
    /// m/s^2/sqrt(Hz)), beyond any body the pendulum still follows (docs/adaptation.md).
    pub const MAX_FACTOR: f64 = 1e5;
    /// [`super::Adaptation::fall`] \[s\] of ekf3d: slow, so that the gravity reference
    /// is trusted over seconds once the motion calms (as in VQF; docs/real-motion.md).
    pub const SPATIAL_FALL: f64 = 5.0;
    /// [`super::Adaptation::threshold`] of ekf3d: keeps the simulated vehicles near the
    /// floor (docs/real-motion.md).
    pub const SPATIAL_THRESHOLD: f64 = 2.0;
    /// [`super::Adaptation::fall_below`] of ekf3d: a consistent filter's mean.
    pub const SPATIAL_FALL_BELOW: f64 = 1.0;
    /// [`super::Adaptation::min_factor`] of ekf3d: the forcing's density is a floor (its
    /// rigs are vehicles; docs/real-motion.md).
    pub const SPATIAL_MIN_FACTOR: f64 = 1.0;
    /// [`super::Adaptation::fall`] \[s\] of the planar ekf: a quiet rig far below the
    /// defaults' scooter reaches its level within a few tens of seconds
    /// (docs/adaptation.md).
    pub const PLANAR_FALL: f64 = 2.0;
    /// [`super::Adaptation::threshold`] of the planar ekf: the scooter ride's encoder NIS
    /// averages 2.2 (its forcing is not white), which must leave the factor where it is
    /// (docs/adaptation.md).
    pub const PLANAR_THRESHOLD: f64 = 4.0;
    /// [`super::Adaptation::fall_below`] of the planar ekf: just under the scooter's 2.2
    /// (docs/adaptation.md).
    pub const PLANAR_FALL_BELOW: f64 = 2.0;
    /// [`super::Adaptation::min_factor`] of the planar ekf: below one, so that the
    /// defaults also come down to a quiet rig (docs/adaptation.md).
    pub const PLANAR_MIN_FACTOR: f64 = 1e-3;
}

impl<T: Real> Adaptation<T> {
    /// The spatial filter's (ekf3d, ukf3d, imu3d) defaults.
    pub fn spatial() -> Self {
        use defaults as d;
        Self {
            enabled: true,
            window: T::lit(d::WINDOW),
            rise: T::lit(d::RISE),
            fall: T::lit(d::SPATIAL_FALL),
            threshold: T::lit(d::SPATIAL_THRESHOLD),
            fall_below: T::lit(d::SPATIAL_FALL_BELOW),
            min_factor: T::lit(d::SPATIAL_MIN_FACTOR),
            max_factor: T::lit(d::MAX_FACTOR),
        }
    }

    /// The planar filter's (ekf, ukf) defaults.
    pub fn planar() -> Self {
        use defaults as d;
        Self {
            enabled: true,
            window: T::lit(d::WINDOW),
            rise: T::lit(d::RISE),
            fall: T::lit(d::PLANAR_FALL),
            threshold: T::lit(d::PLANAR_THRESHOLD),
            fall_below: T::lit(d::PLANAR_FALL_BELOW),
            min_factor: T::lit(d::PLANAR_MIN_FACTOR),
            max_factor: T::lit(d::MAX_FACTOR),
        }
    }

    /// The same settings in another scalar type.
    pub fn cast<U: Real>(&self) -> Adaptation<U> {
        let c = |x: T| U::lit(x.to_f64());
        Adaptation {
            enabled: self.enabled,
            window: c(self.window),
            rise: c(self.rise),
            fall: c(self.fall),
            threshold: c(self.threshold),
            fall_below: c(self.fall_below),
            min_factor: c(self.min_factor),
            max_factor: c(self.max_factor),
        }
    }
}

impl<T: Real> Default for Adaptation<T> {
    /// [`Adaptation::spatial`].
    fn default() -> Self {
        Self::spatial()
    }
}

/// The state of the adaptation: the factor on the forcing's variance and the low-passed
/// normalised innovation. The filter decides when a reading counts (not while it settles
/// or bridges a gap) and applies the factor to its process noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForcingAdaptation<T> {
    factor: T,
    mean: Option<T>,
}

impl<T: Real> Default for ForcingAdaptation<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> ForcingAdaptation<T> {
    /// At the factor 1 (the settings' density), no innovation seen.
    pub fn new() -> Self {
        Self {
            factor: T::one(),
            mean: None,
        }
    }

    /// The factor on the forcing's variance.
    pub fn factor(&self) -> T {
        self.factor
    }

    /// The low-passed normalised innovation squared, once one was seen.
    pub fn mean(&self) -> Option<T> {
        self.mean
    }

    /// Back to [`Self::new`].
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// One step on a reading's normalised innovation squared `nis` (per axis, before the
    /// update), `dt` \[s\] after the last reading that counted: the low-pass moves the log
    /// of the factor by `ln(mean / threshold) dt / rise` above the threshold,
    /// `ln(mean / fall_below) dt / fall` below `fall_below`, at most by one per step.
    /// Nothing if the settings are off or `nis`, `dt` are not usable.
    pub fn step(&mut self, a: &Adaptation<T>, nis: T, dt: T) {
        if !(a.enabled && nis.is_finite() && dt > T::zero()) {
            return;
        }
        let k = (dt / a.window).min(T::one());
        let m = match self.mean {
            Some(m) => m + k * (nis - m),
            None => nis,
        };
        self.mean = Some(m);
        let step = if m > a.threshold {
            (m / a.threshold).ln() * dt / a.rise
        } else if m < a.fall_below {
            (m.max(T::lit(1e-6)) / a.fall_below).ln() * dt / a.fall
        } else {
            T::zero()
        };
        let step = step.max(T::lit(-1.0)).min(T::one());
        self.factor = (self.factor.ln() + step)
            .exp()
            .max(a.min_factor)
            .min(a.max_factor);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Large innovations raise the factor at the rise's pace, small ones lower it to the
    /// planar floor; the spatial settings never go below one; off, nothing moves.
    #[test]
    fn the_factor_follows_the_mean_innovation() {
        let p = Adaptation::<f64>::planar();
        let mut f = ForcingAdaptation::new();
        for _ in 0..1000 {
            f.step(&p, 4.0 * core::f64::consts::E, 1e-3);
        }
        // 1 s at ln(e) / 0.2 s: e^5, less the window's first steps.
        assert!(f.factor() > 100.0 && f.factor() < 150.0, "{}", f.factor());
        for _ in 0..100_000 {
            f.step(&p, 0.5, 1e-3);
        }
        assert_eq!(f.factor(), p.min_factor);
        let s = Adaptation::<f64>::spatial();
        let mut g = ForcingAdaptation::new();
        for _ in 0..10_000 {
            g.step(&s, 0.5, 1e-3);
        }
        assert_eq!(g.factor(), 1.0);
        let off = Adaptation {
            enabled: false,
            ..p
        };
        let mut h = ForcingAdaptation::new();
        h.step(&off, 100.0, 1.0);
        assert_eq!(h, ForcingAdaptation::new());
    }
}
