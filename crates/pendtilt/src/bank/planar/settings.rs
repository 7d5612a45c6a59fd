//! The bank's settings ([`BankSettings`]): the rig's, from its rig file, and the defaults
//! of the estimators beyond the paper and of the restart after a sensor gap.
use pendtilt_core::PendulumParams;

use crate::config::{PendulumConfig, RigConfig};
use crate::peers::PeerSettings;

/// Settings of every estimator in the bank (f64, SI), each defined once: the rig's
/// settings are the rig file's ([`RigConfig`]), and each entry builds its estimator's
/// settings from them ([`RigConfig::alg2_settings`], [`RigConfig::kalman_settings`], ...).
#[derive(Debug, Clone, PartialEq)]
pub struct BankSettings {
    /// The pendulum and the paper's estimators: `accel`, `alg1`-`alg3` (and their
    /// variants), every `kf_*`.
    pub rig: RigConfig,
    /// Gravity \[m/s^2\] of the EKF/UKF model when it is not the rig's
    /// ([`RigConfig::gravity`]): a normalised pendulum has none. Default `None`.
    pub gravity: Option<f64>,
    /// `ekf`, `ukf`, `madgwick`, `mahony`, `complementary` (beyond the paper).
    pub peers: PeerSettings,
    /// A sensor whose readings were all missing for longer than this \[s\] (a gap in the
    /// log, a burst of missing or implausible cells) restarts every estimator that reads
    /// it at its next good reading. Default [`RESTART_GAP`].
    pub restart_gap: f64,
}

pub use crate::sensors::RESTART_GAP;

impl BankSettings {
    /// The rig's settings and the defaults of the rest.
    pub fn from_rig(rig: RigConfig) -> Self {
        Self {
            rig,
            gravity: None,
            peers: PeerSettings::default(),
            restart_gap: RESTART_GAP,
        }
    }

    /// Defaults for a pendulum with parameters `params`.
    pub fn from_params(params: PendulumParams<f64>) -> Self {
        Self::from_rig(RigConfig::with_pendulum(PendulumConfig::Normalised(params)))
    }

    /// The pendulum (a, b, c).
    pub fn params(&self) -> PendulumParams<f64> {
        self.rig.params()
    }

    /// Gravity \[m/s^2\] of the EKF/UKF model: [`BankSettings::gravity`] if set, else the
    /// rig's.
    pub fn gravity(&self) -> f64 {
        self.gravity.unwrap_or_else(|| self.rig.gravity())
    }
}

/// Checks the frequency settings of `settings` against a log whose median time step is
/// `dt` \[s\]: every cutoff below the Nyquist frequency, the differentiator's at least
/// [`crate::units::MIN_DIFF_CUTOFF_TIMES_NATURAL`] f_n. The error names the setting, the log's rate and
/// the valid range.
pub fn check_settings_against_rate(settings: &BankSettings, dt: f64) -> Result<(), String> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Ok(());
    }
    let rate = 1.0 / dt;
    let nyquist = rate / 2.0;
    let f_n = settings.params().natural_frequency_hz();
    let floor = crate::units::MIN_DIFF_CUTOFF_TIMES_NATURAL * f_n;
    let diff = settings.rig.differentiator;
    let hz = diff.cutoff_hz(&settings.params());
    let what = match diff.cutoff {
        pendtilt_core::filters::diff::Cutoff::Hz(_) => {
            format!("[differentiator] cutoff_hz = {hz} Hz")
        }
        pendtilt_core::filters::diff::Cutoff::TimesNatural(k) => format!(
            "[differentiator] cutoff_times_natural = {k}, a cutoff of {hz:.1} Hz \
             (f_n = {f_n:.3} Hz),"
        ),
    };
    if !(hz < nyquist && hz >= floor) {
        let why = if hz >= nyquist {
            format!("at or above the Nyquist frequency {nyquist} Hz of this log")
        } else {
            format!(
                "below {} f_n: it would filter out the \
                 pendulum's own swing at f_n = {f_n:.3} Hz that Eqs (20)-(21) read",
                crate::units::MIN_DIFF_CUTOFF_TIMES_NATURAL
            )
        };
        return Err(format!(
            "{what} is {why} (median time step {dt} s, {rate} Hz); valid range: \
             {floor:.3} Hz up to below {nyquist} Hz"
        ));
    }
    if let Some(p) = settings.rig.accel.prefilter_hz {
        if p >= nyquist {
            return Err(format!(
                "[accel] prefilter_hz = {p} Hz is at or above the Nyquist frequency \
                 {nyquist} Hz of this log (median time step {dt} s, {rate} Hz); valid \
                 range: above 0 up to below {nyquist} Hz"
            ));
        }
    }
    Ok(())
}
