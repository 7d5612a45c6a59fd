//! The process model: the gyro drives the attitude, the pendulum's equations of motion
//! (MODEL.md 7.3) drive the joints.
//!
//! The joint state is `(a, b, p, r)`: the angles, and the pendulum's absolute rates about
//! the joint axes, `p = w_x + a'` (the ring about body x) and `r = u2 + b'` (the pendulum
//! about the inner axis; `u2 = cos a w_y + sin a w_z`). In these rates the body's angular
//! acceleration `wd` drops out of the equations of motion (`p' = a'' + wd_x`,
//! `r' = b'' + v2 + a' u3`, and the `wd` terms of 7.3 are exactly these) except for the
//! small cross-inertia term `(Izz - Ixx) sin b cos b v3`. So the gyro's reading, vibration
//! and all, enters the joints mainly through the kinematics `a' = p - w_x`, `b' = r - u2`;
//! the encoders are never differentiated.
//!
//! The pivot's specific force is `g u` (the world's up direction in body axes, from the
//! attitude), plus O's acceleration `v' x_b + w_p x (v x_b)` from O's forward speed `v`
//! and its rate `v'`, both states (a vehicle braking and turning; held at zero
//! without a `speed` column: O not accelerating), plus the lever arm `wd x r + w x (w x r)` from O (`[mounting] speed_at`,
//! the point the body turns about) to the pivot, `r = P2 - O`: a scooter on its stand
//! swinging about a point 0.25 m below the sensors moves the pivot by `wd x r`, at 0.9 Hz
//! and a few degrees an apparent tilt of a degree. `wd` and the path's turn rate `w_p` are
//! smoothed from the gyro and come in with it ([`Drive`]); what is left of the pivot's
//! acceleration is unknown and is the process noise of `p` and `r`.
//!
//! `v'` is a random walk (white jerk, [`ProcessNoise::jerk`]) and `v` its integral; the
//! `speed` column measures `v` ([`super::measurement::Speed`]). So the filter takes O's
//! acceleration from the speed only where the speed knows it (slowly) and from the
//! pendulum against the gyro elsewhere (the pendulum reads tilt plus acceleration, the
//! gyro the tilt's changes), the way an inertial navigator is aided by a velocity: the
//! speed's derivative alone let its noise through as a longitudinal force (a standing
//! scooter's speed column is noise alone), or lagged the braking.
//!
//! One step of `h`: the attitude turns by `exp((gyro - bias) h)`; the joints take a
//! semi-implicit Euler step (rates first, then angles with the new rates). The Jacobian
//! of the joint step is exact in the up direction (it enters linearly) and taken by
//! forward differences in the working precision for the joints and the body rate (step
//! `sqrt(eps)`): 7.3 has some forty partial derivatives, and the filter needs them to a
//! few digits only; a test checks them against the step itself.
use super::state::{State, A, ACC, B, BIAS, N, P, R, ROT, V};
use crate::engine::{Cov, ProcessModel};
use crate::spatial::cardan::{CardanParams, JointTrig};
use crate::spatial::mounting::lever_arm;
use crate::Real;
use nalgebra::{Matrix3, SMatrix, UnitQuaternion, Vector2, Vector3, Vector4};

/// Continuous-time process noise densities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcessNoise<T> {
    /// Gyro white-noise density [rad/s/sqrt(Hz)]: how the attitude and the joint angles
    /// diffuse between encoder readings.
    pub gyro: T,
    /// Gyro bias random-walk density [rad/s/sqrt(s)].
    pub bias: T,
    /// Density of the pendulum's unmodelled angular acceleration per axis
    /// [rad/s^2/sqrt(Hz)]: the pivot's unknown linear acceleration over `g b`.
    pub joints: [T; 2],
    /// Density of O's jerk along body x [m/s^3/sqrt(Hz)]: how fast the vehicle's
    /// forward acceleration `v'` may change.
    pub jerk: T,
}

/// The spatial process model (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CardanProcess<T: Real> {
    /// The pendulum.
    pub params: CardanParams<T>,
    /// Process noise densities.
    pub noise: ProcessNoise<T>,
    /// The pivot P2 from the point O the body turns about, `P2 - O`, body axes \[m\].
    pub pivot_from_centre: Vector3<T>,
}

