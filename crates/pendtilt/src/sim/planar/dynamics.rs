//! The exact planar pendulum of MODEL.md section 2.
//!
//! State: the pendulum's absolute angle beta (from the downward vertical, CCW positive) and
//! its rate. With f the specific force at the pivot P2 in world axes,
//!
//! ```text
//! I_p beta'' = -m_p l_p (f_x cos beta + f_y sin beta) + C phi',   phi = theta - beta
//! ```
//!
//! f collects gravity, the translational vibration of P1 and the motion of P2 about P1 at
//! distance l12 (see [`specific_force`]). Nothing is linearised or dropped, so with l12 = 0
//! and no vibration this is the paper's Eq (18), and with l12 != 0 it carries the coupling
//! term the paper's Lagrangian omits.

use pendtilt_core::model::PhysicalParams;

use super::motion::Kinematics;

/// The pendulum's constants, pre-divided for the right-hand side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pendulum {
    /// The parameters it was built from.
    pub params: PhysicalParams<f64>,
    ml_over_i: f64,
    c_over_i: f64,
}

impl Pendulum {
    /// From the rig parameters (assumed validated: inertia > 0).
    pub fn new(params: &PhysicalParams<f64>) -> Self {
        Self {
            params: *params,
            ml_over_i: params.mass * params.length / params.inertia,
            c_over_i: params.damping / params.inertia,
        }
    }

    /// beta'' for state (beta, beta'), specific force `f` at P2 in world axes \[m/s^2\] and
    /// body rate `omega` = theta' \[rad/s\].
    #[inline]
    pub fn beta_ddot(&self, beta: f64, beta_dot: f64, f: [f64; 2], omega: f64) -> f64 {
        let (s, c) = beta.sin_cos();
        -self.ml_over_i * (f[0] * c + f[1] * s) + self.c_over_i * (omega - beta_dot)
    }

    /// The right-hand side d/dt (beta, beta').
    #[inline]
    pub fn rhs(&self, y: [f64; 2], f: [f64; 2], omega: f64) -> [f64; 2] {
        [y[1], self.beta_ddot(y[0], y[1], f, omega)]
    }

    /// E = I_p phi'^2 / 2 + m_p g l_p (1 - cos(phi - theta)) \[J\]: conserved when C = 0 and
    /// the body is held still (MODEL.md section 2).
    pub fn energy(&self, phi: f64, phi_dot: f64, theta: f64) -> f64 {
        let p = &self.params;
        0.5 * p.inertia * phi_dot * phi_dot
            + p.mass * p.gravity * p.length * (1.0 - (phi - theta).cos())
    }
}

/// Specific force (acceleration minus gravity) at the point `r` of the body, in body axes
/// \[m/s^2\]. `r` is measured from P1 in body axes \[m\], `kin` = (theta, theta', theta''),
/// `a_p1` = translational acceleration of P1 in body axes, `(s, c)` = sin, cos of theta.
///
/// A point fixed on a body rotating about P1 accelerates by theta'' (k x r) - theta'^2 r,
/// and -g_vec = (0, g) in world axes is (g sin theta, g cos theta) in body axes.
#[inline]
pub fn specific_force(
    kin: &Kinematics,
    a_p1: [f64; 2],
    r: [f64; 2],
    (s, c): (f64, f64),
    g: f64,
) -> [f64; 2] {
    let [_, w, al] = *kin;
    [
        a_p1[0] - al * r[1] - w * w * r[0] + g * s,
        a_p1[1] + al * r[0] - w * w * r[1] + g * c,
    ]
}

/// A body-axes vector in world axes, given `(s, c)` = sin, cos of theta.
#[inline]
pub fn body_to_world(v: [f64; 2], (s, c): (f64, f64)) -> [f64; 2] {
    [v[0] * c - v[1] * s, v[0] * s + v[1] * c]
}

/// The paper's Eq (18) residual, C phi' + I_p (phi'' - theta'') + m_p g l_p sin(phi - theta)
/// \[N m\]: zero along any exact trajectory with l12 = 0 and no translational vibration.
pub fn eq18_residual(p: &PhysicalParams<f64>, phi: [f64; 3], theta: f64, theta_ddot: f64) -> f64 {
    p.damping * phi[1]
        + p.inertia * (phi[2] - theta_ddot)
        + p.mass * p.gravity * p.length * (phi[0] - theta).sin()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The world-axes form equals the body form of MODEL.md section 2 for a body rotating
    /// about a fixed P1, at arbitrary states.
    #[test]
    fn world_form_equals_body_form() {
        let p = PhysicalParams {
            pivot_offset: 0.3,
            ..PhysicalParams::default()
        };
        let pend = Pendulum::new(&p);
        for i in 0..50 {
            let x = i as f64;
            let (th, w, al) = (
                0.7 * (x * 0.3).sin(),
                2.0 * (x * 0.7).cos(),
                30.0 * (x * 1.3).sin(),
            );
            let (beta, beta_dot) = (0.9 * (x * 0.5).cos(), 3.0 * (x * 0.9).sin());
            let sc = th.sin_cos();
            let fb = specific_force(
                &[th, w, al],
                [0.0, 0.0],
                [0.0, p.pivot_offset],
                sc,
                p.gravity,
            );
            let bdd = pend.beta_ddot(beta, beta_dot, body_to_world(fb, sc), w);
            let phi = th - beta;
            let (phi_d, phi_dd) = (w - beta_dot, al - bdd);
            // I (phi'' - theta'') + C phi' + m g l sin(phi - theta)
            //   + m l l12 (theta'' cos phi - theta'^2 sin phi) = 0
            let r = p.inertia * (phi_dd - al)
                + p.damping * phi_d
                + p.mass * p.gravity * p.length * (phi - th).sin()
                + p.mass * p.length * p.pivot_offset * (al * phi.cos() - w * w * phi.sin());
            assert!(r.abs() < 1e-15, "residual {r}");
        }
    }
}
