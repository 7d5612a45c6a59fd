//! The front end Algorithms 1-3 share, and several inversion equations on one front end.
//!
//! The front end ([`FrontEndSettings`]; the crate-internal `FrontEnd`) does the time-step
//! checks, encoder unwrapping, the phi (and gyro) differentiator, theta'' from the gyro
//! and hold-on-missing. Its output, [`Kinematics`], is what every inversion equation
//! ([`Equation`]) reads. Every algorithm is "front end + equation", and the front end is
//! the expensive part: [`SharedFrontEnd`] runs it once per sample and evaluates several
//! equations on its output. Running Algorithms 1, 2 (with its variants) and 3 side by
//! side, as `pendtilt estimate` does, then costs one front end and a few asin: each
//! output is the same number the stand-alone estimator gives (test
//! `shared_outputs_equal_the_stand_alone_estimators`).
use super::encoder::{is_reading, Unwrapper};
use super::equations::{Equation, Kinematics};
use super::theta_dd::{ThetaDd, ThetaDdSource, DEFAULT_WINDOW_CAPACITY};
use crate::filters::diff::{DiffSettings, SmoothingDifferentiator};
use crate::params::GyroSettings;
use crate::{Estimate, Flags, PendulumParams, Real, Sample, StepClock};

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

/// Settings of the front end Algorithms 1-3 share, each defined here once: the
/// algorithms' settings hold one ([`Alg1Settings::front_end`],
/// [`Alg2Settings::front_end`], [`Alg3Settings::front_end`]) beside their own.
///
/// [`Alg1Settings::front_end`]: super::alg1::Alg1Settings::front_end
/// [`Alg2Settings::front_end`]: super::alg2::Alg2Settings::front_end
/// [`Alg3Settings::front_end`]: super::alg3::Alg3Settings::front_end
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontEndSettings<T> {
    /// The pendulum's normalised parameters a, b (and c, for Algorithm 2's pivot-offset
    /// term). Its natural frequency sets a [`Cutoff::TimesNatural`] cutoff. Default: the
    /// MODEL.md rig ([`PendulumParams::default`]).
    ///
    /// [`Cutoff::TimesNatural`]: crate::filters::diff::Cutoff::TimesNatural
    pub params: PendulumParams<T>,
    /// The differentiator of phi (and of the gyro, for a matched theta''). Default:
    /// Butterworth at 1.3 f_n ([`DiffSettings::default`]).
    pub differentiator: DiffSettings<T>,
    /// Which phi enters the equation. Default [`PhiSource::Raw`].
    pub phi: PhiSource,
    /// Where theta'' (G_d) comes from. Default [`ThetaDdSource::Matched`]. Not read by
    /// Algorithm 1.
    pub theta_dd: ThetaDdSource<T>,
    /// The gyro (its full scale). Default: unknown full scale. Not read by Algorithm 1.
    pub gyro: GyroSettings<T>,
}

impl<T: Real> Default for FrontEndSettings<T> {
    fn default() -> Self {
        Self::from_params(PendulumParams::default())
    }
}

impl<T: Real> FrontEndSettings<T> {
    /// Default settings for a pendulum with parameters `params`.
    pub fn from_params(params: PendulumParams<T>) -> Self {
        Self {
            params,
            differentiator: DiffSettings::default(),
            phi: PhiSource::default(),
            theta_dd: ThetaDdSource::default(),
            gyro: GyroSettings::default(),
        }
    }
}

/// The front end itself, one per estimator (or per [`SharedFrontEnd`]). `W` is the Eq (22) window capacity; `C` the number of
/// differentiated signals: 1 (phi) for Algorithm 1, 2 (phi and the gyro) with a gyro.
#[derive(Debug, Clone)]
pub(crate) struct FrontEnd<T: Real, const W: usize, const C: usize = 2> {
    coeffs: Coefficients<T>,
    state: State<T, W, C>,
}

/// What the settings give once (the gyro's full scale can be replaced later, for a clip
/// found in the log): kept apart so that `reset` cannot touch them.
#[derive(Debug, Clone, Copy)]
struct Coefficients<T> {
    phi_source: PhiSource,
    /// The differentiator's DC delay \[s\], for Algorithm 2's delay compensation.
    delay: T,
    gyro_full_scale: Option<T>,
}

/// Everything a run changes: what `reset` starts again.
#[derive(Debug, Clone)]
struct State<T: Real, const W: usize, const C: usize> {
    // Signal 0 is phi, signal 1 the gyro: one discretisation, one step check, and both
    // carry the same delay by construction.
    diff: SmoothingDifferentiator<T, C>,
    gyro: Option<ThetaDd<T, W>>,
    gyro_seen: bool,
    clock: StepClock<T>,
    encoder: Unwrapper<T>,
    last_gyro: T,
    last_theta: T,
}