/// What drives the process over a step: the gyro's reading, the body's angular
/// acceleration (the gyro's smoothed derivative), body axes, and the gyro smoothed to the
/// path's and the body's slow rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive<T: Real> {
    /// The gyro's reading, bias not removed \[rad/s\].
    pub gyro: Vector3<T>,
    /// The body's angular acceleration `wd` \[rad/s^2\].
    pub angular_accel: Vector3<T>,
    /// The gyro's reading low-passed to the rate at which the vehicle's path turns, bias
    /// not removed \[rad/s\]: the body's faster rotations (suspension, wobble) do not
    /// turn O's velocity.
    pub path_gyro: Vector3<T>,
    /// The gyro's reading low-passed at 5 Hz, bias not removed \[rad/s\]: the body's slow
    /// rate, at which the z bias's lever-arm term is taken
    /// ([`CardanProcess::z_bias_partials`]).
    pub slow_gyro: Vector3<T>,
    /// The filter's z bias before the step \[rad/s\] (its mean's): the joints' kinematics
    /// and the pendulum's Coriolis terms take the body's z rate at it, so that a state whose
    /// z bias departs from it (a UKF's sigma point) moves the joints only through the
    /// attitude and the specific force, as the EKF's Jacobian has it
    /// ([`CardanProcess::z_bias_partials`]).
    pub z_bias: T,
}

impl<T: Real> Drive<T> {
    /// O's acceleration in body axes for the body rate `w` (bias removed) and O's forward
    /// speed and its rate `travel = (v, v')`: `v' x_b + w_p x (v x_b)`, the longitudinal
    /// and the centripetal acceleration of a vehicle whose point O moves along body x,
    /// with `w_p = w + path_gyro - gyro` the rate at which its path turns (the
    /// same bias removed).
    #[inline]
    pub fn centre_accel(&self, w: &Vector3<T>, travel: &Vector2<T>) -> Vector3<T> {
        self.centre_accel_per_speed(w) * travel[0] + Vector3::new(travel[1], T::zero(), T::zero())
    }

    /// The derivative of [`Self::centre_accel`] with respect to `v`: `w_p x x_b`.
    #[inline]
    pub fn centre_accel_per_speed(&self, w: &Vector3<T>) -> Vector3<T> {
        let wp = w + self.path_gyro - self.gyro;
        Vector3::new(T::zero(), wp[2], -wp[1])
    }
}

/// `v x`, the cross-product matrix.
#[inline]
pub(crate) fn skew<T: Real>(v: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -v[2], v[1], v[2], z, -v[0], -v[1], v[0], z)
}

impl<T: Real> CardanProcess<T> {
    /// One semi-implicit Euler step of the joints `j = (a, b, p, r)` over `h` for the
    /// bias-corrected body rate `w`, the drive `d` (for the angular acceleration), the up
    /// direction `u` (body axes) and O's speed and its rate `travel`.
    #[inline]
    pub fn joint_step(
        &self,
        j: &Vector4<T>,
        w: &Vector3<T>,
        d: &Drive<T>,
        (u, travel): (&Vector3<T>, &Vector2<T>),
        h: T,
    ) -> Vector4<T> {
        self.joint_step_with(&JointTrig::of(j[0], j[1]), j, w, d, (u, travel), h)
    }

    /// [`Self::joint_step`] with the sines and cosines of `j`'s angles given.
    #[inline]
    fn joint_step_with(
        &self,
        trig: &JointTrig<T>,
        j: &Vector4<T>,
        w: &Vector3<T>,
        d: &Drive<T>,
        ut: (&Vector3<T>, &Vector2<T>),
        h: T,
    ) -> Vector4<T> {
        self.joint_step_in(trig, j, w, d, &self.pivot_force(w, d, ut), h)
    }

