//! Rig parameters: the pendulum (physical values and the normalised a, b, c the estimators
//! use) and the sensors' limits ([`GyroSettings`]), each defined once and composed into
//! the settings of every estimator that needs it.

use crate::Real;

/// Standard gravity [m/s^2], the default of MODEL.md section 5.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The pendulum as built (MODEL.md sections 1-2). SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalParams<T> {
    /// Pendulum mass m_p \[kg\].
    pub mass: T,
    /// Pivot-to-CG distance l_p \[m\].
    pub length: T,
    /// Moment of inertia about the pivot I_p [kg m^2] (includes m_p l_p^2).
    pub inertia: T,
    /// Viscous friction at the pivot C [N m s/rad].
    pub damping: T,
    /// Distance l12 from the body's rotation axis P1 to the pendulum pivot P2 \[m\].
    pub pivot_offset: T,
    /// Gravity g [m/s^2].
    pub gravity: T,
}

impl<T: Real> Default for PhysicalParams<T> {
    /// The values of MODEL.md section 5: a 50 g, 5 cm pendulum, natural frequency 2.19 Hz,
    /// damping ratio 0.30.
    fn default() -> Self {
        Self {
            mass: T::lit(0.05),
            length: T::lit(0.05),
            inertia: T::lit(1.3e-4),
            damping: T::lit(1.07e-3),
            pivot_offset: T::lit(0.0),
            gravity: T::lit(STANDARD_GRAVITY),
        }
    }
}

impl<T: Real> PhysicalParams<T> {
    /// m_p g l_p, the pendulum's gravity stiffness [N m / rad].
    pub fn stiffness(&self) -> T {
        self.mass * self.gravity * self.length
    }

    /// The normalised parameters (section 3): a = C / (m g l), b = I / (m g l), c = l12 / g.
    pub fn normalised(&self) -> PendulumParams<T> {
        let k = self.stiffness();
        PendulumParams {
            a: self.damping / k,
            b: self.inertia / k,
            c: self.pivot_offset / self.gravity,
        }
    }
}

/// The normalised parameters of the paper's estimators (MODEL.md section 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PendulumParams<T> {
    /// a = C / (m_p g l_p) \[s\]: friction over gravity stiffness.
    pub a: T,
    /// b = I_p / (m_p g l_p) [s^2]: inertia over gravity stiffness, 1 / w_n^2.
    pub b: T,
    /// c = l12 / g [s^2]: pivot offset (0 for the paper's Eq 18).
    pub c: T,
}

impl<T: Real> Default for PendulumParams<T> {
    /// [`PhysicalParams::default`] normalised: a = 0.04364 s, b = 5.302e-3 s^2, c = 0.
    fn default() -> Self {
        PhysicalParams::default().normalised()
    }
}

impl<T: Real> PendulumParams<T> {
    /// Small-angle natural frequency w_n = 1 / sqrt(b) [rad/s].
    pub fn natural_frequency(&self) -> T {
        T::one() / self.b.sqrt()
    }

    /// Natural frequency in Hz.
    pub fn natural_frequency_hz(&self) -> T {
        self.natural_frequency() / T::two_pi()
    }

    /// Damping ratio zeta = C / (2 sqrt(I m g l)) = a / (2 sqrt(b)).
    pub fn damping_ratio(&self) -> T {
        self.a / (T::lit(2.0) * self.b.sqrt())
    }

    /// True when a >= 0, b > 0, c finite: the only values the pendulum model admits.
    pub fn is_physical(&self) -> bool {
        self.a.is_finite()
            && self.b.is_finite()
            && self.c.is_finite()
            && self.a >= T::zero()
            && self.b > T::zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_rig_matches_hand_computation() {
        let p = PendulumParams::<f64>::default();
        // m g l = 0.05 * 9.80665 * 0.05 = 0.02451663
        assert!((p.a - 1.07e-3 / 0.024_516_625).abs() < 1e-12);
        assert!((p.b - 1.3e-4 / 0.024_516_625).abs() < 1e-12);
        // w_n = sqrt(0.024516625 / 1.3e-4) = 13.7327 rad/s = 2.1856 Hz
        assert!((p.natural_frequency() - 13.732_79).abs() < 1e-4);
        assert!((p.natural_frequency_hz() - 2.185_64).abs() < 1e-4);
        // zeta = 1.07e-3 / (2 sqrt(1.3e-4 * 0.024516625)) = 0.29966
        assert!((p.damping_ratio() - 0.299_66).abs() < 1e-4);
    }

    #[test]
    fn physicality() {
        let mut p = PendulumParams::<f64>::default();
        assert!(p.is_physical());
        p.b = 0.0;
        assert!(!p.is_physical());
        p.b = 1e-3;
        p.a = -1.0;
        assert!(!p.is_physical());
    }
}

/// The rate gyro as the estimators need to know it (the rig file's `[gyro]` table). One
/// definition, composed into the settings of every estimator that reads the gyro
/// ([`crate::estimators::front_end::FrontEndSettings::gyro`],
/// [`crate::kalman::KalmanSettings::gyro`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields, default)
)]
pub struct GyroSettings<T> {
    /// Full scale [rad/s]: a reading at or beyond it is flagged
    /// [`Flags::SATURATED`](crate::Flags::SATURATED). It is still used as the rate (its
    /// sign is right, its size the closest bound to the truth), but not as if it were
    /// exact: Algorithms 2 and 3 hold theta'' at its last good value rather than read
    /// the clipped plateau as zero, and the Kalman filters grow the angle variance by
    /// `(full_scale dt)^2` so that their measurement carries the angle through.
    /// Default `None` (unknown: no check; a value that is not positive is no check too).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub full_scale: Option<T>,
}

impl<T> Default for GyroSettings<T> {
    fn default() -> Self {
        Self { full_scale: None }
    }
}

impl<T: Real> GyroSettings<T> {
    /// The full scale if it is a usable bound (positive), for the per-sample check.
    pub fn checked_full_scale(&self) -> Option<T> {
        self.full_scale.filter(|f| crate::real::is_positive(*f))
    }
}
