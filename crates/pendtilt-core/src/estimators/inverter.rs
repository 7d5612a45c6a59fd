//! The machinery Algorithms 1-3 share: time-step checks, encoder unwrapping, the phi
//! differentiator, theta'' from the gyro, and hold-on-missing.
use super::encoder::{is_reading, wrap_angle, Unwrapper};
use super::theta_dd::{ThetaDd, ThetaDdSource};
use crate::filters::diff::{DiffSettings, SmoothingDifferentiator};
use crate::{Flags, PendulumParams, Real, Sample};

/// Which phi enters `theta = phi + asin(...)`.
///
/// The derivatives always come from the differentiator. With [`PhiSource::Raw`] the
/// measured phi is used: the pendulum's own (mechanically low-passed) reading plus a
/// low-passed correction, whose error for slow motion is second order in frequency
/// (`(1 - H_lp)(P - 1) theta`, both factors vanish at DC). With [`PhiSource::Filtered`]
/// the differentiator's low-passed phi is used: in the small-angle regime the estimate is
/// then exactly the body tilt through the low-pass (a clean delay), smoother but later.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PhiSource {
    /// The encoder reading as measured (default).
    #[default]
    Raw,
    /// The differentiator's low-passed phi.
    Filtered,
}

/// What the inverter hands an algorithm for one sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Kinematics<T> {
    pub phi: T,
    pub dphi: T,
    pub ddphi: T,
    /// Gyro rate (last good one if missing), theta' [rad/s].
    pub gyro: T,
    /// theta'' [rad/s^2] from the gyro source (0 without a gyro).
    pub theta_dd: T,
    /// The gyro through the phi low-pass (0 without a gyro) [rad/s].
    pub gyro_filtered: T,
    /// DC delay of the phi low-pass [s].
    pub delay: T,
}

/// State shared by Algorithms 1-3. `W` is the Eq (22) window capacity.
#[derive(Debug, Clone)]
pub(crate) struct Inverter<T: Real, const W: usize> {
    phi_source: PhiSource,
    phi_diff: SmoothingDifferentiator<T>,
    gyro: Option<ThetaDd<T, W>>,
    t_prev: Option<T>,
    encoder: Unwrapper<T>,
    last_gyro: T,
    delay: T,
    pub last_theta: T,
}

impl<T: Real, const W: usize> Inverter<T, W> {
    pub fn new(
        params: &PendulumParams<T>,
        diff: &DiffSettings<T>,
        phi_source: PhiSource,
        theta_dd: Option<ThetaDdSource<T>>,
    ) -> Self {
        let d = SmoothingDifferentiator::new(diff.response, diff.cutoff_hz(params));
        Self {
            delay: diff.response.dc_delay(d.cutoff_rad_s()),
            phi_source,
            gyro: theta_dd.map(|s| ThetaDd::new(s, d.clone())),
            phi_diff: d,
            t_prev: None,
            encoder: Unwrapper::new(),
            last_gyro: T::zero(),
            last_theta: T::nan(),
        }
    }

    pub fn reset(&mut self) {
        self.phi_diff.reset();
        if let Some(g) = self.gyro.as_mut() {
            g.reset();
        }
        self.t_prev = None;
        self.encoder = Unwrapper::new();
        self.last_gyro = T::zero();
        self.last_theta = T::nan();
    }

    /// Processes the sample; `Err(flags)` means "hold the previous estimate".
    #[inline]
    pub fn step(&mut self, s: &Sample<T>) -> Result<(Kinematics<T>, Flags), Flags> {
        let mut flags = Flags::empty();
        let first = self.t_prev.is_none();
        if !s.t.is_finite() {
            return Err(Flags::BAD_TIME_STEP);
        }
        let dt = match self.t_prev {
            Some(tp) => {
                let dt = s.t - tp;
                if !crate::real::is_positive(dt) {
                    return Err(Flags::BAD_TIME_STEP);
                }
                dt
            }
            None => T::zero(),
        };
        if !is_reading(s.phi) {
            let f = Flags::SAMPLE_MISSING
                | if first {
                    Flags::INITIALISING
                } else {
                    Flags::empty()
                };
            return Err(f);
        }
        let (phi, wrapped) = self.encoder.unwrap(s.phi);
        if wrapped {
            flags |= Flags::ENCODER_WRAPPED;
        }
        self.t_prev = Some(s.t);
        let d = if first {
            flags |= Flags::INITIALISING;
            self.phi_diff.update(phi, T::one())
        } else {
            self.phi_diff.update_at(phi, dt, s.t)
        };
        let mut theta_dd = T::zero();
        let mut gyro_filtered = T::zero();
        if let Some(g) = self.gyro.as_mut() {
            if s.gyro.is_finite() {
                self.last_gyro = s.gyro;
                let (v, init) = g.update(s.t, s.gyro);
                theta_dd = v;
                gyro_filtered = g.filtered_rate();
                if init {
                    flags |= Flags::INITIALISING;
                }
            } else {
                theta_dd = g.last();
                gyro_filtered = g.filtered_rate();
                flags |= Flags::SAMPLE_MISSING;
            }
        }
        let phi_used = match self.phi_source {
            PhiSource::Raw => phi,
            PhiSource::Filtered => d.value,
        };
        Ok((
            Kinematics {
                phi: phi_used,
                dphi: d.d1,
                ddphi: d.d2,
                gyro: self.last_gyro,
                theta_dd,
                gyro_filtered,
                delay: self.delay,
            },
            flags,
        ))
    }

    /// Wraps an unwrapped estimate back into (-pi, pi] and remembers it.
    #[inline]
    pub fn finish(&mut self, theta: T) -> T {
        let th = wrap_angle(theta);
        self.last_theta = th;
        th
    }
}