    /// The specific force at the pivot for the body rate `w`, the up direction `u` and O's
    /// speed and rate `travel`: gravity, O's acceleration and the lever arm from O.
    #[inline]
    fn pivot_force(
        &self,
        w: &Vector3<T>,
        d: &Drive<T>,
        (u, travel): (&Vector3<T>, &Vector2<T>),
    ) -> Vector3<T> {
        let wd = &d.angular_accel;
        u * self.params.gravity
            + d.centre_accel(w, travel)
            + lever_arm(w, wd, &self.pivot_from_centre)
    }

    /// [`Self::joint_step_with`] with the pivot's specific force `f` given (the same for
    /// every difference but those in the body rate).
    #[inline]
    fn joint_step_in(
        &self,
        trig: &JointTrig<T>,
        j: &Vector4<T>,
        w: &Vector3<T>,
        d: &Drive<T>,
        f: &Vector3<T>,
        h: T,
    ) -> Vector4<T> {
        let pr = &self.params;
        let wd = &d.angular_accel;
        let (sa, ca) = (trig.sa, trig.ca);
        let u2 = ca * w[1] + sa * w[2];
        let u3 = -sa * w[1] + ca * w[2];
        let v2 = ca * wd[1] + sa * wd[2];
        let (ad, bd) = (j[2] - w[0], j[3] - u2);
        let acc = pr.joint_accelerations_with(
            trig,
            ad,
            bd,
            [w[0], w[1], w[2]],
            [wd[0], wd[1], wd[2]],
            [f[0], f[1], f[2]],
        );
        // p' = wd_x + a'', r' = u2' + b'' = v2 + a' u3 + b''.
        let p = j[2] + h * (wd[0] + acc[0]);
        let r = j[3] + h * (v2 + ad * u3 + acc[1]);
        Vector4::new(j[0] + h * (p - w[0]), j[1] + h * (r - u2), p, r)
    }

    /// The partial derivatives of [`Self::joint_step`] with respect to the joints (4 x 4),
    /// the body rate's x and y (4 x 2) and the up direction (4 x 3) at the joints `j` that
    /// the step takes to `next`.
    /// The up direction enters 7.3 linearly (through the specific force), so its columns
    /// are exact; the others are forward differences of step `sqrt(eps)` (the filter needs
    /// them to a few digits: a test checks them against the step itself). The angles'
    /// trigonometry is taken once: the shifted angles' by angle addition; the specific
    /// force once for the joints' differences.
    fn joint_partials(
        &self,
        trig: &JointTrig<T>,
        [j, next]: [&Vector4<T>; 2],
        w: &Vector3<T>,
        dr: &Drive<T>,
        ut: (&Vector3<T>, &Vector2<T>),
        h: T,
    ) -> (SMatrix<T, 4, 4>, SMatrix<T, 4, 2>, SMatrix<T, 4, 3>) {
        let d = T::default_epsilon().sqrt();
        let trig = *trig;
        let shift = d.sin_cos();
        let none = (T::zero(), T::one());
        let f = self.pivot_force(w, dr, ut);
        let mut dj = SMatrix::<T, 4, 4>::zeros();
        for k in 0..4 {
            let mut hi = *j;
            hi[k] += d;
            let t_hi = match k {
                0 => trig.shifted(shift, none),
                1 => trig.shifted(none, shift),
                _ => trig,
            };
            let c = (self.joint_step_in(&t_hi, &hi, w, dr, &f, h) - next) / d;
            dj.set_column(k, &c);
        }
        let mut dw = SMatrix::<T, 4, 2>::zeros();
        for k in 0..2 {
            let mut hi = *w;
            hi[k] += d;
            let c = (self.joint_step_with(&trig, j, &hi, dr, ut, h) - next) / d;
            dw.set_column(k, &c);
        }
        (dj, dw, self.up_partials(&trig, h))
    }

