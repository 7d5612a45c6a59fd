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

/// Default of [`BankSettings::restart_gap`] \[s\]. Shorter sensor gaps are bridged: each
/// estimator holds its input (or predicts) and resumes; longer ones restart it, because
/// after them a held gyro rate has been integrated for too long (Madgwick and Mahony were
/// left 180 and 110 deg off after a 10 s gap and never came back).
pub const RESTART_GAP: f64 = 0.5;

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
