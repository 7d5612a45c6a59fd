//! The file form of the tables whose keys are not a core struct's fields one for one, read
//! and written straight into the core settings by serde `with` functions:
//! - `[differentiator]`: the core's [`Cutoff`] is one of two keys, `cutoff_hz` or
//!   `cutoff_times_natural`;
//! - `[alg1]`, `[alg2]`, `[alg3]`: an algorithm's own settings beside its front end's `phi`
//!   and theta'' source, which the file gives as `theta_dd` and `window`.
//!
//! The keys' meanings are documented once, on the core fields they set. The front end's
//! shared settings are not keys of an algorithm's table: `[pendulum]`,
//! `[differentiator]` and `[gyro]` give them ([`super::RigConfig::alg2_settings`]).
use pendtilt_core::estimators::alg1::Alg1Settings;
use pendtilt_core::estimators::alg2::Alg2Settings;
use pendtilt_core::estimators::alg3::Alg3Settings;
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::estimators::PhiSource;
use pendtilt_core::filters::diff::{Cutoff, DiffSettings, Response};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The `window` key's default \[s\] (the Eq (22) window has no core default: it is part of
/// [`ThetaDdSource::Window`]).
pub const DEFAULT_WINDOW: f64 = 0.02;

/// Why a `window` value is refused, if it is.
pub(super) fn window_problem(window: f64) -> Option<&'static str> {
    if !window.is_finite() {
        Some("must be a finite number")
    } else if window <= 0.0 {
        Some("the Eq (22) window must be > 0 [s]")
    } else {
        None
    }
}

/// Why a file gives two cutoffs.
pub(super) const BOTH_CUTOFFS: &str = "give either cutoff_hz or cutoff_times_natural, not both";

/// The `theta_dd` key: which [`ThetaDdSource`] (its span is the `window` key).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum ThetaDdKey {
    Matched,
    Window,
}

/// `theta_dd` and `window` of a [`ThetaDdSource`]; a matched source writes the default
/// window, as the file always has.
fn theta_dd_keys(source: ThetaDdSource<f64>) -> (ThetaDdKey, f64) {
    match source {
        ThetaDdSource::Matched => (ThetaDdKey::Matched, DEFAULT_WINDOW),
        ThetaDdSource::Window { span } => (ThetaDdKey::Window, span),
    }
}

/// The [`ThetaDdSource`] of `theta_dd` and `window`. A bad window is refused even when it
/// is not used, as a typo waiting for `theta_dd = "window"`.
fn theta_dd_source<E: serde::de::Error>(
    key: ThetaDdKey,
    window: f64,
) -> Result<ThetaDdSource<f64>, E> {
    if let Some(why) = window_problem(window) {
        return Err(E::custom(why));
    }
    Ok(match key {
        ThetaDdKey::Matched => ThetaDdSource::Matched,
        ThetaDdKey::Window => ThetaDdSource::Window { span: window },
    })
}

/// `[differentiator]`: [`DiffSettings`].
pub(super) mod differentiator {
    use super::*;

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields, default)]
    struct Keys {
        response: Response,
        #[serde(skip_serializing_if = "Option::is_none")]
        cutoff_hz: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        cutoff_times_natural: Option<f64>,
    }

    impl Keys {
        /// The keys of `d`; the cutoff left out when it is the core's default.
        fn of(d: &DiffSettings<f64>) -> Self {
            let default = DiffSettings::<f64>::default().cutoff;
            let (cutoff_hz, cutoff_times_natural) = match d.cutoff {
                c if c == default => (None, None),
                Cutoff::Hz(f) => (Some(f), None),
                Cutoff::TimesNatural(k) => (None, Some(k)),
            };
            Self {
                response: d.response,
                cutoff_hz,
                cutoff_times_natural,
            }
        }
    }

    impl Default for Keys {
        fn default() -> Self {
            Self::of(&DiffSettings::default())
        }
    }

    pub fn serialize<S: Serializer>(d: &DiffSettings<f64>, s: S) -> Result<S::Ok, S::Error> {
        Keys::of(d).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DiffSettings<f64>, D::Error> {
        let k = Keys::deserialize(d)?;
        let cutoff = match (k.cutoff_hz, k.cutoff_times_natural) {
            (Some(_), Some(_)) => return Err(D::Error::custom(BOTH_CUTOFFS)),
            (Some(f), None) => Cutoff::Hz(f),
            (None, Some(k)) => Cutoff::TimesNatural(k),
            (None, None) => DiffSettings::<f64>::default().cutoff,
        };
        Ok(DiffSettings {
            response: k.response,
            cutoff,
        })
    }
}