impl<T: Real, const W: usize, const C: usize> FrontEnd<T, W, C> {
    /// The front end of `settings`; `with_gyro` false for Algorithm 1 (no theta'').
    pub fn new(settings: &FrontEndSettings<T>, with_gyro: bool) -> Self {
        let diff = &settings.differentiator;
        let d = SmoothingDifferentiator::new(diff.response, diff.cutoff_hz(&settings.params));
        Self {
            coeffs: Coefficients {
                delay: diff.response.dc_delay(d.cutoff_rad_s()),
                phi_source: settings.phi,
                gyro_full_scale: settings.gyro.checked_full_scale(),
            },
            state: State {
                gyro: with_gyro.then(|| ThetaDd::new(settings.theta_dd)),
                gyro_seen: false,
                diff: d,
                clock: StepClock::new(),
                encoder: Unwrapper::new(),
                last_gyro: T::zero(),
                last_theta: T::nan(),
            },
        }
    }

    /// Replaces the gyro's full scale (`None`: unknown), from the next sample on.
    pub fn set_gyro_full_scale(&mut self, full_scale: Option<T>) {
        self.coeffs.gyro_full_scale = full_scale.filter(|f| crate::real::is_positive(*f));
    }

    /// Back to the state before the first sample; the differentiator keeps its design.
    pub fn reset(&mut self) {
        let st = &mut self.state;
        st.diff.reset();
        if let Some(g) = st.gyro.as_mut() {
            g.reset();
        }
        st.gyro_seen = false;
        st.clock.restart();
        st.encoder = Unwrapper::new();
        st.last_gyro = T::zero();
        st.last_theta = T::nan();
    }

    /// Processes the sample; `Err(flags)` means "hold the previous estimate". The flags
    /// returned with the kinematics are those of the phi path ([`Kinematics::gyro_flags`]
    /// has the gyro's).
    #[inline]
    pub fn step(&mut self, s: &Sample<T>) -> Result<(Kinematics<T>, Flags), Flags> {
        let (phi, dt, flags) = self.accept_phi(s)?;
        let first = flags.contains(Flags::INITIALISING);
        let gyro = self.read_gyro(s.gyro, first);
        let mut u = [self.state.last_gyro; C];
        u[0] = phi;
        if first {
            self.state.diff.start_all(u);
        } else {
            self.state.diff.update_all(u, dt);
        }
        // Read phi's derivatives before the gyro's step, right after the update: read
        // after it, the compiler re-loaded the state just stored, a store-forwarding stall
        // that made alg1 (f64) 1.4x slower (docs/performance.md).
        let d = self.state.diff.signal(0);
        let (theta_dd, gyro_filtered, gyro_flags) = self.theta_dd(s.gyro, gyro, dt);
        let phi_used = match self.coeffs.phi_source {
            PhiSource::Raw => phi,
            PhiSource::Filtered => d.value,
        };
        Ok((
            Kinematics {
                phi: phi_used,
                dphi: d.d1,
                ddphi: d.d2,
                gyro: self.state.last_gyro,
                theta_dd,
                gyro_filtered,
                delay: self.coeffs.delay,
                dt,
                gyro_flags,
            },
            flags,
        ))
    }

    /// The time step and the unwrapped phi of a usable sample (the clock then accepts
    /// it), with the phi path's flags (`INITIALISING` on the first sample); `Err` with the
    /// flags of a sample to hold on.
    #[inline]
    fn accept_phi(&mut self, s: &Sample<T>) -> Result<(T, T, Flags), Flags> {
        let step = self.state.clock.offer(s.dt)?;
        let first = if step.is_none() {
            Flags::INITIALISING
        } else {
            Flags::empty()
        };
        if !is_reading(s.phi) {
            return Err(Flags::SAMPLE_MISSING | first);
        }
        let (phi, wrapped) = self.state.encoder.unwrap(s.phi);
        self.state.clock.accept();
        let mut flags = first;
        if wrapped {
            flags |= Flags::ENCODER_WRAPPED;
        }
        Ok((phi, step.unwrap_or(T::zero()), flags))
    }

    /// Records a gyro reading and says what it is. A missing one is held (zero-order hold)
    /// so phi and the gyro stay in step. A saturated one still enters as the rate (its sign
    /// is right and its size the closest bound to the truth), but the derivative of its
    /// clipped plateau is not theta'': theta'' is held instead.
    #[inline]
    fn read_gyro(&mut self, gyro: T, first: bool) -> GyroReading {
        let reading = self.state.gyro.is_some() && gyro.is_finite();
        if !reading {
            return GyroReading::Missing;
        }
        self.state.last_gyro = gyro;
        if !self.state.gyro_seen && !first {
            // The gyro starts later than phi: start its signal at rest on it.
            self.state.diff.restart_signal(1, gyro);
        }
        self.state.gyro_seen = true;
        if self
            .coeffs
            .gyro_full_scale
            .is_some_and(|fs| gyro.abs() >= fs)
        {
            GyroReading::Saturated
        } else {
            GyroReading::Good
        }
    }