    /// The step's exact partial derivatives with respect to the up direction `u`: `f = g u +
    /// ...` enters 7.3 only through `-cb h2` in `a''` and `cb h1 - sb h3` in `b''` (`h` the
    /// specific force over g in ring axes), and the step gives the rates `h` times, the
    /// angles `h^2` times, the accelerations.
    fn up_partials(&self, trig: &JointTrig<T>, h: T) -> SMatrix<T, 4, 3> {
        let pr = &self.params;
        let JointTrig { sa, ca, sb, cb } = *trig;
        let ia = pr.b_x * cb * cb + pr.b_z * sb * sb;
        let ka = -cb / (pr.b_ring + ia);
        let kb = T::one() / pr.b_y;
        let da = [T::zero(), ka * ca, ka * sa];
        let db = [kb * cb, kb * sb * sa, -kb * sb * ca];
        let h2 = h * h;
        SMatrix::<T, 4, 3>::from_fn(|row, col| match row {
            0 => h2 * da[col],
            1 => h2 * db[col],
            2 => h * da[col],
            _ => h * db[col],
        })
    }
}

impl<T: Real> CardanProcess<T> {
    /// The step's partial derivatives with respect to the body rate's z as the z bias
    /// moves them, given the step's up partials `du`.
    ///
    /// The z bias reaches the joints three ways: through the attitude (the rotation
    /// error's columns, kept), through the pivot's specific force (O's centripetal
    /// acceleration `v w_z` across, the lever arm's `w x (w x r)`), and through the Cardan
    /// kinematics and the pendulum's Coriolis terms (`sin a w_z` in the inner joint's
    /// rate, `a' u3`), products of the bias with the pendulum's own swing. An engine
    /// shaking two axes out of phase swings the pendulum round an ellipse at its
    /// frequency, which those last terms cannot tell from a turn about z: with them,
    /// ekf3d took ride3d's idling engine for a z bias of -2 deg/s within 6 s (seed 2,
    /// true 0.2) and the first run-up for 1.6 deg/s (roll 1.5 deg off). So the z column
    /// is the specific force's alone, at the body's slow rate `w_s` ([`Drive::slow_gyro`]
    /// less the bias; the lever arm's vibrating part is another such product), and exact:
    /// `du / g (v e_y + e_z x (w_s x r) + w_s x (e_z x r))`.
    pub fn z_bias_partials(
        &self,
        du: &SMatrix<T, 4, 3>,
        d: &Drive<T>,
        bias: &Vector3<T>,
        speed: T,
    ) -> Vector4<T> {
        let ws = d.slow_gyro - bias;
        let r = &self.pivot_from_centre;
        let ez = Vector3::z();
        let df = Vector3::new(T::zero(), speed, T::zero())
            + ez.cross(&ws.cross(r))
            + ws.cross(&ez.cross(r));
        du * (df / self.params.gravity)
    }
}

impl<T: Real> ProcessModel<T, N> for CardanProcess<T> {
    type State = State<T>;
    type Input = Drive<T>;

    #[inline]
    fn step(&self, x: &State<T>, d: &Drive<T>, h: T) -> State<T> {
        let w = d.gyro - x.bias;
        let mut q = x.q * UnitQuaternion::from_scaled_axis(w * h);
        q.renormalize_fast();
        let ut = (&x.up(), &x.travel);
        // A z bias away from the drive's reaches the joints through the specific force
        // alone (the attitude turns with the whole of it above).
        let off = x.bias[2] - d.z_bias;
        let joints = if off == T::zero() {
            self.joint_step(&x.joints, &w, d, ut, h)
        } else {
            let trig = JointTrig::of(x.joints[0], x.joints[1]);
            let at_drive = w + Vector3::z() * off;
            let du = self.up_partials(&trig, h);
            self.joint_step_with(&trig, &x.joints, &at_drive, d, ut, h)
                - self.z_bias_partials(&du, d, &x.bias, x.travel[0]) * off
        };
        State {
            q,
            bias: x.bias,
            joints,
            travel: travel_step(&x.travel, h),
        }
    }

    fn jacobian(&self, x: &State<T>, d: &Drive<T>, h: T) -> Cov<T, N> {
        self.step_with_jacobian(x, d, h).1
    }

