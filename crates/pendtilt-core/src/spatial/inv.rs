//! `inv3d`: Algorithm 2 in three dimensions. The two joint equations of MODEL.md 7.3 are
//! solved for the specific force at the pivot, given the encoder angles, their smoothed
//! derivatives and the gyro (its derivative as Algorithm 2's theta'').
//!
//! Both equations are linear in the specific force `f`, and they see it in pendulum axes,
//! `v = Ry(b)^T Rx(a)^T f / g` (MODEL.md 7.3's `h`, turned by `b`):
//!
//! ```text
//! (b_ring + Ia) a'' = K_a - cos b h2          h2  = v_y
//!           b_y b'' = K_b + (cos b h1 - sin b h3)  = K_b + v_x
//! ```
//!
//! with `K_a`, `K_b` every other term (damping, the body's rate and angular acceleration,
//! the gyroscopic terms), which [`CardanParams::joint_accelerations`] gives for `f = 0`.
//! So `v_y = (b_ring + Ia)(K_a / (b_ring + Ia) - a'') / cos b`,
//! `v_x = b_y (b'' - K_b / b_y)`, `v_z = sqrt(1 - v_x^2 - v_y^2)` (a body without linear
//! acceleration: `|f| = g`), and the world's up direction in body axes is
//! `u = Rx(a) Ry(b) v`, less the pivot's lever-arm terms `wd x r12 + w x (w x r12)` when it
//! sits off the IMU point. A travelling vehicle's known acceleration (the `speed` column,
//! [`super::travel`]) is the pivot's too: `u = f / g - (a_O + wd x r + w x (w x
//! r)) / g` with `r` the pivot from O (`[mounting] speed_at`), which without a speed and
//! with O at the IMU point is the lever arm above. On a pure roll this is exactly the planar Eq (21),
//! `theta = phi + asin(a phi' + b (phi'' - theta''))`: `v_y` is the asin's argument (test
//! `a_pure_roll_is_the_planar_algorithm_2`).
//!
//! Each encoder axis goes through the planar front end with its gyro axis (the same
//! differentiator, so phi', phi'' and the gyro carry the same delay, and theta'' from the
//! gyro matched to it, as the planar findings prescribe); the gyro's z axis through a third
//! (its theta'' only). The gyroscopic terms use the gyro through the same low-pass.
use super::attitude::roll_pitch_from_up;
use super::cardan::{CardanParams, JointTrig};
use super::mounting::{lever_arm, Mounting};
use super::travel::{Travel, TravelSettings};
use super::{Attitude, SpatialSample};
use crate::estimators::equations::Kinematics;
use crate::estimators::front_end::{FrontEnd, FrontEndSettings};
use crate::estimators::theta_dd::DEFAULT_WINDOW_CAPACITY;
use crate::{Estimator, Flags, PendulumParams, Real, Sample};
use nalgebra::Vector3;

/// Default cutoff \[Hz\] of inv3d's speed derivative: lower than the spatial filter's
/// ([`super::travel::DEFAULT_SPEED_RATE_HZ`]), because inv3d does not filter what it
/// inverts, so the speed's noise through the derivative is tilt noise. Measured
/// (`estimate`, 120 s, seed 1, deg RMS inclination; scooter3d / ship3d / ride3d): 5 Hz
/// 0.878 / 1.064 / 7.93, 2 Hz 0.429 / 0.740 / 7.89, 1 Hz 0.383 / 0.723 / 7.90.
pub const INV3D_SPEED_RATE_HZ: f64 = 1.0;

/// Settings of [`Inv3d`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inv3dSettings<T> {
    /// The pendulum (normalised, MODEL.md 7.3). Default: MODEL.md 7.6's rig.
    pub params: CardanParams<T>,
    /// The front end each axis goes through (differentiator, theta'' source, gyro full
    /// scale), as Algorithm 2's. Default: Algorithm 2's defaults for the x axis'
    /// pendulum (its natural frequency sets the differentiator's cutoff).
    pub front_end: FrontEndSettings<T>,
    /// Where the sensors sit; its `speed_at` is the point O whose speed the `speed` column
    /// gives and about which the body turns. Default: P1.
    pub mounting: Mounting<T>,
    /// How the speed and the gyro give O's acceleration. Default: [`TravelSettings`]'s
    /// but for the speed's derivative, [`INV3D_SPEED_RATE_HZ`].
    pub travel: TravelSettings<T>,
}

impl<T: Real> Default for Inv3dSettings<T> {
    fn default() -> Self {
        Self::from_params(CardanParams::default())
    }
}

