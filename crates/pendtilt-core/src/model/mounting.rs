//! Where the sensors sit on the body (MODEL.md 7.6 `[mounting]`), and the rigid-body
//! kinematics that carry a known motion from one body point to another.
//!
//! For two points of a rigid body, `f_Q = f_P + wd x r_PQ + w x (w x r_PQ)` (MODEL.md 7.1):
//! the specific force at the pendulum's pivot or at the accelerometer follows from the one
//! at the point O whose motion is known, the body rate `w` and its derivative `wd`.
use crate::Real;
use nalgebra::Vector3;

/// Sensor positions relative to P1 (the gyro's point), body axes \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields, default)
)]
pub struct Mounting<T> {
    /// Accelerometer position - P1. Default 0 (the accelerometer at P1).
    pub accel_at: [T; 3],
    /// O - P1: the point whose forward speed the `speed` column gives. Without a speed the
    /// estimators take O as the point the body turns about, not accelerating (a standing
    /// scooter on its stand, a ship about its centre of roll). Default 0 (P1).
    pub speed_at: [T; 3],
}

impl<T: Real> Default for Mounting<T> {
    fn default() -> Self {
        Self {
            accel_at: [T::zero(); 3],
            speed_at: [T::zero(); 3],
        }
    }
}

impl<T: Real> Mounting<T> {
    /// The same positions in another scalar type.
    pub fn cast<U: Real>(&self) -> Mounting<U> {
        let c = |x: T| U::lit(x.to_f64());
        Mounting {
            accel_at: self.accel_at.map(c),
            speed_at: self.speed_at.map(c),
        }
    }

    /// `point - O` for a point given relative to P1 \[m\].
    #[inline]
    pub fn from_centre(&self, point: [T; 3]) -> Vector3<T> {
        Vector3::new(
            point[0] - self.speed_at[0],
            point[1] - self.speed_at[1],
            point[2] - self.speed_at[2],
        )
    }
}

/// The specific force added between two body points `r` apart (`r = Q - P`, body axes):
/// `wd x r + w x (w x r)` (MODEL.md 7.1).
#[inline]
pub fn lever_arm<T: Real>(w: &Vector3<T>, wd: &Vector3<T>, r: &Vector3<T>) -> Vector3<T> {
    wd.cross(r) + w.cross(&w.cross(r))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body spinning at w about z, a point 2 m out on x: the centripetal specific force
    /// is -w^2 r (towards the axis); an angular acceleration adds wd r along y.
    #[test]
    fn the_lever_arm_is_centripetal_plus_tangential() {
        let w = Vector3::new(0.0, 0.0, 3.0);
        let wd = Vector3::new(0.0, 0.0, 0.5);
        let r = Vector3::new(2.0, 0.0, 0.0);
        let f = lever_arm(&w, &wd, &r);
        assert!((f - Vector3::new(-18.0, 1.0, 0.0)).norm() < 1e-12, "{f}");
        let m = Mounting {
            accel_at: [0.1, 0.0, 0.0],
            speed_at: [0.0, 0.0, -0.25],
        };
        assert_eq!(m.from_centre(m.accel_at), Vector3::new(0.1, 0.0, 0.25));
    }
}