    fn step_with_jacobian(&self, x: &State<T>, d: &Drive<T>, h: T) -> (State<T>, Cov<T, N>) {
        let w = d.gyro - x.bias;
        let u = x.up();
        let turn = UnitQuaternion::from_scaled_axis(w * h);
        // The joint angles' trigonometry, once for the step and all its differences.
        let trig = JointTrig::of(x.joints[0], x.joints[1]);
        let mut q = x.q * turn;
        q.renormalize_fast();
        let ut = (&u, &x.travel);
        let next = State {
            q,
            bias: x.bias,
            joints: self.joint_step_with(&trig, &x.joints, &w, d, ut, h),
            travel: travel_step(&x.travel, h),
        };
        let mut f = Cov::<T, N>::identity();
        // Rotation error: d' = exp(w h)^T d - h d_bias (first order in h for the bias).
        let rt = turn.to_rotation_matrix().into_inner().transpose();
        f.fixed_view_mut::<3, 3>(ROT, ROT).copy_from(&rt);
        f.fixed_view_mut::<3, 3>(ROT, BIAS)
            .copy_from(&(Matrix3::identity() * -h));
        let (dj, dw, du) = self.joint_partials(&trig, [&x.joints, &next.joints], &w, d, ut, h);
        f.fixed_view_mut::<4, 4>(A, A).copy_from(&dj);
        // w = gyro - bias; u(q exp d) = u + u x d.
        f.fixed_view_mut::<4, 2>(A, BIAS).copy_from(&(-dw));
        let dz = self.z_bias_partials(&du, d, &x.bias, x.travel[0]);
        f.fixed_view_mut::<4, 1>(A, BIAS + 2).copy_from(&(-dz));
        f.fixed_view_mut::<4, 3>(A, ROT).copy_from(&(du * skew(&u)));
        // O's speed and rate enter the specific force linearly, as `g u` does.
        let per_g = du / self.params.gravity;
        f.fixed_view_mut::<4, 1>(A, V)
            .copy_from(&(per_g * d.centre_accel_per_speed(&w)));
        f.fixed_view_mut::<4, 1>(A, ACC).copy_from(&per_g.column(0));
        f[(V, ACC)] = h;
        (next, f)
    }

    /// `F P F^T` through the rows of `F` that are not the identity's: the rotation
    /// (`[R, -h I, 0]`), the joints (full) and the speed (`e_v + h e_v'`), the set `S`;
    /// the bias and `v'` rows are the identity's, `I`. `M = F P` is `P` with the rows `S`
    /// replaced; `F P F^T = M F^T` is then `M` on the columns `I`, `M`'s `S` rows times
    /// `F`'s `S` rows on the block `S x S` (symmetrised), and `I x S` its mirror image.
    /// About 1,250 multiplications against the dense product's 3,500; a test checks it
    /// against the dense product.
    #[inline]
    fn propagate(&self, f: &Cov<T, N>, p: &Cov<T, N>) -> Cov<T, N> {
        // The rows S in order: rotation (3), then a, b, p, r, v (contiguous from A).
        const S: [usize; 8] = [ROT, ROT + 1, ROT + 2, A, B, P, R, V];
        let r = f.fixed_view::<3, 3>(ROT, ROT);
        let minus_h = f[(ROT, BIAS)];
        let h = f[(V, ACC)];
        let jac = f.fixed_view::<4, N>(A, 0);
        // M's rows S.
        let mut ms = SMatrix::<T, 8, N>::zeros();
        ms.fixed_rows_mut::<3>(0)
            .copy_from(&(r * p.fixed_rows::<3>(ROT) + p.fixed_rows::<3>(BIAS) * minus_h));
        ms.fixed_rows_mut::<4>(3).copy_from(&(jac * p));
        ms.set_row(7, &(p.row(V) + p.row(ACC) * h));
        // M F^T on the columns S, rows S.
        let mut b = SMatrix::<T, 8, 8>::zeros();
        b.fixed_columns_mut::<3>(0).copy_from(
            &(ms.fixed_columns::<3>(ROT) * r.transpose() + ms.fixed_columns::<3>(BIAS) * minus_h),
        );
        b.fixed_columns_mut::<4>(3)
            .copy_from(&(ms * jac.transpose()));
        b.set_column(7, &(ms.column(V) + ms.column(ACC) * h));
        let half = T::lit(0.5);
        let mut out = *p;
        for (bi, &i) in S.iter().enumerate() {
            for (bj, &j) in S.iter().enumerate() {
                out[(i, j)] = (b[(bi, bj)] + b[(bj, bi)]) * half;
            }
            for k in [BIAS, BIAS + 1, BIAS + 2, ACC] {
                out[(i, k)] = ms[(bi, k)];
                out[(k, i)] = ms[(bi, k)];
            }
        }
        out
    }

