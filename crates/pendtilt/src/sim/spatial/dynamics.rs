//! The exact equations of motion of the Cardan pendulum (MODEL.md 7.3).
//!
//! Everything is in body axes: the body rate w, its derivative wd and the specific force f
//! at the pivot P2 are all the joint equations need; no world-frame quantity enters. The
//! mass matrix is diagonal, diag(J_ring + Ia, Iyy), so a'' and b'' are explicit.

use super::params::Pendulum3d;

/// a x b.
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Specific force at the body point P + `r` (body axes) from the specific force `f_p` at P,
/// the body rate `w` and its derivative `wd` (MODEL.md 7.1):
/// f_Q = f_P + wd x r + w x (w x r) \[m/s^2\].
#[inline]
pub fn specific_force_at(f_p: [f64; 3], w: [f64; 3], wd: [f64; 3], r: [f64; 3]) -> [f64; 3] {
    let t = cross(wd, r);
    let c = cross(w, cross(w, r));
    [
        f_p[0] + t[0] + c[0],
        f_p[1] + t[1] + c[1],
        f_p[2] + t[2] + c[2],
    ]
}

/// The joint angles and rates: a (outer ring about body x), b (pendulum about the ring's y
/// axis) \[rad\] and a', b' \[rad/s\] (MODEL.md 7.2). The encoders read phi_x = -a,
/// phi_y = -b.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointState {
    /// a \[rad\].
    pub a: f64,
    /// b \[rad\].
    pub b: f64,
    /// a' \[rad/s\].
    pub a_dot: f64,
    /// b' \[rad/s\].
    pub b_dot: f64,
}

impl JointState {
    /// The state "hanging still in the world" of MODEL.md 7.3 on a body with roll `roll`,
    /// pitch `pitch` and body rate `w`: a = -roll, b = -pitch, and the pendulum's rate about
    /// its own x and y axes zero: b' = -u2, a' = -(cb w_x - sb u3) / cb (its rate about its
    /// own z axis follows the body's).
    pub fn hanging_still(roll: f64, pitch: f64, w: [f64; 3]) -> Self {
        let (a, b) = (-roll, -pitch);
        let (sa, ca) = a.sin_cos();
        let (sb, cb) = b.sin_cos();
        let u2 = ca * w[1] + sa * w[2];
        let u3 = -sa * w[1] + ca * w[2];
        Self {
            a,
            b,
            a_dot: -(cb * w[0] - sb * u3) / cb,
            b_dot: -u2,
        }
    }

    /// The encoder angles (phi_x, phi_y) = (-a, -b) \[rad\] (MODEL.md 7.2).
    pub fn encoders(&self) -> [f64; 2] {
        [-self.a, -self.b]
    }
}

impl Pendulum3d {
    /// (a'', b'') \[rad/s^2\] from the joint state `s`, the body rate `w` \[rad/s\], its
    /// derivative `wd` \[rad/s^2\] and the specific force `f` at the pivot P2 \[m/s^2\], all
    /// body axes: the explicit form of MODEL.md 7.3, term by term.
    #[inline]
    pub fn joint_accelerations(
        &self,
        s: &JointState,
        w: [f64; 3],
        wd: [f64; 3],
        f: [f64; 3],
    ) -> [f64; 2] {
        let (ixx, iyy, izz, jr) = (
            self.inertia_xx,
            self.inertia_yy,
            self.inertia_zz,
            self.ring_inertia,
        );
        let ml = self.mass * self.length;
        let (sa, ca) = s.a.sin_cos();
        let (sb, cb) = s.b.sin_cos();
        let (ad, bd) = (s.a_dot, s.b_dot);
        // w, wd and f in outer-ring axes.
        let u2 = ca * w[1] + sa * w[2];
        let u3 = -sa * w[1] + ca * w[2];
        let v2 = ca * wd[1] + sa * wd[2];
        let v3 = -sa * wd[1] + ca * wd[2];
        let h1 = f[0];
        let h2 = ca * f[1] + sa * f[2];
        let h3 = -sa * f[1] + ca * f[2];
        let p = w[0] + ad;
        // The pendulum's rate in pendulum axes.
        let w1 = cb * p - sb * u3;
        let w2 = u2 + bd;
        let w3 = sb * p + cb * u3;
        let ia = ixx * cb * cb + izz * sb * sb;

        let rhs_a = -self.damping_x * ad
            - (jr + ia) * wd[0]
            - ml * cb * h2
            - (izz - ixx) * sb * cb * (bd * p + v3 - ad * u2)
            + ia * bd * u3
            - w2 * (cb * (izz - iyy) * w3 + sb * (iyy - ixx) * w1);
        let rhs_b = -self.damping_y * bd - iyy * (v2 + ad * u3) - (ixx - izz) * w1 * w3
            + ml * (cb * h1 - sb * h3);
        [rhs_a / (jr + ia), rhs_b / iyy]
    }

