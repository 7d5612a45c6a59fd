//! Integrating the Cardan pendulum under a prescribed body motion (MODEL.md 7.3).
//!
//! The state is u = (a + roll, b + pitch) and u', as 7.3 recommends: u is smooth under
//! angular vibration of the body (under pure roll u_x is the planar beta, so this is the
//! planar simulator's state). RK4 from [`crate::sim::planar::integrator`] at `substeps` steps per
//! sample; the body's kinematics are evaluated once per node (start, middle, end of each
//! step), exactly as the planar simulator does, so a pure-roll run reproduces it (7.4).

use crate::sim::planar::integrator::{rk4_step, Node};
use crate::sim::planar::SimError;

use super::dynamics::{specific_force_at, JointState};
use super::motion::{BodyKinematics, BodyMotion};
use super::params::Pendulum3d;

/// The exact state behind one sample (MODEL.md 7.3 quantities, before any sensor model).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Truth3d {
    /// t_k = k / rate \[s\].
    pub t: f64,
    /// The body's kinematics at t.
    pub body: BodyKinematics,
    /// The joint angles and rates at t.
    pub joint: JointState,
    /// (a'', b'') at t \[rad/s^2\].
    pub joint_acc: [f64; 2],
    /// Specific force at the pivot P2, body axes \[m/s^2\].
    pub f_pivot: [f64; 3],
    /// True forward speed of the vehicle's speed point O (MODEL.md 7.7) \[m/s\].
    pub speed: f64,
}

impl Truth3d {
    /// The true encoder angles (phi_x, phi_y) = (-a, -b) \[rad\] (MODEL.md 7.2).
    pub fn encoders(&self) -> [f64; 2] {
        self.joint.encoders()
    }
}

/// A running 3-D simulation: an iterator over [`Truth3d`] rows at `rate`.
#[derive(Debug, Clone)]
pub struct Simulator3d<M: BodyMotion> {
    pend: Pendulum3d,
    motion: M,
    rate: f64,
    substeps: usize,
    rows: u64,
    k: u64,
    /// (u_x, u_y, u_x', u_y').
    y: [f64; 4],
    nodes: Vec<BodyKinematics>,
}

/// (u, u') from the joint state and the body's Euler angles.
fn to_u(s: &JointState, e: &[[f64; 3]; 3]) -> [f64; 4] {
    [
        s.a + e[0][0],
        s.b + e[1][0],
        s.a_dot + e[0][1],
        s.b_dot + e[1][1],
    ]
}

/// The joint state from (u, u') and the body's Euler angles.
fn from_u(y: &[f64; 4], e: &[[f64; 3]; 3]) -> JointState {
    JointState {
        a: y[0] - e[0][0],
        b: y[1] - e[1][0],
        a_dot: y[2] - e[0][1],
        b_dot: y[3] - e[1][1],
    }
}

impl<M: BodyMotion> Simulator3d<M> {
    /// A run of `duration` s at `rate` Hz with `substeps` RK4 steps per sample, the
    /// pendulum starting "hanging still in the world" (MODEL.md 7.3).
    pub fn new(
        pend: Pendulum3d,
        motion: M,
        rate: f64,
        substeps: u32,
        duration: f64,
    ) -> Result<Self, SimError> {
        pend.validate()?;
        if !(rate.is_finite() && rate > 0.0) {
            return Err(SimError::invalid(
                "rate",
                format!("must be > 0 Hz, got {rate:?}"),
            ));
        }
        if !(1..=10_000).contains(&substeps) {
            return Err(SimError::invalid(
                "substeps",
                format!("must be in 1..=10000, got {substeps}"),
            ));
        }
        if !(duration.is_finite() && duration >= 0.0 && duration * rate <= 1e11) {
            return Err(SimError::invalid(
                "duration",
                format!("must be >= 0 s and at most 1e11 rows, got {duration:?} s"),
            ));
        }
        let (k, m) = (pend.stiffness(0.0), pend.inertia(0.0));
        let c = [pend.damping_x, pend.damping_y];
        let lambda = (0..2)
            .map(|i| crate::sim::planar::integrator::fastest_mode(k[i] / m[i], c[i] / m[i]))
            .fold(0.0, f64::max);
        crate::sim::planar::integrator::check_step(lambda, rate, substeps)?;
        let k0 = motion.kinematics(0.0, pend.gravity);
        let start = JointState::hanging_still(k0.euler[0][0], k0.euler[1][0], k0.w);
        Ok(Self {
            pend,
            motion,
            rate,
            substeps: substeps as usize,
            rows: (duration * rate).round() as u64,
            k: 0,
            y: to_u(&start, &k0.euler),
            nodes: vec![k0; 2 * substeps as usize + 1],
        })
    }

    /// Starts from the joint state `s` instead (free swings, energy checks). Call before
    /// the first row.
    pub fn with_joint_state(mut self, s: JointState) -> Self {
        let k0 = self.motion.kinematics(0.0, self.pend.gravity);
        self.y = to_u(&s, &k0.euler);
        self
    }

    /// The pendulum in use.
    pub fn pendulum(&self) -> &Pendulum3d {
        &self.pend
    }

    /// d/dt (u, u') at one node.
    fn rhs(pend: &Pendulum3d, y: [f64; 4], k: &BodyKinematics) -> [f64; 4] {
        let s = from_u(&y, &k.euler);
        let f = specific_force_at(k.f_p1, k.w, k.wd, pend.pivot_offset);
        let [add, bdd] = pend.joint_accelerations(&s, k.w, k.wd, f);
        [y[2], y[3], add + k.euler[0][2], bdd + k.euler[1][2]]
    }

    fn step(&mut self) -> Truth3d {
        let t0 = self.k as f64 / self.rate;
        let h = 1.0 / (self.rate * self.substeps as f64);
        let half = 0.5 * h;
        let g = self.pend.gravity;
        self.motion.fill(t0, half, g, &mut self.nodes);
        // The row at t0, from the state before this interval is integrated.
        let body = self.nodes[0];
        let joint = from_u(&self.y, &body.euler);
        let f_pivot = specific_force_at(body.f_p1, body.w, body.wd, self.pend.pivot_offset);
        let joint_acc = self
            .pend
            .joint_accelerations(&joint, body.w, body.wd, f_pivot);
        for i in 0..self.substeps {
            let j = 2 * i;
            let (pend, nodes) = (&self.pend, &self.nodes);
            self.y = rk4_step(self.y, h, |node, y| {
                let jj = match node {
                    Node::Start => j,
                    Node::Mid => j + 1,
                    Node::End => j + 2,
                };
                Self::rhs(pend, y, &nodes[jj])
            });
        }
        self.k += 1;
        Truth3d {
            t: t0,
            body,
            joint,
            joint_acc,
            f_pivot,
            speed: self.motion.speed(t0, g),
        }
    }
}

impl<M: BodyMotion> Iterator for Simulator3d<M> {
    type Item = Truth3d;

    fn next(&mut self) -> Option<Truth3d> {
        (self.k < self.rows).then(|| self.step())
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = usize::try_from(self.rows - self.k).unwrap_or(usize::MAX);
        (left, Some(left))
    }
}
