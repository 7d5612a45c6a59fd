//! `[ekf]`: the noise figures of the model-based filters (`ekf`, `ukf`), as `pendtilt tune`
//! writes them. Every key is optional; one left out keeps the value derived from the
//! default sensors and environment ([`pendtilt_core::ekf::ModelSettings::derived`]), so a
//! file without the table runs the filters exactly as before.
use pendtilt_core::ekf::ModelSettings;
use serde::{Deserialize, Serialize};

/// The `[ekf]` table: overrides of [`ModelSettings`]' sensor figures and process noise.
/// Each key sets the field of the same meaning, documented on
/// [`pendtilt_core::ekf::SensorNoise`], [`ModelSettings`] and
/// [`pendtilt_core::ekf::ProcessNoise`].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EkfConfig {
    /// Encoder resolution \[bits per turn\] (0: not quantised).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub encoder_bits: Option<u32>,
    /// Encoder noise, standard deviation \[rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub encoder_noise: Option<f64>,
    /// The pendulum's jitter from vibration above its band, standard deviation \[rad\]
    /// (`ModelSettings::encoder_jitter`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub encoder_jitter: Option<f64>,
    /// Gyro white-noise density \[rad/s/sqrt(Hz)\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_density: Option<f64>,
    /// Initial gyro bias spread, standard deviation \[rad/s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias: Option<f64>,
    /// Accelerometer white-noise density per axis \[m/s^2/sqrt(Hz)\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_density: Option<f64>,
    /// RMS of the vibration the accelerometer reads per axis \[m/s^2\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_vibration: Option<f64>,
    /// Process noise density of the tilt jerk \[rad^2/s^5\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub process_jerk: Option<f64>,
    /// Process noise density of the pendulum's unknown forcing \[1/s^3\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub process_pendulum: Option<f64>,
    /// Process noise density of the gyro bias walk \[(rad/s)^2/s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub process_bias: Option<f64>,
    /// Adapt the pendulum's forcing and the encoder's variance to the log
    /// (`ModelSettings::adaptation`; default true). `pendtilt tune` writes false: its
    /// figures are already the log's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt: Option<bool>,
}

impl EkfConfig {
    /// True when no key is set (the table is then not written).
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// `base` with every key that is set.
    pub fn apply(&self, base: ModelSettings<f64>) -> ModelSettings<f64> {
        let mut s = base;
        let set = |dst: &mut f64, v: Option<f64>| {
            if let Some(v) = v {
                *dst = v;
            }
        };
        if let Some(b) = self.encoder_bits {
            s.sensors.encoder_bits = b;
        }
        set(&mut s.sensors.encoder_noise, self.encoder_noise);
        set(&mut s.encoder_jitter, self.encoder_jitter);
        set(&mut s.sensors.gyro_density, self.gyro_density);
        set(&mut s.sensors.gyro_bias, self.gyro_bias);
        set(&mut s.sensors.accel_density, self.accel_density);
        set(&mut s.accel_vibration, self.accel_vibration);
        set(&mut s.process.jerk, self.process_jerk);
        set(&mut s.process.pendulum, self.process_pendulum);
        set(&mut s.process.bias, self.process_bias);
        if let Some(a) = self.adapt {
            s.adaptation.enabled = a;
        }
        s
    }

    /// Every key, set from `s`.
    pub fn from_settings(s: &ModelSettings<f64>) -> Self {
        Self {
            encoder_bits: Some(s.sensors.encoder_bits),
            encoder_noise: Some(s.sensors.encoder_noise),
            encoder_jitter: Some(s.encoder_jitter),
            gyro_density: Some(s.sensors.gyro_density),
            gyro_bias: Some(s.sensors.gyro_bias),
            accel_density: Some(s.sensors.accel_density),
            accel_vibration: Some(s.accel_vibration),
            process_jerk: Some(s.process.jerk),
            process_pendulum: Some(s.process.pendulum),
            process_bias: Some(s.process.bias),
            adapt: Some(s.adaptation.enabled),
        }
    }

    /// The keys with a value, as (`ekf.key`, value) for the checks.
    pub(super) fn values(&self) -> Vec<(&'static str, f64)> {
        [
            ("ekf.encoder_noise", self.encoder_noise),
            ("ekf.encoder_jitter", self.encoder_jitter),
            ("ekf.gyro_density", self.gyro_density),
            ("ekf.gyro_bias", self.gyro_bias),
            ("ekf.accel_density", self.accel_density),
            ("ekf.accel_vibration", self.accel_vibration),
            ("ekf.process_jerk", self.process_jerk),
            ("ekf.process_pendulum", self.process_pendulum),
            ("ekf.process_bias", self.process_bias),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.map(|v| (k, v)))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_table_changes_nothing_and_a_full_one_round_trips() {
        let base = ModelSettings::<f64>::default();
        assert_eq!(EkfConfig::default().apply(base), base);
        let mut other = base;
        other.sensors.encoder_bits = 14;
        other.sensors.gyro_density = 3e-4;
        other.accel_vibration = 0.7;
        other.encoder_jitter = 4e-4;
        other.process.jerk = 12.0;
        other.process.pendulum = 3.5;
        other.process.bias = 2e-9;
        other.adaptation.enabled = false;
        let c = EkfConfig::from_settings(&other);
        assert_eq!(c.apply(base), other);
    }
}