    /// The pendulum's angular velocity in pendulum axes, W = Q^T w + nu, Q = Rx(a) Ry(b),
    /// nu = (a' cb, b', a' sb) (MODEL.md 7.3) \[rad/s\].
    pub fn pendulum_rate(&self, s: &JointState, w: [f64; 3]) -> [f64; 3] {
        let (sa, ca) = s.a.sin_cos();
        let (sb, cb) = s.b.sin_cos();
        let p = w[0] + s.a_dot;
        let u3 = -sa * w[1] + ca * w[2];
        [
            cb * p - sb * u3,
            ca * w[1] + sa * w[2] + s.b_dot,
            sb * p + cb * u3,
        ]
    }

    /// Kinetic energy of the pendulum and the ring \[J\]: W.I W / 2 + J_ring (w_x + a')^2 / 2
    /// (the ring's other two inertias are taken as zero: they drop out of the equations,
    /// MODEL.md 7.2, and add only a function of the prescribed body rate).
    pub fn kinetic_energy(&self, s: &JointState, w: [f64; 3]) -> f64 {
        let wp = self.pendulum_rate(s, w);
        let p = w[0] + s.a_dot;
        0.5 * (self.inertia_xx * wp[0] * wp[0]
            + self.inertia_yy * wp[1] * wp[1]
            + self.inertia_zz * wp[2] * wp[2]
            + self.ring_inertia * p * p)
    }

    /// Potential of the pendulum in a uniform specific-force field `f` at the pivot (body
    /// axes) \[J\]: m (Q r_c) . f with r_c = (0, 0, -l); on a body at rest f = g u and this is
    /// m g z_cm relative to P2. Conserved with the kinetic energy when the body is still and
    /// there is no damping.
    pub fn potential_energy(&self, s: &JointState, f: [f64; 3]) -> f64 {
        let (sa, ca) = s.a.sin_cos();
        let (sb, cb) = s.b.sin_cos();
        // Q e_z = Rx(a) (sb, 0, cb).
        let qz = [sb, -sa * cb, ca * cb];
        -self.mass * self.length * (qz[0] * f[0] + qz[1] * f[1] + qz[2] * f[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hanging-still start has zero pendulum rate about its own x and y axes.
    #[test]
    fn hanging_still_has_no_swing_rate() {
        let p = Pendulum3d::default();
        let w = [0.3, -0.7, 1.1];
        let s = JointState::hanging_still(0.4, -0.3, w);
        let wp = p.pendulum_rate(&s, w);
        assert!(wp[0].abs() < 1e-15 && wp[1].abs() < 1e-15, "{wp:?}");
    }

    /// f_Q from a point at r and back from -r returns to f_P (rigid-body field).
    #[test]
    fn specific_force_transfer_round_trip() {
        let (w, wd) = ([0.3, -1.2, 0.8], [4.0, 2.5, -3.0]);
        let f = [0.1, 9.0, -2.0];
        let r = [0.2, -0.1, 0.5];
        let q = specific_force_at(f, w, wd, r);
        let back = specific_force_at(q, w, wd, r.map(|x| -x));
        for i in 0..3 {
            assert!((back[i] - f[i]).abs() < 1e-14);
        }
        // Pure spin about z at 2 rad/s, r = 1 m along x: centripetal -4 m/s^2 along x.
        let c = specific_force_at([0.0; 3], [0.0, 0.0, 2.0], [0.0; 3], [1.0, 0.0, 0.0]);
        assert_eq!(c, [-4.0, 0.0, 0.0]);
    }
}