    /// theta'', the gyro through the phi low-pass, and the gyro path's flags (all zero and
    /// empty without a gyro), once the differentiator has taken this sample.
    #[inline]
    fn theta_dd(&mut self, gyro: T, reading: GyroReading, dt: T) -> (T, T, Flags) {
        let Some(g) = self.state.gyro.as_mut() else {
            return (T::zero(), T::zero(), Flags::empty());
        };
        let gd = self.state.diff.signal(1);
        g.advance(dt);
        match reading {
            GyroReading::Good => {
                let (v, init) = g.update(gyro, &gd);
                let flags = if init {
                    Flags::INITIALISING
                } else {
                    Flags::empty()
                };
                (v, gd.value, flags)
            }
            GyroReading::Saturated => (g.last(), gd.value, Flags::SATURATED),
            GyroReading::Missing => (g.last(), gd.value, Flags::SAMPLE_MISSING),
        }
    }

    /// One sample through the front end and `eq`: the estimate (held on a bad sample)
    /// and, when the sample was usable, its kinematics.
    #[inline]
    pub fn run(&mut self, s: &Sample<T>, eq: &Equation<T>) -> (Estimate<T>, Option<Kinematics<T>>) {
        match self.step(s) {
            Ok((k, phi_flags)) => {
                let (theta, flags) = eq.estimate(&k, phi_flags);
                self.state.last_theta = theta;
                (Estimate { theta, flags }, Some(k))
            }
            Err(flags) => (
                Estimate {
                    theta: self.state.last_theta,
                    flags,
                },
                None,
            ),
        }
    }
}

/// What one sample's gyro cell is, for the front end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum GyroReading {
    /// A finite reading below the full scale.
    Good,
    /// A finite reading at or beyond the full scale: the rate, but not its derivative.
    Saturated,
    /// Not a number (or no gyro in this front end).
    Missing,
}

/// The most equations one [`SharedFrontEnd`] evaluates.
pub const MAX_EQUATIONS: usize = 8;

/// Several inversion equations on one front end; no allocation (at most
/// [`MAX_EQUATIONS`]). Each output holds its own previous estimate on a bad sample, like
/// the stand-alone estimators.
#[derive(Debug, Clone)]
pub struct SharedFrontEnd<T: Real, const W: usize = DEFAULT_WINDOW_CAPACITY> {
    settings: FrontEndSettings<T>,
    front: FrontEnd<T, W, 2>,
    equations: [Equation<T>; MAX_EQUATIONS],
    last: [T; MAX_EQUATIONS],
    len: usize,
}

impl<T: Real, const W: usize> SharedFrontEnd<T, W> {
    /// The front end with `equations` (in output order). `None` if there are more than
    /// [`MAX_EQUATIONS`].
    pub fn new(settings: &FrontEndSettings<T>, equations: &[Equation<T>]) -> Option<Self> {
        if equations.len() > MAX_EQUATIONS {
            return None;
        }
        let mut eqs = [Equation::Alg1(settings.params); MAX_EQUATIONS];
        eqs[..equations.len()].copy_from_slice(equations);
        Some(Self {
            settings: *settings,
            front: FrontEnd::new(settings, true),
            equations: eqs,
            last: [T::nan(); MAX_EQUATIONS],
            len: equations.len(),
        })
    }

    /// The equations, in output order.
    pub fn equations(&self) -> &[Equation<T>] {
        &self.equations[..self.len]
    }

    /// The front end's settings.
    pub fn settings(&self) -> &FrontEndSettings<T> {
        &self.settings
    }

    /// Adds an equation (its output comes after the others); false when full. Add every
    /// equation before the first update: a later one starts with the next sample.
    pub fn push(&mut self, equation: Equation<T>) -> bool {
        if self.len == MAX_EQUATIONS {
            return false;
        }
        self.equations[self.len] = equation;
        self.len += 1;
        true
    }

    /// Processes one sample and writes one estimate per equation into `out` (as many as
    /// fit: `out` should hold [`Self::equations`]`.len()`).
    #[inline]
    pub fn update(&mut self, s: &Sample<T>, out: &mut [Estimate<T>]) {
        let n = self.len.min(out.len());
        match self.front.step(s) {
            Ok((k, phi_flags)) => {
                for ((eq, last), o) in self.equations[..n]
                    .iter()
                    .zip(&mut self.last[..n])
                    .zip(out.iter_mut())
                {
                    let (theta, flags) = eq.estimate(&k, phi_flags);
                    *last = theta;
                    *o = Estimate { theta, flags };
                }
            }
            Err(flags) => {
                for (last, o) in self.last[..n].iter().zip(out.iter_mut()) {
                    *o = Estimate {
                        theta: *last,
                        flags,
                    };
                }
            }
        }
    }

