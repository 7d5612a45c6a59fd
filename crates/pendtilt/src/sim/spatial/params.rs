//! The Cardan pendulum's constants (MODEL.md 7.2, 7.3, 7.6): physical form, the normalised
//! form of 7.3, and the linearised natural frequencies and damping ratios of 7.2.

use pendtilt_core::model::cardan::CardanParams;
use serde::{Deserialize, Serialize};

use crate::sim::planar::SimError;

/// A two-axis pendulum on a Cardan joint, SI units (MODEL.md 7.2; the `[pendulum3d]` table
/// of 7.6). The outer ring turns about body x, the pendulum about the ring's y axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Pendulum3d {
    /// m \[kg\]. Default 0.05.
    pub mass: f64,
    /// l, pivot P2 to the centre of mass \[m\]. Default 0.05.
    pub length: f64,
    /// Ixx about P2, pendulum axes, including m l^2 \[kg m^2\]. Default 1.3e-4.
    pub inertia_xx: f64,
    /// Iyy about P2, pendulum axes, including m l^2 \[kg m^2\]. Default 1.3e-4.
    pub inertia_yy: f64,
    /// Izz about P2, pendulum axes (small, > 0) \[kg m^2\]. Default 1e-6.
    pub inertia_zz: f64,
    /// J_ring, the outer ring about body x \[kg m^2\]. Default 0.
    pub ring_inertia: f64,
    /// C_x, outer joint viscous damping \[N m s/rad\]. Default 1.07e-3 (zeta 0.30).
    pub damping_x: f64,
    /// C_y, inner joint viscous damping \[N m s/rad\]. Default 1.07e-3 (zeta 0.30).
    pub damping_y: f64,
    /// r12 = P2 - P1, body axes \[m\]. Default 0.
    pub pivot_offset: [f64; 3],
    /// g \[m/s^2\]. Default 9.80665.
    pub gravity: f64,
}

impl Default for Pendulum3d {
    /// The rig of MODEL.md 7.6: f_n = 2.19 Hz and zeta = 0.30 on each axis.
    fn default() -> Self {
        Self {
            mass: 0.05,
            length: 0.05,
            inertia_xx: 1.3e-4,
            inertia_yy: 1.3e-4,
            inertia_zz: 1.0e-6,
            ring_inertia: 0.0,
            damping_x: 1.07e-3,
            damping_y: 1.07e-3,
            pivot_offset: [0.0; 3],
            gravity: 9.80665,
        }
    }
}

impl Pendulum3d {
    /// m g l \[N m\]: the gravity stiffness of either joint on a level body.
    pub fn mgl(&self) -> f64 {
        self.mass * self.gravity * self.length
    }

    /// The normalised parameters of MODEL.md 7.3, as the core's estimators take them
    /// (the one conversion from the physical form).
    pub fn normalised(&self) -> CardanParams<f64> {
        let k = self.mgl();
        CardanParams {
            a_x: self.damping_x / k,
            a_y: self.damping_y / k,
            b_x: self.inertia_xx / k,
            b_y: self.inertia_yy / k,
            b_z: self.inertia_zz / k,
            b_ring: self.ring_inertia / k,
            c: self.pivot_offset.map(|r| r / self.gravity),
            gravity: self.gravity,
        }
    }

    /// Linearised stiffness (K_x, K_y) \[N m/rad\] about the hanging equilibrium on a body at
    /// rest with pitch `pitch` (MODEL.md 7.2): (m g l cos^2 p, m g l). Roll and yaw do not
    /// enter.
    pub fn stiffness(&self, pitch: f64) -> [f64; 2] {
        let c = pitch.cos();
        [self.mgl() * c * c, self.mgl()]
    }

    /// Linearised inertia (M_x, M_y) \[kg m^2\] about the same equilibrium (MODEL.md 7.2):
    /// (J_ring + Ixx cos^2 p + Izz sin^2 p, Iyy).
    pub fn inertia(&self, pitch: f64) -> [f64; 2] {
        let (s, c) = pitch.sin_cos();
        [
            self.ring_inertia + self.inertia_xx * c * c + self.inertia_zz * s * s,
            self.inertia_yy,
        ]
    }