/// `[alg1]`: [`Alg1Settings`] (its front end's `phi`).
pub(super) mod alg1 {
    use super::*;
    use crate::config::Alg1Table;

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields, default)]
    struct Keys {
        phi: PhiSource,
        #[serde(skip_serializing_if = "Option::is_none")]
        cutoff_times_natural: Option<f64>,
    }

    impl Default for Keys {
        fn default() -> Self {
            Self {
                phi: Alg1Settings::<f64>::default().front_end.phi,
                cutoff_times_natural: None,
            }
        }
    }

    pub fn serialize<S: Serializer>(a: &Alg1Table, s: S) -> Result<S::Ok, S::Error> {
        Keys {
            phi: a.settings.front_end.phi,
            cutoff_times_natural: a.cutoff_times_natural,
        }
        .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Alg1Table, D::Error> {
        let k = Keys::deserialize(d)?;
        let d = Alg1Settings::<f64>::default();
        Ok(Alg1Table {
            settings: Alg1Settings {
                front_end: FrontEndSettings {
                    phi: k.phi,
                    ..d.front_end
                },
            },
            cutoff_times_natural: k.cutoff_times_natural,
        })
    }
}

/// `[alg2]`: [`Alg2Settings`] (its front end's `phi` and theta'' source, and its own).
pub(super) mod alg2 {
    use super::*;

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields, default)]
    struct Keys {
        phi: PhiSource,
        theta_dd: ThetaDdKey,
        window: f64,
        pivot_offset: bool,
        delay_compensation: bool,
    }

    impl Keys {
        fn of(a: &Alg2Settings<f64>) -> Self {
            let (theta_dd, window) = theta_dd_keys(a.front_end.theta_dd);
            Self {
                phi: a.front_end.phi,
                theta_dd,
                window,
                pivot_offset: a.pivot_offset,
                delay_compensation: a.delay_compensation,
            }
        }
    }

    impl Default for Keys {
        fn default() -> Self {
            Self::of(&Alg2Settings::default())
        }
    }

    pub fn serialize<S: Serializer>(a: &Alg2Settings<f64>, s: S) -> Result<S::Ok, S::Error> {
        Keys::of(a).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Alg2Settings<f64>, D::Error> {
        let k = Keys::deserialize(d)?;
        let d = Alg2Settings::<f64>::default();
        Ok(Alg2Settings {
            front_end: FrontEndSettings {
                phi: k.phi,
                theta_dd: theta_dd_source(k.theta_dd, k.window)?,
                ..d.front_end
            },
            pivot_offset: k.pivot_offset,
            delay_compensation: k.delay_compensation,
        })
    }
}

/// `[alg3]`: [`Alg3Settings`] (its gains, its front end's `phi` and theta'' source).
///
/// A gain left out of the file is the Eq (21) equivalent of the file's pendulum (K = a,
/// L = b, M = -b, N = 0), which only the whole file knows: read alone, a table gives the
/// default pendulum's, and [`super::RigConfig::from_toml_str`] puts the file's in their
/// place. Written, the four gains are left out when they are all the Eq (21) equivalent of
/// the settings' own `front_end.params`, and written otherwise.
pub(super) mod alg3 {
    use super::*;

    /// The gain keys, in the order of [`Alg3Gains`]'s fields.
    pub const GAINS: [&str; 4] = ["k", "l", "m", "n"];

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields, default)]
    struct Keys {
        #[serde(skip_serializing_if = "Option::is_none")]
        k: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        l: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        m: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        n: Option<f64>,
        phi: PhiSource,
        theta_dd: ThetaDdKey,
        window: f64,
    }

    impl Keys {
        fn of(a: &Alg3Settings<f64>) -> Self {
            let (theta_dd, window) = theta_dd_keys(a.front_end.theta_dd);
            let g = a.gains;
            let given = g != Alg3Gains::from_params(&a.front_end.params);
            Self {
                k: given.then_some(g.k),
                l: given.then_some(g.l),
                m: given.then_some(g.m),
                n: given.then_some(g.n),
                phi: a.front_end.phi,
                theta_dd,
                window,
            }
        }
    }

    impl Default for Keys {
        fn default() -> Self {
            Self::of(&Alg3Settings::default())
        }
    }

    pub fn serialize<S: Serializer>(a: &Alg3Settings<f64>, s: S) -> Result<S::Ok, S::Error> {
        Keys::of(a).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Alg3Settings<f64>, D::Error> {
        let k = Keys::deserialize(d)?;
        let d = Alg3Settings::<f64>::default();
        Ok(Alg3Settings {
            front_end: FrontEndSettings {
                phi: k.phi,
                theta_dd: theta_dd_source(k.theta_dd, k.window)?,
                ..d.front_end
            },
            gains: Alg3Gains {
                k: k.k.unwrap_or(d.gains.k),
                l: k.l.unwrap_or(d.gains.l),
                m: k.m.unwrap_or(d.gains.m),
                n: k.n.unwrap_or(d.gains.n),
            },
        })
    }
}
