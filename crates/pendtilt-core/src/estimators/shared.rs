//! Algorithms 1-3 on one front end: the inversion equations as values ([`Equation`]) and
//! [`SharedFrontEnd`], which runs the differentiator once per sample and evaluates several
//! equations on its [`Kinematics`].
//!
//! Every algorithm is "front end + equation": the front end (time checks, encoder
//! unwrapping, the phi and gyro differentiator, theta'') is the expensive part and is the
//! same for every equation with the same differentiator settings. Running Algorithms 1, 2
//! (with its variants) and 3 side by side, as `pendtilt estimate` does, then costs one
//! front end and a few asin: each output is the same number the stand-alone estimator
//! gives (test `shared_outputs_equal_the_stand_alone_estimators`).
use super::encoder::wrap_angle;
use super::equations::{self, Alg3Gains, Inversion};
use super::inverter::{Inverter, Kinematics, PhiSource};
use super::theta_dd::{ThetaDdSource, DEFAULT_WINDOW_CAPACITY};
use crate::filters::diff::DiffSettings;
use crate::params::GyroSettings;
use crate::{Estimate, Flags, PendulumParams, Real, Sample};

/// One inversion equation of the paper (or a variant), evaluated on the front end's
/// [`Kinematics`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Equation<T> {
    /// Eq (20), Algorithm 1: `phi + asin(a phi' + b phi'')`.
    Alg1(PendulumParams<T>),
    /// Eq (21), Algorithm 2: `phi + asin(a phi' + b (phi'' - theta''))`, optionally with the
    /// pivot-offset term and the delay compensation (see
    /// [`super::alg2::Alg2Settings`]).
    Alg2 {
        /// a, b (and c with `pivot_offset`).
        params: PendulumParams<T>,
        /// Add the pivot-offset term (output `alg2_offset`).
        pivot_offset: bool,
        /// Remove the differentiator's first-order delay with the gyro (`alg2_dc`).
        delay_compensation: bool,
    },
    /// Eq (30), Algorithm 3: `phi + asin(K phi' + L phi'' + M G_d) + N G_k`.
    Alg3(Alg3Gains<T>),
}

impl<T: Real> Equation<T> {
    /// True when the equation reads the gyro (its flags then include the gyro's).
    pub fn reads_gyro(&self) -> bool {
        !matches!(self, Equation::Alg1(_))
    }

    /// The unwrapped estimate for one sample's kinematics.
    // Always inlined: the stand-alone estimators pass a known variant, and the match then
    // folds away (measured: out of line it was a fifth of Algorithm 2's per-sample time).
    #[inline(always)]
    pub fn evaluate(&self, k: &Kinematics<T>) -> Inversion<T> {
        match self {
            Equation::Alg1(p) => equations::alg1(p, k.phi, k.dphi, k.ddphi),
            Equation::Alg2 {
                params: p,
                pivot_offset,
                delay_compensation,
            } => {
                let mut r = if *pivot_offset {
                    equations::alg2_offset(p, k.phi, k.dphi, k.ddphi, k.gyro, k.theta_dd)
                } else {
                    equations::alg2(p, k.phi, k.dphi, k.ddphi, k.theta_dd)
                };
                if *delay_compensation {
                    r.theta -= k.delay * (k.dphi - k.gyro_filtered);
                }
                r
            }
            Equation::Alg3(g) => equations::alg3(g, k.phi, k.dphi, k.ddphi, k.theta_dd, k.gyro),
        }
    }

    /// The estimate and its flags for one sample, from the front end's output.
    #[inline(always)]
    pub(crate) fn estimate(&self, k: &Kinematics<T>, phi_flags: Flags) -> (T, Flags) {
        let r = self.evaluate(k);
        let mut flags = phi_flags;
        if self.reads_gyro() {
            flags |= k.gyro_flags;
        }
        if r.clamped {
            flags |= Flags::ASIN_CLAMPED;
        }
        (wrap_angle(r.theta), flags)
    }
}

/// The most equations one [`SharedFrontEnd`] evaluates.
pub const MAX_EQUATIONS: usize = 8;

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

/// Several inversion equations on one front end; no allocation (at most
/// [`MAX_EQUATIONS`]). Each output holds its own previous estimate on a bad sample, like
/// the stand-alone estimators.
#[derive(Debug, Clone)]
pub struct SharedFrontEnd<T: Real, const W: usize = DEFAULT_WINDOW_CAPACITY> {
    settings: FrontEndSettings<T>,
    front: Inverter<T, W, 2>,
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
            front: Inverter::new(settings, true),
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
