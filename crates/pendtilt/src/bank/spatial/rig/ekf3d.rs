//! `[ekf3d]`: the spatial filter's settings a 3-D rig file may change.
use pendtilt_core::spatial::ekf;
use serde::{Deserialize, Serialize};

/// `[ekf3d]`: the settings of `ekf3d` and `ukf3d` a rig may set, each optional and each
/// the field of [`ekf::Settings`] of the same name (documented there, with its default).
/// A travelling vehicle may want a larger `vibration_density` than the standing
/// scooter's default: see docs/spatial.md, "The 3-D estimators (library)".
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Ekf3dConfig {
    /// [`pendtilt_core::ekf::Environment::vibration_density`] \[m/s^2/sqrt(Hz)\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vibration_density: Option<f64>,
    /// [`ekf::Settings::angular_accel_hz`] \[Hz\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angular_accel_hz: Option<f64>,
    /// [`ekf::Settings::angular_accel_lead`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angular_accel_lead: Option<bool>,
    /// [`ekf::SpeedSettings::noise`] \[m/s\] of [`ekf::Settings::speed`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_noise: Option<f64>,
    /// [`ekf::SpeedSettings::jerk_density`] \[m/s^3/sqrt(Hz)\] of [`ekf::Settings::speed`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jerk_density: Option<f64>,
    /// [`pendtilt_core::spatial::travel::PathSettings::path_turn_hz`] \[Hz\] (`inf`: the gyro as read).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_turn_hz: Option<f64>,
    /// [`pendtilt_core::spatial::travel::PathSettings::path_pitch_hz`] \[Hz\] (`inf`: the gyro as read).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_pitch_hz: Option<f64>,
    /// [`ekf::Settings::encoder_jitter`] \[rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub encoder_jitter: Option<f64>,
    /// [`ekf::Settings::use_accel`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub use_accel: Option<bool>,
    /// [`pendtilt_core::spatial::ekf::Adaptation::enabled`] of
    /// [`ekf::Settings::adaptation`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt: Option<bool>,
    /// [`pendtilt_core::spatial::ekf::Adaptation::min_factor`]: the lowest factor on
    /// `vibration_density`'s variance the adaptation may reach.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt_min_factor: Option<f64>,
    /// [`pendtilt_core::spatial::ekf::Adaptation::max_factor`]: the highest factor on
    /// `vibration_density`'s variance the adaptation may reach.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapt_max_factor: Option<f64>,
    /// [`ekf::Settings::guard_angle`] \[rad\] (`inf`: no guard).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guard_angle: Option<f64>,
    /// [`ekf::Settings::pendulum_range`] \[rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pendulum_range: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::encoder_bits`] of [`ekf::Settings::sensors`]
    /// (0: not quantised).
    pub encoder_bits: Option<u32>,
    /// [`pendtilt_core::ekf::SensorNoise::encoder_noise`] \[rad\].
    pub encoder_noise: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::gyro_density`] \[rad/s/sqrt(Hz)\].
    pub gyro_density: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::gyro_bias_walk`] \[rad/s/sqrt(s)\].
    pub gyro_bias_walk: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::gyro_bias`] \[rad/s\]: the initial bias' spread.
    pub gyro_bias: Option<f64>,
    /// [`pendtilt_core::ekf::SensorNoise::accel_density`] \[m/s^2/sqrt(Hz)\].
    pub accel_density: Option<f64>,
}

impl Ekf3dConfig {
    /// `key: why` for a value no filter can use.
    pub(super) fn check(&self) -> Result<(), String> {
        for (key, v) in [
            ("vibration_density", self.vibration_density),
            ("angular_accel_hz", self.angular_accel_hz),
            ("jerk_density", self.jerk_density),
            ("gyro_density", self.gyro_density),
            ("gyro_bias_walk", self.gyro_bias_walk),
            ("gyro_bias", self.gyro_bias),
            ("accel_density", self.accel_density),
            ("adapt_min_factor", self.adapt_min_factor),
            ("adapt_max_factor", self.adapt_max_factor),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(format!("ekf3d.{key}: {v} must be finite and > 0"));
            }
        }
        for (key, v) in [
            ("path_turn_hz", self.path_turn_hz),
            ("path_pitch_hz", self.path_pitch_hz),
        ] {
            if let Some(v) = v.filter(|v| v.is_nan() || *v <= 0.0) {
                return Err(format!(
                    "ekf3d.{key}: {v} must be > 0 (inf takes the gyro as read)"
                ));
            }
        }
        if let (Some(lo), Some(hi)) = (self.adapt_min_factor, self.adapt_max_factor) {
            if lo > hi {
                return Err(format!(
                    "ekf3d.adapt_min_factor {lo} is above adapt_max_factor {hi}"
                ));
            }
        }
        if let Some(v) = self.guard_angle.filter(|v| v.is_nan() || *v <= 0.0) {
            return Err(format!(
                "ekf3d.guard_angle: {v} must be > 0 rad (inf: no guard)"
            ));
        }
        if let Some(v) = self
            .pendulum_range
            .filter(|v| !(v.is_finite() && *v > 0.0 && *v <= std::f64::consts::FRAC_PI_2))
        {
            return Err(format!(
                "ekf3d.pendulum_range: {v} must be between 0 and pi/2 rad (the Cardan joint locks at pi/2)"
            ));
        }
        // An exact sensor may say 0 (a speed from a simulation, a jitter-free encoder).
        for (key, v) in [
            ("encoder_jitter", self.encoder_jitter),
            ("speed_noise", self.speed_noise),
            ("encoder_noise", self.encoder_noise),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(format!("ekf3d.{key}: {v} must be finite and >= 0"));
            }
        }
        if let Some(b) = self.encoder_bits.filter(|b| *b > 52) {
            return Err(format!(
                "ekf3d.encoder_bits: {b} must be 0 (not quantised) to 52"
            ));
        }
        Ok(())
    }

    /// Writes the keys given into `s`.
    pub fn apply(&self, s: &mut ekf::Settings<f64>) {
        if let Some(v) = self.vibration_density {
            s.environment.vibration_density = v;
        }
        if let Some(v) = self.angular_accel_hz {
            s.angular_accel_hz = v;
        }
        if let Some(v) = self.angular_accel_lead {
            s.angular_accel_lead = v;
        }
        if let Some(v) = self.speed_noise {
            s.speed.noise = v;
        }
        if let Some(v) = self.jerk_density {
            s.speed.jerk_density = v;
        }
        if let Some(v) = self.path_turn_hz {
            s.path.path_turn_hz = v;
        }
        if let Some(v) = self.path_pitch_hz {
            s.path.path_pitch_hz = v;
        }
        if let Some(v) = self.encoder_jitter {
            s.encoder_jitter = v;
        }
        if let Some(v) = self.use_accel {
            s.use_accel = v;
        }
        if let Some(v) = self.adapt {
            s.adaptation.enabled = v;
        }
        if let Some(v) = self.adapt_min_factor {
            s.adaptation.min_factor = v;
        }
        if let Some(v) = self.adapt_max_factor {
            s.adaptation.max_factor = v;
        }
        if let Some(v) = self.guard_angle {
            s.guard_angle = v;
        }
        if let Some(v) = self.pendulum_range {
            s.pendulum_range = v;
        }
        let n = &mut s.sensors;
        if let Some(v) = self.encoder_bits {
            n.encoder_bits = v;
        }
        if let Some(v) = self.encoder_noise {
            n.encoder_noise = v;
        }
        if let Some(v) = self.gyro_density {
            n.gyro_density = v;
        }
        if let Some(v) = self.gyro_bias_walk {
            n.gyro_bias_walk = v;
        }
        if let Some(v) = self.gyro_bias {
            n.gyro_bias = v;
        }
        if let Some(v) = self.accel_density {
            n.accel_density = v;
        }
    }

    /// True when the table gives every sensor noise figure (then a log's filter needs no
    /// `--scenario` for them).
    pub fn gives_sensor_noise(&self) -> bool {
        self.encoder_bits.is_some()
            && self.encoder_noise.is_some()
            && self.gyro_density.is_some()
            && self.gyro_bias_walk.is_some()
            && self.accel_density.is_some()
    }
}
