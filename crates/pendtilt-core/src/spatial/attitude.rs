//! Roll, pitch and the world's up direction in body axes (MODEL.md 7.1), and the
//! inclination error (MODEL.md 7.9).
use crate::Real;

/// `u = R^T e_z = (-sin pitch, cos pitch sin roll, cos pitch cos roll)`: the world's up
/// direction in body axes for roll and pitch (any yaw). A still accelerometer reads `g u`.
#[inline]
pub fn up_from_roll_pitch<T: Real>(roll: T, pitch: T) -> [T; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    [-sp, cp * sr, cp * cr]
}

/// Roll and pitch `(atan2(u_y, u_z), atan2(-u_x, sqrt(u_y^2 + u_z^2)))` of a direction `u`
/// in body axes taken as up (any length; `u` = the specific force of a still body).
#[inline]
pub fn roll_pitch_from_up<T: Real>(u: [T; 3]) -> (T, T) {
    let roll = u[1].atan2(u[2]);
    let pitch = (-u[0]).atan2((u[1] * u[1] + u[2] * u[2]).sqrt());
    (roll, pitch)
}

/// The inclination error of MODEL.md 7.9: the angle between two up directions,
/// `atan2(|u1 x u2|, u1 . u2)` \[rad\] (independent of yaw; accurate at small angles,
/// where an `acos` of the dot product is not).
#[inline]
pub fn inclination_between<T: Real>(u1: [T; 3], u2: [T; 3]) -> T {
    let c = [
        u1[1] * u2[2] - u1[2] * u2[1],
        u1[2] * u2[0] - u1[0] * u2[2],
        u1[0] * u2[1] - u1[1] * u2[0],
    ];
    let s = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let d = u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2];
    s.atan2(d)
}

/// The inclination error between two (roll, pitch) pairs \[rad\] (MODEL.md 7.9).
#[inline]
pub fn inclination_error<T: Real>(roll: T, pitch: T, roll_ref: T, pitch_ref: T) -> T {
    inclination_between(
        up_from_roll_pitch(roll, pitch),
        up_from_roll_pitch(roll_ref, pitch_ref),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roll_and_pitch_round_trip_through_the_up_direction() {
        for &(r, p) in &[(0.3f64, -0.2f64), (-1.2, 0.7), (0.0, 1.5), (2.5, -0.4)] {
            let (r2, p2) = roll_pitch_from_up(up_from_roll_pitch(r, p));
            assert!((r2 - r).abs() < 1e-14 && (p2 - p).abs() < 1e-14, "{r} {p}");
        }
    }

    #[test]
    fn up_is_r_transpose_ez_for_zyx_angles() {
        // R = Rz(y) Ry(p) Rx(r); the third row of R is R^T e_z.
        let (r, p, y) = (0.4f64, -0.3f64, 1.1f64);
        let (sr, cr) = r.sin_cos();
        let (sp, cp) = p.sin_cos();
        let _ = y; // R's third row does not depend on yaw.
        let row3 = [-sp, cp * sr, cp * cr];
        assert_eq!(up_from_roll_pitch(r, p), row3);
        // Positive roll lowers the right side (-y): the up direction tilts to +y in body
        // axes; positive pitch lowers the nose: up tilts to -x.
        assert!(up_from_roll_pitch(0.1, 0.0)[1] > 0.0);
        assert!(up_from_roll_pitch(0.0, 0.1)[0] < 0.0);
    }

    #[test]
    fn inclination_error_is_yaw_free_and_small_angle_consistent() {
        // Small errors: sqrt((cos pitch d_roll)^2 + d_pitch^2) (MODEL.md 7.9).
        let (r, p) = (0.2f64, 0.6f64);
        let (dr, dp) = (1e-4f64, -2e-4f64);
        let e = inclination_error(r + dr, p + dp, r, p);
        let approx = ((p.cos() * dr).powi(2) + dp * dp).sqrt();
        assert!((e - approx).abs() < 1e-3 * approx, "{e} {approx}");
        assert_eq!(inclination_error(r, p, r, p), 0.0);
        // A pure pitch error of 10 deg is 10 deg.
        let e = inclination_error(0.0f64, 0.1745, 0.0, 0.0);
        assert!((e - 0.1745).abs() < 1e-12);
    }
}
