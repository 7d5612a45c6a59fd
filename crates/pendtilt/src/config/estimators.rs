//! The estimator tables of the rig file: `[differentiator]`, `[accel]`, `[alg1]`,
//! `[alg2]`, `[alg3]`. Each key maps onto a field of a core settings struct
//! ([`pendtilt_core::estimators`], [`pendtilt_core::filters::diff`]); every key is
//! optional and its default is the core's default.
use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::estimators::PhiSource;
use pendtilt_core::filters::diff::{Cutoff, DiffSettings, Response};
use pendtilt_core::PendulumParams;
use serde::{Deserialize, Serialize};

/// Where theta'' (G_d) comes from in Algorithms 2 and 3 (`theta_dd = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ThetaDdChoice {
    /// `"matched"` (default): the gyro through the same differentiator as phi.
    #[default]
    Matched,
    /// `"window"`: the paper's Eq (22) over `window` seconds.
    Window,
}

/// The `[differentiator]` table: the smoothing differentiator that gives phi' and phi''
/// to `alg1`, `alg2` and `alg3` (and theta'' under `theta_dd = "matched"`).
///
/// The cutoff is either fixed (`cutoff_hz`) or relative to the pendulum's natural
/// frequency (`cutoff_times_natural`, default 1.3); giving both is an error. A higher
/// cutoff lets more residual vibration through phi''; a lower one delays the estimate
/// (see [`pendtilt_core::filters::diff`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DifferentiatorConfig {
    /// Filter shape, `response = "butterworth" | "bessel" | "critically_damped"`: the
    /// core's [`Response`] (default [`Response::Butterworth`]).
    pub response: Response,
    /// Fixed cutoff \[Hz\], > 0. Default: unset (relative cutoff).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cutoff_hz: Option<f64>,
    /// Cutoff as a multiple of the natural frequency f_n, > 0. Default: unset, meaning 1.3.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cutoff_times_natural: Option<f64>,
}

impl DifferentiatorConfig {
    /// The core settings.
    pub fn settings(&self) -> DiffSettings<f64> {
        let default = DiffSettings::<f64>::default();
        DiffSettings {
            response: self.response,
            cutoff: match (self.cutoff_hz, self.cutoff_times_natural) {
                (Some(hz), _) => Cutoff::Hz(hz),
                (None, Some(k)) => Cutoff::TimesNatural(k),
                (None, None) => default.cutoff,
            },
        }
    }
}

/// The `[alg1]` table: Eq (20).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Alg1Config {
    /// Which phi enters the equation, `phi = "raw" | "filtered"`: the core's
    /// [`PhiSource`] (default [`PhiSource::Raw`]).
    pub phi: PhiSource,
}

/// Default Eq (22) window \[s\] when `theta_dd = "window"`.
pub const DEFAULT_GD_WINDOW: f64 = 0.02;

fn default_window() -> f64 {
    DEFAULT_GD_WINDOW
}

/// The `[alg2]` table: Eqs (21)-(22), and `alg2_offset` (the pivot-offset term).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Alg2Config {
    /// Which phi enters the equation, `phi = "raw" | "filtered"`: the core's
    /// [`PhiSource`] (default [`PhiSource::Raw`]).
    pub phi: PhiSource,
    /// Where theta'' comes from. Default `"matched"`.
    pub theta_dd: ThetaDdChoice,
    /// Eq (22) window \[s\], > 0, used with `theta_dd = "window"`. Default 0.02.
    #[serde(default = "default_window")]
    pub window: f64,
    /// Add the pivot-offset term c (theta'' cos phi - theta'^2 sin phi) to `alg2` itself.
    /// Default false (the paper's Eq 21).
    pub pivot_offset: bool,
    /// Remove the differentiator's first-order delay with the gyro (not in the paper; see
    /// `Alg2Settings::delay_compensation`). Default false (Eq 21 as printed).
    pub delay_compensation: bool,
}

impl Default for Alg2Config {
    fn default() -> Self {
        Self {
            phi: PhiSource::Raw,
            theta_dd: ThetaDdChoice::Matched,
            window: DEFAULT_GD_WINDOW,
            pivot_offset: false,
            delay_compensation: false,
        }
    }
}

pub(super) fn theta_dd(choice: ThetaDdChoice, window: f64) -> ThetaDdSource<f64> {
    match choice {
        ThetaDdChoice::Matched => ThetaDdSource::Matched,
        ThetaDdChoice::Window => ThetaDdSource::Window { span: window },
    }
}

/// The `[alg3]` table: Eq (30) with gains K, L, M, N (as fitted by `pendtilt fit`).
///
/// A gain left out takes the value under which Eq (30) equals Eq (21): K = a, L = b,
/// M = -b, N = 0, with a, b from `[pendulum]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Alg3Config {
    /// K, multiplies phi' \[s\]. Default a.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    /// L, multiplies phi'' \[s^2\]. Default b.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub l: Option<f64>,
    /// M, multiplies G_d \[s^2\]. Default -b.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub m: Option<f64>,
    /// N, multiplies the gyro G_k outside the asin \[s\]. Default 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub n: Option<f64>,
    /// Which phi enters the equation, `phi = "raw" | "filtered"`: the core's
    /// [`PhiSource`] (default [`PhiSource::Raw`]).
    pub phi: PhiSource,
    /// Where G_d comes from. Default `"matched"`.
    pub theta_dd: ThetaDdChoice,
    /// Eq (22) window \[s\], > 0, used with `theta_dd = "window"`. Default 0.02.
    #[serde(default = "default_window")]
    pub window: f64,
}