impl<T: Real> Inv3dSettings<T> {
    /// Defaults for the pendulum `params`.
    pub fn from_params(params: CardanParams<T>) -> Self {
        let planar = PendulumParams {
            a: params.a_x,
            b: params.b_x + params.b_ring,
            c: T::zero(),
        };
        Self {
            params,
            front_end: FrontEndSettings::from_params(planar),
            mounting: Mounting::default(),
            travel: TravelSettings {
                speed_rate_hz: T::lit(INV3D_SPEED_RATE_HZ),
                ..TravelSettings::default()
            },
        }
    }
}

/// Algorithm 2 in three dimensions (see the module documentation).
#[derive(Debug, Clone)]
pub struct Inv3d<T: Real, const W: usize = DEFAULT_WINDOW_CAPACITY> {
    settings: Inv3dSettings<T>,
    coeffs: Coefficients<T>,
    state: State<T, W>,
}

/// What the settings give once, so that no sample derives it again.
#[derive(Debug, Clone, Copy)]
struct Coefficients<T: Real> {
    /// The pivot P2 from O, `c g - speed_at` \[m\], body axes.
    pivot_from_centre: Vector3<T>,
}

/// Everything a run changes: what `reset` starts again.
#[derive(Debug, Clone)]
struct State<T: Real, const W: usize> {
    /// x, y (the encoders with their gyro axes) and z (the z gyro's theta'' only).
    axes: [FrontEnd<T, W>; 3],
    travel: Travel<T>,
    /// The last estimate, held while none is made.
    last: Attitude<T>,
}