    /// Gyro noise turns the attitude and, oppositely, the joint angles it moves past
    /// (`a' = p - w_x`, `b' = r - u2`; the cross terms are those at small `a`); the
    /// pendulum's rates take the unmodelled acceleration as a double integrator, O's speed
    /// and rate white jerk (the estimator leaves it out while no `speed` column reads
    /// them: both are then held at zero).
    fn q(&self, h: T) -> Cov<T, N> {
        let n = &self.noise;
        let mut q = Cov::<T, N>::zeros();
        let g2 = n.gyro * n.gyro * h;
        for k in 0..3 {
            q[(ROT + k, ROT + k)] = g2;
            q[(BIAS + k, BIAS + k)] = n.bias * n.bias * h;
        }
        q[(A, A)] = g2;
        q[(B, B)] = g2;
        q[(ROT, A)] = -g2;
        q[(A, ROT)] = -g2;
        q[(ROT + 1, B)] = -g2;
        q[(B, ROT + 1)] = -g2;
        let h2 = h * h;
        for (angle, rate, d) in [(A, P, n.joints[0]), (B, R, n.joints[1])] {
            let v = d * d;
            q[(angle, angle)] += v * h2 * h / T::lit(3.0);
            q[(angle, rate)] = v * h2 / T::lit(2.0);
            q[(rate, angle)] = q[(angle, rate)];
            q[(rate, rate)] = v * h;
        }
        let j = n.jerk * n.jerk;
        q[(V, V)] = j * h2 * h / T::lit(3.0);
        q[(V, ACC)] = j * h2 / T::lit(2.0);
        q[(ACC, V)] = q[(V, ACC)];
        q[(ACC, ACC)] = j * h;
        q
    }
}

