//! The two-axis pendulum on a Cardan joint in the normalised form of MODEL.md 7.3 (both
//! joint equations divided by m g l), for the model-based filters.
//!
//! The outer ring turns about body x by `a`, the pendulum about the ring's y axis by `b`;
//! the encoders read `phi_x = -a`, `phi_y = -b`. The inputs are the body rate `w`, its
//! derivative `wd` and the specific force `f` at the pivot P2, all in body axes; the mass
//! matrix is diagonal, so `a''` and `b''` are explicit.
use crate::Real;

/// The normalised parameters of MODEL.md 7.3: per axis the planar a, b, c.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct CardanParams<T> {
    /// `a_x = C_x / (m g l)` \[s\]: outer-joint damping.
    pub a_x: T,
    /// `a_y = C_y / (m g l)` \[s\]: inner-joint damping.
    pub a_y: T,
    /// `b_x = Ixx / (m g l)` \[s^2\] (Ixx about the pivot, pendulum axes).
    pub b_x: T,
    /// `b_y = Iyy / (m g l)` \[s^2\].
    pub b_y: T,
    /// `b_z = Izz / (m g l)` \[s^2\] (small, > 0).
    pub b_z: T,
    /// `b_ring = J_ring / (m g l)` \[s^2\] (outer ring about body x).
    pub b_ring: T,
    /// `c = r12 / g` \[s^2\]: the pivot P2 - the IMU point P1, body axes, over g.
    pub c: [T; 3],
    /// g \[m/s^2\] (the specific force enters as f / g).
    pub gravity: T,
}

impl<T: Real> Default for CardanParams<T> {
    /// The rig of MODEL.md 7.6 (m = 0.05 kg, l = 0.05 m, Ixx = Iyy = 1.3e-4, Izz = 1e-6
    /// kg m^2, no ring inertia, C = 1.07e-3 N m s/rad, no pivot offset): f_n = 2.19 Hz and
    /// zeta = 0.30 on each axis.
    fn default() -> Self {
        let g = 9.80665;
        let mgl = 0.05 * g * 0.05;
        Self {
            a_x: T::lit(1.07e-3 / mgl),
            a_y: T::lit(1.07e-3 / mgl),
            b_x: T::lit(1.3e-4 / mgl),
            b_y: T::lit(1.3e-4 / mgl),
            b_z: T::lit(1.0e-6 / mgl),
            b_ring: T::zero(),
            c: [T::zero(); 3],
            gravity: T::lit(g),
        }
    }
}

/// Joint angles and rates: `a` (outer ring about body x), `b` (pendulum about the ring's
/// y axis) \[rad\] and their rates \[rad/s\] (MODEL.md 7.2).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Joints<T> {
    /// a \[rad\].
    pub a: T,
    /// b \[rad\].
    pub b: T,
    /// a' \[rad/s\].
    pub a_dot: T,
    /// b' \[rad/s\].
    pub b_dot: T,
}

/// Sines and cosines of the joint angles a and b.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointTrig<T> {
    /// sin a.
    pub sa: T,
    /// cos a.
    pub ca: T,
    /// sin b.
    pub sb: T,
    /// cos b.
    pub cb: T,
}

impl<T: Real> JointTrig<T> {
    /// Of the angles `a`, `b`.
    #[inline]
    pub fn of(a: T, b: T) -> Self {
        let (sa, ca) = a.sin_cos();
        let (sb, cb) = b.sin_cos();
        Self { sa, ca, sb, cb }
    }

    /// Of `a + d_a` and `b + d_b` for small shifts given by their sines and cosines.
    #[inline]
    pub fn shifted(&self, (sda, cda): (T, T), (sdb, cdb): (T, T)) -> Self {
        Self {
            sa: self.sa * cda + self.ca * sda,
            ca: self.ca * cda - self.sa * sda,
            sb: self.sb * cdb + self.cb * sdb,
            cb: self.cb * cdb - self.sb * sdb,
        }
    }
}

impl<T: Real> CardanParams<T> {
    /// The same parameters in another scalar type.
    pub fn cast<U: Real>(&self) -> CardanParams<U> {
        let c = |x: T| U::lit(x.to_f64());
        CardanParams {
            a_x: c(self.a_x),
            a_y: c(self.a_y),
            b_x: c(self.b_x),
            b_y: c(self.b_y),
            b_z: c(self.b_z),
            b_ring: c(self.b_ring),
            c: self.c.map(c),
            gravity: c(self.gravity),
        }
    }

    /// Small-angle natural frequencies `(w_x, w_y)` \[rad/s\] on a level body:
    /// `1 / sqrt(b_x + b_ring)`, `1 / sqrt(b_y)` (MODEL.md 7.2).
    pub fn natural_frequencies(&self) -> [T; 2] {
        [
            T::one() / (self.b_x + self.b_ring).sqrt(),
            T::one() / self.b_y.sqrt(),
        ]
    }

