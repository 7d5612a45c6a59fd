//! The rig written as TOML, every value with a comment giving its unit.
use std::path::Path;

use super::RigConfig;

impl RigConfig {
    /// The rig as TOML text, every value written out with a comment giving its unit.
    /// [`RigConfig::from_toml_str`] reads it back to an equal value.
    pub fn to_toml_string(&self) -> String {
        // alg3 with its pendulum, so that gains that are its Eq (21) equivalent are left
        // out, as in a file that gives none.
        let file = Self {
            alg3: self.alg3_settings(),
            ..self.clone()
        };
        // Serialising plain structs of finite floats cannot fail; fall back to an empty
        // body rather than panic if it ever did.
        let body = toml::to_string(&file).unwrap_or_default();
        let mut out = String::from(
            "# pendtilt rig file (MODEL.md section 5). SI units; every key is optional.\n",
        );
        let mut table = String::new();
        for line in body.lines() {
            let trimmed = line.trim();
            if let Some(name) = trimmed.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
                table = name.to_string();
                out.push_str(line);
                out.push('\n');
                if table == "ekf" && self.ekf.is_empty() {
                    out.push_str(
                        "# no key: every figure derived from the default sensors; \
                         `pendtilt tune` writes them\n",
                    );
                }
                continue;
            }
            let key = trimmed.split('=').next().unwrap_or("").trim();
            match key_comment(&table, key) {
                Some(comment) if !key.is_empty() => {
                    out.push_str(&format!("{line:<28} # {comment}\n"));
                }
                _ => {
                    out.push_str(line);
                    out.push('\n');
                }
            }
        }
        out
    }

    /// Writes [`RigConfig::to_toml_string`] to `path`; an error message names the path.
    pub fn save(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        let path = path.as_ref();
        std::fs::write(path, self.to_toml_string()).map_err(|e| {
            std::io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
        })
    }
}

/// The unit and meaning of each key, for the comments of [`RigConfig::to_toml_string`]
/// (test `every_written_key_has_a_comment`).
fn key_comment(table: &str, key: &str) -> Option<&'static str> {
    Some(match (table, key) {
        ("pendulum", "mass") => "m_p [kg]",
        ("pendulum", "length") => "l_p, pivot to centre of gravity [m]",
        ("pendulum", "inertia") => "I_p about the pivot [kg m^2]",
        ("pendulum", "damping") => "C, viscous friction [N m s/rad]",
        ("pendulum", "pivot_offset") => "l12, body axis to pendulum pivot [m]",
        ("pendulum", "gravity") => "g [m/s^2]",
        ("pendulum", "a") => "C / (m_p g l_p) [s]",
        ("pendulum", "b") => "I_p / (m_p g l_p) [s^2]",
        ("pendulum", "c") => "l12 / g [s^2]",
        ("kalman", "q_angle") => "angle noise density [rad^2/s], Q = q dt",
        ("kalman", "q_bias") => "bias noise density [(rad/s)^2/s], Q = q dt",
        ("kalman", "r_accel") => "accelerometer angle variance [rad^2]",
        ("kalman", "r_pendulum") => "pendulum angle variance [rad^2]",
        ("kalman", "r_accel_fused") => "kf_fused's accelerometer angle variance [rad^2]",
        ("kalman", "p0_angle") => "initial angle variance [rad^2]",
        ("kalman", "p0_bias") => "initial bias variance [(rad/s)^2]",
        ("differentiator", "response") => "butterworth | bessel | critically_damped",
        ("differentiator", "cutoff_hz") => "fixed cutoff [Hz]",
        ("differentiator", "cutoff_times_natural") => "cutoff / natural frequency",
        ("accel", "prefilter_hz") => "low-pass on ax, ay before atan2 [Hz]",
        ("accel", "full_scale") => "accelerometer full scale [m/s^2]",
        ("gyro", "full_scale") => "gyro full scale [rad/s]",
        ("alg1" | "alg2" | "alg3", "phi") => "raw | filtered",
        ("alg1", "cutoff_times_natural") => "alg1's own cutoff / natural frequency",
        ("alg2" | "alg3", "theta_dd") => "matched | window (Eq 22)",
        ("alg2" | "alg3", "window") => "Eq (22) window [s]",
        ("alg2", "pivot_offset") => "add the l12 term to alg2",
        ("alg2", "delay_compensation") => "remove the differentiator delay with the gyro",
        ("alg3", "k") => "K, times phi' [s]",
        ("alg3", "l") => "L, times phi'' [s^2]",
        ("alg3", "m") => "M, times G_d [s^2]",
        ("alg3", "n") => "N, times G_k [s]",
        ("ekf", "encoder_bits") => "encoder resolution [bits per turn], 0: not quantised",
        ("ekf", "encoder_noise") => "encoder noise, standard deviation [rad]",
        ("ekf", "gyro_density") => "gyro white-noise density [rad/s/sqrt(Hz)]",
        ("ekf", "gyro_bias") => "initial gyro bias spread [rad/s]",
        ("ekf", "accel_density") => "accelerometer noise density [m/s^2/sqrt(Hz)]",
        ("ekf", "accel_vibration") => "vibration RMS the accelerometer reads [m/s^2]",
        ("ekf", "process_jerk") => "tilt jerk process noise density [rad^2/s^5]",
        ("ekf", "process_pendulum") => "pendulum forcing process noise density [1/s^3]",
        ("ekf", "process_bias") => "gyro bias walk process noise density [(rad/s)^2/s]",
        ("ekf", "adapt") => "adapt the forcing and encoder noise to the log (docs/adaptation.md)",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pendtilt_core::PendulumParams;

    #[test]
    fn every_written_key_has_a_comment() {
        let phys = RigConfig::default().to_toml_string();
        let norm = RigConfig::from_params(PendulumParams::default())
            .unwrap()
            .to_toml_string();
        for text in [phys, norm] {
            for line in text.lines() {
                if line.contains('=') {
                    assert!(line.contains('#'), "no comment on `{line}`");
                }
            }
        }
    }
}