/// O's speed and rate after `h`: the rate held (a random walk), the speed its integral.
#[inline]
fn travel_step<T: Real>(travel: &Vector2<T>, h: T) -> Vector2<T> {
    Vector2::new(travel[0] + h * travel[1], travel[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::ErrorState;
    use crate::spatial::ekf::state::Error;

    fn model() -> CardanProcess<f64> {
        CardanProcess {
            params: CardanParams {
                c: [0.01, -0.005, 0.02],
                ..CardanParams::default()
            },
            noise: ProcessNoise {
                gyro: 1e-4,
                bias: 1e-5,
                joints: [0.3, 0.3],
                jerk: 2.0,
            },
            pivot_from_centre: Vector3::new(0.01, -0.05, 0.3),
        }
    }

    fn drive(gyro: Vector3<f64>, angular_accel: Vector3<f64>) -> Drive<f64> {
        Drive {
            gyro,
            angular_accel,
            path_gyro: gyro * 0.8,
            slow_gyro: gyro * 0.9,
            z_bias: 0.005,
        }
    }

    /// A tilted, turned state with a swinging pendulum and a gyro bias.
    fn tilted() -> State<f64> {
        State {
            q: UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7),
            bias: Vector3::new(0.01, -0.02, 0.005),
            joints: Vector4::new(-0.25, 0.15, 0.4, -0.3),
            travel: Vector2::new(7.0, -2.0),
        }
    }

    /// The Jacobian maps a small error before the step to the error after it: compare
    /// `step(x ⊞ e) ⊟ step(x)` with `F e` for small `e` in every direction, the z bias's
    /// included (the step takes the joints' rate at the drive's z bias, so a state's own
    /// moves them through the attitude and the specific force alone, as `F` has it).
    #[test]
    fn the_jacobian_maps_errors_through_the_step() {
        let m = model();
        let x = tilted();
        let gyro = drive(Vector3::new(0.5, -0.8, 0.3), Vector3::new(2.0, -1.0, 3.0));
        let h = 2e-3;
        let (next, f) = m.step_with_jacobian(&x, &gyro, h);
        for k in 0..N {
            let mut e = Error::<f64>::zeros();
            e[k] = 1e-6;
            let moved = next.local(&m.step(&x.retract(&e), &gyro, h));
            let lin = f * e;
            let err = (moved - lin).norm();
            assert!(err < 1e-3 * 1e-6 + 1e-12, "direction {k}: {moved} vs {lin}");
        }
    }

    /// Where the z bias moves nothing but the specific force (the pendulum hanging at
    /// rest, a = 0, the body not turning), its column is the step's own derivative: O's
    /// centripetal term `v` across, with the mounting's lever arm.
    #[test]
    fn the_z_bias_column_is_the_specific_forces_derivative() {
        let m = model();
        let bias = Vector3::new(0.01, -0.02, 0.005);
        let x = State {
            q: UnitQuaternion::from_euler_angles(0.0, -0.2, 0.7),
            bias,
            joints: Vector4::new(0.0, 0.2, 0.0, 0.0),
            travel: Vector2::new(7.0, 0.0),
        };
        let mut d = drive(bias, Vector3::zeros());
        d.slow_gyro = bias;
        d.path_gyro = bias;
        let h = 2e-3;
        let (next, f) = m.step_with_jacobian(&x, &d, h);
        let mut e = Error::<f64>::zeros();
        e[BIAS + 2] = 1e-6;
        let moved = next.local(&m.step(&x.retract(&e), &d, h));
        let lin = f * e;
        assert!(lin[A + 2].abs() > 1e-9, "the speed moves p: {lin}");
        assert!((moved - lin).norm() < 1e-3 * lin.norm(), "{moved} vs {lin}");
    }

    /// The z column does not follow the pendulum's swing (the engine's ellipse) or the
    /// body's vibration: the same for any joint rates and any fast gyro reading, at the
    /// same angles and slow rate.
    #[test]
    fn the_z_bias_column_ignores_the_swing_and_the_vibration() {
        let m = model();
        let x = tilted();
        let d = drive(Vector3::new(0.5, -0.8, 0.3), Vector3::new(2.0, -1.0, 3.0));
        let mut swinging = x;
        swinging.joints[2] += 3.0;
        swinging.joints[3] -= 2.0;
        let mut shaken = d;
        shaken.gyro += Vector3::new(0.4, -0.3, 0.2);
        let h = 2e-3;
        let col = |x: &State<f64>, d: &Drive<f64>| {
            m.step_with_jacobian(x, d, h)
                .1
                .fixed_view::<4, 1>(A, BIAS + 2)
                .into_owned()
        };
        let base = col(&x, &d);
        assert!(base.norm() > 1e-8);
        assert!((col(&swinging, &d) - base).norm() < 1e-12 * base.norm().max(1.0));
        // The up partials change with the joints' angles only; the fast rate not at all.
        assert_eq!(col(&x, &shaken), base);
    }

    /// A pendulum hanging still on a still, tilted body stays where it is.
    #[test]
    fn the_hanging_equilibrium_is_kept() {
        let m = model();
        let (roll, pitch) = (0.2f64, -0.35f64);
        let x = State {
            q: UnitQuaternion::from_euler_angles(roll, pitch, 1.2),
            bias: Vector3::zeros(),
            joints: Vector4::new(-roll, -pitch, 0.0, 0.0),
            travel: Vector2::zeros(),
        };
        let still = Drive {
            slow_gyro: Vector3::zeros(),
            z_bias: 0.0,
            ..drive(Vector3::zeros(), Vector3::zeros())
        };
        let mut y = x;
        for _ in 0..1000 {
            y = m.step(&y, &still, 1e-3);
        }
        assert!((y.joints - x.joints).norm() < 1e-12, "{}", y.joints);
    }

    /// An angular acceleration about body x turns the pivot about O, and O itself
    /// accelerates with the speed: both reach the pendulum only as the specific force
    /// `v' x_b + w x (v x_b) + wd x r` (the `wd_x` of `a''` and of `p' = wd_x + a''`
    /// cancel), so the step equals one on a still body whose up direction carries that
    /// force.
    #[test]
    fn the_lever_arm_and_the_speed_enter_as_a_specific_force() {
        let m = model();
        let j = Vector4::new(-0.2, 0.1, 0.3, -0.1);
        let u = Vector3::new(-0.1, 0.2, 0.97);
        let wd = Vector3::new(4.0, 0.0, 0.0);
        let w = Vector3::zeros();
        // w = 0: O's acceleration is v' x_b alone.
        let d = drive(w, wd);
        let travel = Vector2::new(7.0, -2.0);
        let moved = m.joint_step(&j, &w, &d, (&u, &travel), 1e-3);
        let at_pivot = CardanProcess {
            pivot_from_centre: Vector3::zeros(),
            ..m
        };
        let force = wd.cross(&m.pivot_from_centre) + Vector3::new(travel[1], 0.0, 0.0);
        let f = u + force / m.params.gravity;
        let still = Drive {
            slow_gyro: Vector3::zeros(),
            ..drive(w, w)
        };
        let at_rest = Vector2::zeros();
        let same = at_pivot.joint_step(&j, &w, &still, (&f, &at_rest), 1e-3);
        assert!((moved - same).norm() < 1e-15, "{moved} vs {same}");
        // And it matters: 4 rad/s^2 at 0.3 m is 0.12 g.
        let ignored = m.joint_step(&j, &w, &still, (&u, &at_rest), 1e-3);
        assert!((moved - ignored).norm() > 1e-4, "{moved} vs {ignored}");
        // A turn: the centripetal v w_z along body y, -v w_y along z.
        let turn = Vector3::new(0.0, 0.1, 0.5);
        let c = d.centre_accel(&turn, &travel);
        assert!((c - Vector3::new(-2.0, 3.5, -0.7)).norm() < 1e-12, "{c}");
        // Only the path's rate turns O's velocity: here 0.8 of the gyro's 0.5 rad/s.
        let d = drive(Vector3::new(0.0, 0.0, 0.5), wd);
        let c = d.centre_accel(&Vector3::new(0.0, 0.0, 0.5), &travel);
        assert!((c - Vector3::new(-2.0, 2.8, 0.0)).norm() < 1e-12, "{c}");
    }

    /// The structured `F P F^T` equals the dense product symmetrised (to rounding: the
    /// sums run in another order).
    #[test]
    fn propagate_equals_the_dense_product() {
        let m = model();
        let x = tilted();
        let d = drive(Vector3::new(0.5, -0.8, 0.3), Vector3::new(2.0, -1.0, 3.0));
        let (_, f) = m.step_with_jacobian(&x, &d, 2e-3);
        let a = Cov::<f64, N>::from_fn(|i, j| ((i * 7 + j * 3) % 11) as f64 * 0.1 - 0.4);
        let p = a * a.transpose() + Cov::<f64, N>::identity();
        assert_eq!(p, p.transpose());
        let mut dense = f * p * f.transpose();
        crate::engine::update::symmetrise(&mut dense);
        let fast = m.propagate(&f, &p);
        assert_eq!(fast, fast.transpose());
        let err = (fast - dense).abs().max();
        assert!(err < 1e-13 * dense.abs().max(), "{err}");
    }

    /// White jerk integrated over `h` on `(v, v')`, nothing else.
    #[test]
    fn the_jerk_noise_is_white_jerk_integrated() {
        let m = model();
        let h = 4e-3;
        let with = m.q(h);
        let without = CardanProcess {
            noise: ProcessNoise {
                jerk: 0.0,
                ..m.noise
            },
            ..m
        }
        .q(h);
        let q = with - without;
        let j2 = m.noise.jerk * m.noise.jerk;
        let want = [
            (V, V, j2 * h * h * h / 3.0),
            (V, ACC, j2 * h * h / 2.0),
            (ACC, ACC, j2 * h),
        ];
        for (r, c, w) in want {
            assert!(
                (q[(r, c)] - w).abs() < 1e-12 * w,
                "{r} {c}: {} vs {w}",
                q[(r, c)]
            );
            assert_eq!(q[(r, c)], q[(c, r)]);
        }
        assert_eq!(q.iter().filter(|x| **x != 0.0).count(), 4);
    }
}