    /// Small-angle natural frequencies (w_x, w_y) = sqrt(K / M) \[rad/s\] at pitch `pitch`
    /// (MODEL.md 7.2; on a level body sqrt(m g l / (Ixx + J_ring)), sqrt(m g l / Iyy)).
    pub fn natural_frequencies(&self, pitch: f64) -> [f64; 2] {
        let (k, m) = (self.stiffness(pitch), self.inertia(pitch));
        [(k[0] / m[0]).sqrt(), (k[1] / m[1]).sqrt()]
    }

    /// Damping ratios (zeta_x, zeta_y) = C / (2 sqrt(K M)) at pitch `pitch` (MODEL.md 7.2).
    pub fn damping_ratios(&self, pitch: f64) -> [f64; 2] {
        let (k, m) = (self.stiffness(pitch), self.inertia(pitch));
        [
            self.damping_x / (2.0 * (k[0] * m[0]).sqrt()),
            self.damping_y / (2.0 * (k[1] * m[1]).sqrt()),
        ]
    }

    /// Checks every value; errors name the `pendulum3d.<key>` and why.
    pub fn validate(&self) -> Result<(), SimError> {
        let positive = [
            ("mass", self.mass),
            ("length", self.length),
            ("inertia_xx", self.inertia_xx),
            ("inertia_yy", self.inertia_yy),
            ("inertia_zz", self.inertia_zz),
            ("gravity", self.gravity),
        ];
        for (key, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(SimError::invalid(
                    format!("pendulum3d.{key}"),
                    format!("must be finite and > 0, got {v:?}"),
                ));
            }
        }
        let non_negative = [
            ("ring_inertia", self.ring_inertia),
            ("damping_x", self.damping_x),
            ("damping_y", self.damping_y),
        ];
        for (key, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SimError::invalid(
                    format!("pendulum3d.{key}"),
                    format!("must be finite and >= 0, got {v:?}"),
                ));
            }
        }
        if self.pivot_offset.iter().any(|r| !r.is_finite()) {
            return Err(SimError::invalid(
                "pendulum3d.pivot_offset",
                format!("must be finite, got {:?}", self.pivot_offset),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults are the rig MODEL.md 7.6 describes: 2.19 Hz and zeta 0.30 per axis.
    #[test]
    fn default_rig_is_2_19_hz_and_zeta_0_30() {
        let p = Pendulum3d::default();
        for w in p.natural_frequencies(0.0) {
            assert!((w / std::f64::consts::TAU - 2.19).abs() < 0.005, "{w}");
        }
        for z in p.damping_ratios(0.0) {
            assert!((z - 0.30).abs() < 0.001, "{z}");
        }
    }

    /// In normalised form w_x = 1 / sqrt(b_x + b_ring) (the planar w_n = 1 / sqrt(b)).
    #[test]
    fn normalised_form_gives_the_same_frequencies() {
        let p = Pendulum3d {
            ring_inertia: 2e-5,
            inertia_yy: 1.1e-4,
            ..Pendulum3d::default()
        };
        let n = p.normalised();
        let w = p.natural_frequencies(0.0);
        assert!((w[0] - 1.0 / (n.b_x + n.b_ring).sqrt()).abs() < 1e-12);
        assert!((w[1] - 1.0 / n.b_y.sqrt()).abs() < 1e-12);
        let z = p.damping_ratios(0.0);
        assert!((z[1] - n.a_y / (2.0 * n.b_y.sqrt())).abs() < 1e-12);
    }

    /// The simulator's default rig and the core's default parameters are one pendulum.
    #[test]
    fn default_rig_normalises_to_the_core_default() {
        let (n, c) = (
            Pendulum3d::default().normalised(),
            CardanParams::<f64>::default(),
        );
        let (a, b) = (
            [n.a_x, n.a_y, n.b_x, n.b_y, n.b_z, n.b_ring, n.gravity],
            [c.a_x, c.a_y, c.b_x, c.b_y, c.b_z, c.b_ring, c.gravity],
        );
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-12 * y.abs(), "{a:?} {b:?}");
        }
        assert_eq!(n.c, c.c);
    }

    #[test]
    fn validate_names_the_key() {
        let p = Pendulum3d {
            inertia_zz: 0.0,
            ..Pendulum3d::default()
        };
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("pendulum3d.inertia_zz"), "{e}");
        assert!(Pendulum3d::default().validate().is_ok());
    }
}