    /// `(a'', b'')` \[rad/s^2\] of MODEL.md 7.3, normalised, from the joint state `s`, the
    /// body rate `w`, its derivative `wd` and the specific force `f` at the pivot, body
    /// axes.
    #[inline]
    pub fn joint_accelerations(&self, s: &Joints<T>, w: [T; 3], wd: [T; 3], f: [T; 3]) -> [T; 2] {
        let trig = JointTrig::of(s.a, s.b);
        self.joint_accelerations_with(&trig, s.a_dot, s.b_dot, w, wd, f)
    }

    /// [`Self::joint_accelerations`] with the joint angles' sines and cosines given (a
    /// filter that differentiates it by perturbing the angles shifts them by angle
    /// addition instead of calling the trigonometry again).
    #[inline]
    pub fn joint_accelerations_with(
        &self,
        trig: &JointTrig<T>,
        ad: T,
        bd: T,
        w: [T; 3],
        wd: [T; 3],
        f: [T; 3],
    ) -> [T; 2] {
        let (bx, by, bz, br) = (self.b_x, self.b_y, self.b_z, self.b_ring);
        let inv_g = T::one() / self.gravity;
        let JointTrig { sa, ca, sb, cb } = *trig;
        // w, wd and f in outer-ring axes.
        let u2 = ca * w[1] + sa * w[2];
        let u3 = -sa * w[1] + ca * w[2];
        let v2 = ca * wd[1] + sa * wd[2];
        let v3 = -sa * wd[1] + ca * wd[2];
        let h1 = f[0] * inv_g;
        let h2 = (ca * f[1] + sa * f[2]) * inv_g;
        let h3 = (-sa * f[1] + ca * f[2]) * inv_g;
        let p = w[0] + ad;
        // The pendulum's rate in pendulum axes.
        let w1 = cb * p - sb * u3;
        let w2 = u2 + bd;
        let w3 = sb * p + cb * u3;
        let ia = bx * cb * cb + bz * sb * sb;
        let rhs_a = -self.a_x * ad
            - (br + ia) * wd[0]
            - cb * h2
            - (bz - bx) * sb * cb * (bd * p + v3 - ad * u2)
            + ia * bd * u3
            - w2 * (cb * (bz - by) * w3 + sb * (by - bx) * w1);
        let rhs_b =
            -self.a_y * bd - by * (v2 + ad * u3) - (bx - bz) * w1 * w3 + (cb * h1 - sb * h3);
        [rhs_a / (br + ia), rhs_b / by]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::attitude::up_from_roll_pitch;

    /// Hanging still on a still body with roll r and pitch p: a = -r, b = -p is an
    /// equilibrium (MODEL.md 7.2).
    #[test]
    fn the_hanging_pendulum_is_in_equilibrium_for_any_tilt() {
        let c = CardanParams::<f64>::default();
        for &(r, p) in &[(0.3, -0.2), (-0.8, 0.5), (0.0, 0.0)] {
            let f = up_from_roll_pitch(r, p).map(|v| v * c.gravity);
            let s = Joints {
                a: -r,
                b: -p,
                a_dot: 0.0,
                b_dot: 0.0,
            };
            let acc = c.joint_accelerations(&s, [0.0; 3], [0.0; 3], f);
            assert!(acc[0].abs() < 1e-12 && acc[1].abs() < 1e-12, "{acc:?}");
        }
    }

    /// Small deflections on a level body oscillate at the natural frequencies: the
    /// restoring acceleration per radian is -w_n^2.
    #[test]
    fn small_deflections_restore_at_the_natural_frequencies() {
        let c = CardanParams::<f64>::default();
        let f = [0.0, 0.0, c.gravity];
        let w = c.natural_frequencies();
        // 2.19 Hz, as MODEL.md 7.6 says of its defaults.
        assert!((w[0] / core::f64::consts::TAU - 2.19).abs() < 0.01, "{w:?}");
        let e = 1e-6;
        let ax = c.joint_accelerations(
            &Joints {
                a: e,
                ..Default::default()
            },
            [0.0; 3],
            [0.0; 3],
            f,
        );
        let by = c.joint_accelerations(
            &Joints {
                b: e,
                ..Default::default()
            },
            [0.0; 3],
            [0.0; 3],
            f,
        );
        assert!(
            (ax[0] / e + w[0] * w[0]).abs() < 1e-4 * w[0] * w[0],
            "{ax:?}"
        );
        assert!(
            (by[1] / e + w[1] * w[1]).abs() < 1e-4 * w[1] * w[1],
            "{by:?}"
        );
        // Damping: a rate alone decelerates by a_x / b_x per rad/s.
        let d = c.joint_accelerations(
            &Joints {
                a_dot: 1.0,
                ..Default::default()
            },
            [0.0; 3],
            [0.0; 3],
            f,
        );
        assert!((d[0] + c.a_x / c.b_x).abs() < 1e-12, "{d:?}");
    }
}
