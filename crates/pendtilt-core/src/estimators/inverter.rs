//! The front end Algorithms 1-3 share: time-step checks, encoder unwrapping, the phi (and
//! gyro) differentiator, theta'' from the gyro, and hold-on-missing. Its output,
//! [`Kinematics`], is what every inversion equation ([`super::shared::Equation`]) reads.
use super::encoder::{is_reading, Unwrapper};
use super::shared::Equation;
use super::shared::FrontEndSettings;
use super::theta_dd::ThetaDd;
use crate::filters::diff::SmoothingDifferentiator;
use crate::{Estimate, Flags, Real, Sample, StepClock};

/// Which phi enters `theta = phi + asin(...)`.
///
/// The derivatives always come from the differentiator. With [`PhiSource::Raw`] the
/// measured phi is used: the pendulum's own (mechanically low-passed) reading plus a
/// low-passed correction, whose error for slow motion is second order in frequency
/// (`(1 - H_lp)(P - 1) theta`, both factors vanish at DC). With [`PhiSource::Filtered`]
/// the differentiator's low-passed phi is used: in the small-angle regime the estimate is
/// then exactly the body tilt through the low-pass (a clean delay), smoother but later.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "snake_case")
)]
pub enum PhiSource {
    /// The encoder reading as measured (default).
    #[default]
    Raw,
    /// The differentiator's low-passed phi.
    Filtered,
}

/// What the front end hands an inversion equation for one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics<T> {
    /// The phi that enters `theta = phi + asin(...)` ([`PhiSource`]) \[rad\].
    pub phi: T,
    /// phi' through the differentiator [rad/s].
    pub dphi: T,
    /// phi'' through the differentiator [rad/s^2].
    pub ddphi: T,
    /// Gyro rate (last good one if missing), theta' [rad/s].
    pub gyro: T,
    /// theta'' [rad/s^2] from the gyro source (0 without a gyro).
    pub theta_dd: T,
    /// The gyro through the phi low-pass (0 without a gyro) [rad/s].
    pub gyro_filtered: T,
    /// DC delay of the phi low-pass \[s\].
    pub delay: T,
    /// Time since the previous accepted sample \[s\] (0 on the first).
    pub dt: T,
    /// Flags of the gyro path alone (missing gyro sample, Eq (22) window filling): the
    /// algorithms that read the gyro add them, Algorithm 1 does not.
    pub gyro_flags: Flags,
}

/// State shared by Algorithms 1-3. `W` is the Eq (22) window capacity; `C` the number of
/// differentiated signals: 1 (phi) for Algorithm 1, 2 (phi and the gyro) with a gyro.
#[derive(Debug, Clone)]
pub(crate) struct Inverter<T: Real, const W: usize, const C: usize = 2> {
    phi_source: PhiSource,
    // Signal 0 is phi, signal 1 the gyro: one discretisation, one step check, and both
    // carry the same delay by construction.
    diff: SmoothingDifferentiator<T, C>,
    gyro: Option<ThetaDd<T, W>>,
    gyro_full_scale: Option<T>,
    gyro_seen: bool,
    clock: StepClock<T>,
    encoder: Unwrapper<T>,
    last_gyro: T,
    delay: T,
    last_theta: T,
}

impl<T: Real, const W: usize, const C: usize> Inverter<T, W, C> {
    /// The front end of `settings`; `with_gyro` false for Algorithm 1 (no theta'').
    pub fn new(settings: &FrontEndSettings<T>, with_gyro: bool) -> Self {
        let diff = &settings.differentiator;
        let d = SmoothingDifferentiator::new(diff.response, diff.cutoff_hz(&settings.params));
        Self {
            delay: diff.response.dc_delay(d.cutoff_rad_s()),
            phi_source: settings.phi,
            gyro: with_gyro.then(|| ThetaDd::new(settings.theta_dd)),
            gyro_full_scale: settings.gyro.checked_full_scale(),
            gyro_seen: false,
            diff: d,
            clock: StepClock::new(),
            encoder: Unwrapper::new(),
            last_gyro: T::zero(),
            last_theta: T::nan(),
        }
    }

    pub fn reset(&mut self) {
        self.diff.reset();
        if let Some(g) = self.gyro.as_mut() {
            g.reset();
        }
        self.gyro_seen = false;
        self.clock.restart();
        self.encoder = Unwrapper::new();
        self.last_gyro = T::zero();
        self.last_theta = T::nan();
    }

    /// Processes the sample; `Err(flags)` means "hold the previous estimate". The flags
    /// returned with the kinematics are those of the phi path ([`Kinematics::gyro_flags`]
    /// has the gyro's).
    #[inline]
    pub fn step(&mut self, s: &Sample<T>) -> Result<(Kinematics<T>, Flags), Flags> {
        let mut flags = Flags::empty();
        let step = self.clock.offer(s.dt)?;
        let first = step.is_none();
        let dt = step.unwrap_or(T::zero());
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
        self.clock.accept();
        // A missing gyro sample is held (zero-order hold) so the two signals stay in step.
        // A saturated one still enters as the rate (its sign is right and its size the
        // closest bound to the truth), but the derivative of its clipped plateau is not
        // theta'': theta'' is held instead.
        let reading = self.gyro.is_some() && s.gyro.is_finite();
        let saturated = reading && self.gyro_full_scale.is_some_and(|fs| s.gyro.abs() >= fs);
        let gyro_ok = reading && !saturated;
        if reading {
            self.last_gyro = s.gyro;
            if !self.gyro_seen && !first {
                // The gyro starts later than phi: start its signal at rest on it.
                self.diff.restart_signal(1, s.gyro);
            }
            self.gyro_seen = true;
        }
        let mut u = [self.last_gyro; C];
        u[0] = phi;
        if first {
            flags |= Flags::INITIALISING;
            self.diff.start_all(u);
        } else {
            self.diff.update_all(u, dt);
        }
        let d = self.diff.signal(0);
        let mut theta_dd = T::zero();
        let mut gyro_filtered = T::zero();
        let mut gyro_flags = Flags::empty();
        if let Some(g) = self.gyro.as_mut() {
            let gd = self.diff.signal(1);
            gyro_filtered = gd.value;
            g.advance(dt);
            if gyro_ok {
                let (v, init) = g.update(s.gyro, &gd);
                theta_dd = v;
                if init {
                    gyro_flags |= Flags::INITIALISING;
                }
            } else {
                theta_dd = g.last();
                gyro_flags |= if saturated {
                    Flags::SATURATED
                } else {
                    Flags::SAMPLE_MISSING
                };
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
                dt,
                gyro_flags,
            },
            flags,
        ))
    }

    /// One sample through the front end and `eq`: the estimate (held on a bad sample)
    /// and, when the sample was usable, its kinematics.
    #[inline]
    pub fn run(&mut self, s: &Sample<T>, eq: &Equation<T>) -> (Estimate<T>, Option<Kinematics<T>>) {
        match self.step(s) {
            Ok((k, phi_flags)) => {
                let (theta, flags) = eq.estimate(&k, phi_flags);
                self.last_theta = theta;
                (Estimate { theta, flags }, Some(k))
            }
            Err(flags) => (
                Estimate {
                    theta: self.last_theta,
                    flags,
                },
                None,
            ),
        }
    }
}