impl Default for Alg3Config {
    fn default() -> Self {
        Self {
            k: None,
            l: None,
            m: None,
            n: None,
            phi: PhiSource::Raw,
            theta_dd: ThetaDdChoice::Matched,
            window: DEFAULT_GD_WINDOW,
        }
    }
}

impl Alg3Config {
    /// The gains, those left out taken from `params` (K = a, L = b, M = -b, N = 0).
    pub fn gains(&self, params: &PendulumParams<f64>) -> Alg3Gains<f64> {
        let d = Alg3Gains::from_params(params);
        Alg3Gains {
            k: self.k.unwrap_or(d.k),
            l: self.l.unwrap_or(d.l),
            m: self.m.unwrap_or(d.m),
            n: self.n.unwrap_or(d.n),
        }
    }

    /// A table with all four gains given (for example a fit result) and the other keys at
    /// their defaults.
    pub fn from_gains(g: &Alg3Gains<f64>) -> Self {
        let mut c = Self::default();
        c.set_gains(*g);
        c
    }

    /// Sets all four gains (for example a fit result).
    pub fn set_gains(&mut self, g: Alg3Gains<f64>) {
        self.k = Some(g.k);
        self.l = Some(g.l);
        self.m = Some(g.m);
        self.n = Some(g.n);
    }
}

/// A rule broken: (dotted key, value, why).
pub(super) type Issue = (String, f64, String);

fn positive(issues: &mut Vec<Issue>, key: &str, value: Option<f64>, why: &str) {
    if let Some(v) = value {
        if !v.is_finite() {
            issues.push((key.into(), v, "must be a finite number".into()));
        } else if v <= 0.0 {
            issues.push((key.into(), v, why.into()));
        }
    }
}

pub(super) fn check_estimators(e: &super::RigConfig, issues: &mut Vec<Issue>) {
    let d = &e.differentiator;
    positive(
        issues,
        "differentiator.cutoff_hz",
        d.cutoff_hz,
        "the cutoff must be > 0 [Hz]",
    );
    positive(
        issues,
        "differentiator.cutoff_times_natural",
        d.cutoff_times_natural,
        "the cutoff must be > 0 (a multiple of f_n)",
    );
    if let (Some(_), Some(k)) = (d.cutoff_hz, d.cutoff_times_natural) {
        issues.push((
            "differentiator.cutoff_times_natural".into(),
            k,
            "give either cutoff_hz or cutoff_times_natural, not both".into(),
        ));
    }
    positive(
        issues,
        "accel.prefilter_hz",
        e.accel.prefilter_hz,
        "the prefilter cutoff must be > 0 [Hz] (leave it out to turn it off)",
    );
    positive(
        issues,
        "accel.full_scale",
        e.accel.full_scale,
        "the full scale must be > 0 [m/s^2] (leave it out when unknown)",
    );
    positive(
        issues,
        "gyro.full_scale",
        e.gyro.full_scale,
        "the full scale must be > 0 [rad/s] (leave it out when unknown)",
    );
    positive(
        issues,
        "alg2.window",
        Some(e.alg2.window),
        "the Eq (22) window must be > 0 [s]",
    );
    positive(
        issues,
        "alg3.window",
        Some(e.alg3.window),
        "the Eq (22) window must be > 0 [s]",
    );
    for (key, v) in [
        ("alg3.k", e.alg3.k),
        ("alg3.l", e.alg3.l),
        ("alg3.m", e.alg3.m),
        ("alg3.n", e.alg3.n),
    ] {
        if let Some(v) = v.filter(|v| !v.is_finite()) {
            issues.push((key.into(), v, "must be a finite number".into()));
        }
    }
}

/// The unit and meaning of each estimator key, for the written file's comments.
pub(super) fn key_comment(table: &str, key: &str) -> Option<&'static str> {
    Some(match (table, key) {
        ("differentiator", "response") => "butterworth | bessel | critically_damped",
        ("differentiator", "cutoff_hz") => "fixed cutoff [Hz]",
        ("differentiator", "cutoff_times_natural") => "cutoff / natural frequency",
        ("accel", "prefilter_hz") => "low-pass on ax, ay before atan2 [Hz]",
        ("accel", "full_scale") => "accelerometer full scale [m/s^2]",
        ("gyro", "full_scale") => "gyro full scale [rad/s]",
        ("alg1" | "alg2" | "alg3", "phi") => "raw | filtered",
        ("alg2" | "alg3", "theta_dd") => "matched | window (Eq 22)",
        ("alg2" | "alg3", "window") => "Eq (22) window [s]",
        ("alg2", "pivot_offset") => "add the l12 term to alg2",
        ("alg2", "delay_compensation") => "remove the differentiator delay with the gyro",
        ("alg3", "k") => "K, times phi' [s]",
        ("alg3", "l") => "L, times phi'' [s^2]",
        ("alg3", "m") => "M, times G_d [s^2]",
        ("alg3", "n") => "N, times G_k [s]",
        _ => return None,
    })
}