    /// Replaces the gyro's full scale (`None`: unknown), from the next sample on: a reading
    /// at or beyond it is saturated (theta'' held, [`Flags::SATURATED`]). For a clip found
    /// in the log itself rather than given by the rig.
    pub fn set_gyro_full_scale(&mut self, full_scale: Option<T>) {
        self.front.set_gyro_full_scale(full_scale);
    }

    /// Forgets all state.
    pub fn reset(&mut self) {
        self.front.reset();
        self.last = [T::nan(); MAX_EQUATIONS];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimators::alg1::{Alg1, Alg1Settings};
    use crate::estimators::alg2::{Alg2, Alg2Settings};
    use crate::estimators::alg3::{Alg3, Alg3Settings};
    use crate::estimators::equations::Alg3Gains;
    use std::boxed::Box;
    use std::vec::Vec;

    /// Tilt with vibration, a gyro gap, a missing phi, a repeated time stamp, a jittered step.
    fn log() -> Vec<Sample<f64>> {
        let mut t = 0.0f64;
        let mut gate = crate::StepGate::new();
        (0..4000)
            .map(|k| {
                t += if k % 7 == 0 { 1.3e-3 } else { 1e-3 };
                if k == 2500 {
                    t -= 1e-3; // not increasing
                }
                let th = 0.3 * (1.1 * t).sin() + 0.01 * (190.0 * t).sin();
                Sample {
                    dt: gate.step(t),
                    phi: if k == 1200 { f64::NAN } else { 0.9 * th },
                    gyro: if (1500..1520).contains(&k) {
                        f64::NAN
                    } else {
                        0.33 * (1.1 * t).cos()
                    },
                    ax: 0.0,
                    ay: 9.8,
                }
            })
            .collect()
    }

    #[test]
    fn shared_outputs_equal_the_stand_alone_estimators() {
        let p = PendulumParams::<f64> {
            c: 0.02,
            ..Default::default()
        };
        for theta_dd in [ThetaDdSource::Matched, ThetaDdSource::Window { span: 0.01 }] {
            let fe = FrontEndSettings {
                theta_dd,
                ..FrontEndSettings::from_params(p)
            };
            let a2 = Alg2Settings {
                front_end: fe,
                ..Alg2Settings::from_params(p)
            };
            let g = Alg3Gains {
                n: 0.004,
                ..Alg3Gains::from_params(&p)
            };
            let mut alone: Vec<Box<dyn crate::PlanarEstimator<f64>>> = std::vec![
                Box::new(Alg1::new(Alg1Settings::from_params(p))),
                Box::new(Alg2::<f64>::new(a2)),
                Box::new(Alg2::<f64>::new(Alg2Settings {
                    pivot_offset: true,
                    ..a2
                })),
                Box::new(Alg2::<f64>::new(Alg2Settings {
                    delay_compensation: true,
                    ..a2
                })),
                Box::new(Alg3::<f64>::new(Alg3Settings {
                    gains: g,
                    front_end: fe,
                })),
            ];
            let eq2 = |pivot_offset, delay_compensation| Equation::Alg2 {
                params: p,
                pivot_offset,
                delay_compensation,
            };
            let eqs = [
                Equation::Alg1(p),
                eq2(false, false),
                eq2(true, false),
                eq2(false, true),
                Equation::Alg3(g),
            ];
            let mut shared = SharedFrontEnd::<f64>::new(&fe, &eqs).unwrap();
            let mut out = [Estimate {
                theta: 0.0,
                flags: Flags::empty(),
            }; 5];
            let mut flagged = 0;
            for (k, s) in log().into_iter().enumerate() {
                shared.update(&s, &mut out);
                for (j, e) in alone.iter_mut().enumerate() {
                    let want = e.update(&s);
                    assert_eq!(
                        out[j].flags, want.flags,
                        "{theta_dd:?} output {j} sample {k}"
                    );
                    assert!(
                        (out[j].theta - want.theta).abs() < 1e-12
                            || (out[j].theta.is_nan() && want.theta.is_nan()),
                        "{theta_dd:?} output {j} sample {k}: {} vs {}",
                        out[j].theta,
                        want.theta
                    );
                    flagged += usize::from(!want.flags.is_empty());
                }
            }
            // The faults were exercised: alg1 unflagged in the gyro gap, the others flagged.
            assert!(flagged >= 5 * 3 + 4 * 20, "{flagged}");
        }
        assert!(SharedFrontEnd::<f64>::new(
            &FrontEndSettings::from_params(PendulumParams::default()),
            &[Equation::Alg1(PendulumParams::default()); MAX_EQUATIONS + 1]
        )
        .is_none());
    }
}