impl<T: Real, const W: usize> Inv3d<T, W> {
    /// A new estimator.
    pub fn new(settings: Inv3dSettings<T>) -> Self {
        let fe = FrontEnd::new(&settings.front_end, true);
        let p = &settings.params;
        Self {
            coeffs: Coefficients {
                pivot_from_centre: settings.mounting.from_centre(p.c.map(|c| c * p.gravity)),
            },
            state: State {
                axes: [fe.clone(), fe.clone(), fe],
                travel: Travel::new(settings.travel),
                last: Attitude::unknown(),
            },
            settings,
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &Inv3dSettings<T> {
        &self.settings
    }

    fn hold(&self, flags: Flags) -> Attitude<T> {
        Attitude {
            flags,
            ..self.state.last
        }
    }

    /// Feeds the speed and the gyro to the travel filters on every row with a usable time
    /// step, held rows included, so that their clocks follow the log's.
    fn track_travel(&mut self, s: &SpatialSample<T>) {
        if !(s.dt.is_finite() && s.dt >= T::zero()) {
            return;
        }
        let travel = &mut self.state.travel;
        if s.gyro.iter().all(|g| g.is_finite()) {
            travel.gyro(&Vector3::from(s.gyro), s.dt);
        }
        travel.speed(s.speed, s.dt);
    }

    /// The pivot's acceleration \[m/s^2\], body axes: O's from the speed and the gyro,
    /// and the lever arm from O at the front ends' rate `w` and angular acceleration `wd`.
    fn pivot_accel(&self, w: [T; 3], wd: [T; 3]) -> [T; 3] {
        let (w, wd) = (Vector3::from(w), Vector3::from(wd));
        let r = &self.coeffs.pivot_from_centre;
        (self.state.travel.centre_accel(&Vector3::zeros()) + lever_arm(&w, &wd, r)).into()
    }
}

/// The front ends' outputs of one sample: x, y (encoders with their gyro axes) and z (the
/// z gyro's theta'' only).
type AxesKinematics<T> = [Kinematics<T>; 3];

impl<T: Real, const W: usize> Inv3d<T, W> {
    /// Each axis through its front end; `Err(flags)` if one could not take the sample.
    fn front_ends(&mut self, s: &SpatialSample<T>) -> Result<(AxesKinematics<T>, Flags), Flags> {
        let nan = T::nan();
        let planar = |phi: T, gyro: T| Sample {
            dt: s.dt,
            phi,
            gyro,
            ax: nan,
            ay: nan,
        };
        // The z gyro rides on phi_x's clock and validity (its phi output is unused).
        let inputs = [
            planar(s.phi[0], s.gyro[0]),
            planar(s.phi[1], s.gyro[1]),
            planar(s.phi[0], s.gyro[2]),
        ];
        let mut k = [None; 3];
        let mut flags = Flags::empty();
        for (i, (fe, x)) in self.state.axes.iter_mut().zip(&inputs).enumerate() {
            match fe.step(x) {
                Ok((kin, f)) => {
                    flags |= f | kin.gyro_flags;
                    k[i] = Some(kin);
                }
                Err(f) => flags |= f,
            }
        }
        match k {
            [Some(x), Some(y), Some(z)] => Ok(([x, y, z], flags)),
            _ => Err(flags),
        }
    }
}

/// The horizontal part `(v_x, v_y)` of the specific force at the pivot over g, in
/// pendulum axes, that the joint equations require (see the module documentation).
fn pendulum_axes_force<T: Real>(
    p: &CardanParams<T>,
    trig: &JointTrig<T>,
    k: &AxesKinematics<T>,
    w: [T; 3],
    wd: [T; 3],
) -> [T; 2] {
    // Encoder convention: phi = -angle (MODEL.md 7.2).
    let (ad, bd) = (-k[0].dphi, -k[1].dphi);
    let (add, bdd) = (-k[0].ddphi, -k[1].ddphi);
    let k0 = p.joint_accelerations_with(trig, ad, bd, w, wd, [T::zero(); 3]);
    let ia = p.b_x * trig.cb * trig.cb + p.b_z * trig.sb * trig.sb;
    [
        p.b_y * (bdd - k0[1]),
        (p.b_ring + ia) * (k0[0] - add) / trig.cb,
    ]
}

/// The world's up direction in body axes from the pendulum's horizontal specific force
/// `v_xy` (pendulum axes, over g) and the pivot's known acceleration over g, `acc` (body
/// axes): `u = f / g - acc` with `|u| = 1`, which fixes the one unknown, `v_z` (the
/// pendulum hangs below its pivot: the positive root). With `d = R^T acc`,
/// `v_z = d_z + sqrt(1 - |v_xy - d_xy|^2)`; a horizontal part beyond the unit circle
/// (as Eq 21's asin argument out of [-1, 1]) is clamped to it, and `true` says so.
fn up_from<T: Real>(v_xy: [T; 2], trig: &JointTrig<T>, acc: [T; 3]) -> ([T; 3], bool) {
    let JointTrig { sa, ca, sb, cb } = *trig;
    // R = Rx(a) Ry(b): pendulum -> body; d = R^T acc.
    let (ry, rz) = (ca * acc[1] + sa * acc[2], -sa * acc[1] + ca * acc[2]);
    let d = [cb * acc[0] - sb * rz, ry, sb * acc[0] + cb * rz];
    let (mut hx, mut hy) = (v_xy[0] - d[0], v_xy[1] - d[1]);
    let mut r2 = hx * hx + hy * hy;
    let clamped = r2 > T::one() || !r2.is_finite();
    if clamped {
        let scale = if r2.is_finite() && r2 > T::zero() {
            T::one() / r2.sqrt()
        } else {
            T::zero()
        };
        hx *= scale;
        hy *= scale;
        r2 = T::one();
    }
    // u = R (v - d), with v - d = (hx, hy, sqrt(1 - r2)).
    let hz = (T::one() - r2).max(T::zero()).sqrt();
    let (x, z) = (cb * hx + sb * hz, -sb * hx + cb * hz);
    ([x, ca * hy - sa * z, sa * hy + ca * z], clamped)
}

impl<T: Real, const W: usize> Estimator for Inv3d<T, W> {
    type Input = SpatialSample<T>;
    type Output = Attitude<T>;

    fn update(&mut self, s: &SpatialSample<T>) -> Attitude<T> {
        self.track_travel(s);
        let (k, mut flags) = match self.front_ends(s) {
            Ok(x) => x,
            Err(flags) => return self.hold(flags),
        };
        let trig = JointTrig::of(-k[0].phi, -k[1].phi);
        let w = [k[0].gyro_filtered, k[1].gyro_filtered, k[2].gyro_filtered];
        let wd = [k[0].theta_dd, k[1].theta_dd, k[2].theta_dd];
        let a = self.pivot_accel(w, wd);
        let p = &self.settings.params;
        let v = pendulum_axes_force(p, &trig, &k, w, wd);
        let (u, clamped) = up_from(v, &trig, a.map(|x| x / p.gravity));
        if clamped {
            flags |= Flags::ASIN_CLAMPED;
        }
        let (roll, pitch) = roll_pitch_from_up(u);
        if !(roll.is_finite() && pitch.is_finite()) {
            return self.hold(flags | Flags::SAMPLE_MISSING);
        }
        self.state.last = Attitude { roll, pitch, flags };
        self.state.last
    }

    fn reset(&mut self) {
        let st = &mut self.state;
        for fe in &mut st.axes {
            fe.reset();
        }
        st.travel.reset();
        st.last = Attitude::unknown();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimators::alg2::{Alg2, Alg2Settings};

    /// On a pure roll (no pitch, no yaw), inv3d's roll is the planar Algorithm 2 on
    /// (phi_x, gyro_x) with a = a_x, b = b_x, and its pitch is zero.
    #[test]
    fn a_pure_roll_is_the_planar_algorithm_2() {
        let p = CardanParams::<f64>::default();
        let settings = Inv3dSettings::from_params(p);
        let mut inv = Inv3d::<f64>::new(settings);
        let mut alg2 = Alg2::<f64>::new(Alg2Settings {
            front_end: settings.front_end,
            ..Alg2Settings::from_params(settings.front_end.params)
        });
        let tau = core::f64::consts::TAU;
        let mut worst = 0.0f64;
        for k in 0..5000 {
            let t = k as f64 * 1e-3;
            let roll = 0.2 * (tau * 0.7 * t).sin();
            let rate = 0.2 * tau * 0.7 * (tau * 0.7 * t).cos();
            let phi = 0.2 * (tau * 0.7 * (t - 0.03)).sin() + 0.01 * (tau * 3.0 * t).sin();
            let dt = if k == 0 { 0.0 } else { 1e-3 };
            let s = SpatialSample {
                speed: nan(),
                ..SpatialSample::new(dt, [phi, 0.0], [rate, 0.0, 0.0], [nan(); 3])
            };
            let a = inv.update(&s);
            let e = alg2.update(&Sample {
                dt,
                phi,
                gyro: rate,
                ax: nan(),
                ay: nan(),
            });
            let _ = roll;
            worst = worst.max((a.roll - e.theta).abs()).max(a.pitch.abs());
        }
        assert!(worst < 1e-12, "{worst}");
    }

    fn nan() -> f64 {
        f64::NAN
    }
}

#[cfg(test)]
mod travel_tests {
    use super::*;

    /// A level body accelerating forward at 1.5 m/s^2 with its pendulum hanging along the
    /// specific force `(a, 0, g)`: tilted back, as a nose-up pitch of atan(a / g) reads.
    /// With the speed, inv3d's pitch is the body's, 0; without, the apparent -atan(a / g).
    #[test]
    fn a_steady_acceleration_is_taken_out_of_the_tilt() {
        let p = CardanParams::<f64>::default();
        let acc = 1.5;
        let apparent = -(acc / p.gravity).atan();
        for (speed, expect) in [(true, 0.0), (false, apparent)] {
            let mut inv = Inv3d::<f64>::new(Inv3dSettings::from_params(p));
            let mut last = Attitude::unknown();
            for k in 0..6000 {
                let t = k as f64 * 1e-3;
                let s = SpatialSample {
                    speed: if speed { 2.0 + acc * t } else { f64::NAN },
                    ..SpatialSample::new(
                        if k == 0 { 0.0 } else { 1e-3 },
                        [0.0, apparent],
                        [0.0; 3],
                        [f64::NAN; 3],
                    )
                };
                last = inv.update(&s);
            }
            assert!(last.roll.abs() < 1e-6, "{speed}: roll {}", last.roll);
            assert!(
                (last.pitch - expect).abs() < 1e-4,
                "{speed}: pitch {} vs {expect}",
                last.pitch
            );
        }
    }

    /// A level body in a steady left turn (10 m/s, 0.2 rad/s about z): the centripetal
    /// 2 m/s^2 towards +y swings the pendulum outwards, as a roll of atan(v w / g) reads.
    /// With the speed inv3d's roll is the body's, 0 (within what the pendulum's own
    /// turning adds, `w^2` against `g / l`); without, the apparent roll.
    #[test]
    fn a_steady_turn_is_taken_out_of_the_tilt() {
        let p = CardanParams::<f64>::default();
        let (v, w) = (10.0, 0.2);
        let apparent = (v * w / p.gravity).atan();
        for (speed, expect) in [(true, 0.0), (false, apparent)] {
            let mut inv = Inv3d::<f64>::new(Inv3dSettings::from_params(p));
            let mut last = Attitude::unknown();
            for k in 0..6000 {
                let s = SpatialSample {
                    speed: if speed { v } else { f64::NAN },
                    ..SpatialSample::new(
                        if k == 0 { 0.0 } else { 1e-3 },
                        [apparent, 0.0],
                        [0.0, 0.0, w],
                        [f64::NAN; 3],
                    )
                };
                last = inv.update(&s);
            }
            assert!(
                (last.roll - expect).abs() < 2e-3,
                "{speed}: roll {} vs {expect}",
                last.roll
            );
            assert!(last.pitch.abs() < 2e-3, "{speed}: pitch {}", last.pitch);
        }
    }
}
