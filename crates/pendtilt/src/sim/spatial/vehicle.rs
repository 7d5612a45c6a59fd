//! The vehicle motion of MODEL.md 7.7: a body that travels, brakes, turns, climbs and heaves,
//! its attitude a sum of components (some tagged `path`, some locked to the engine), with
//! vibration in body axes; every derivative analytic.
//!
//! - [`MotionSpec`]: what a scenario file holds (angles in degrees, SI otherwise).
//! - [`VehicleMotion`]: the built motion, a [`BodyMotion`] for the simulator, with the true
//!   forward speed of the point O that the `speed` column reads.
//!
//! The point O = P1 + `speed_at` moves with V_O = v(t) d + z_h'(t) e_z,
//! d = Rz(yaw_path) Ry(pitch_path) e_x, so a_O = v' d + v d' + z_h'' e_z; P1 turns about O
//! with the vehicle attitude R_s (every component but the engine-locked ones, which turn the
//! rig about P1):
//!     f_P1 = R^T (a_O + R_s (wd_s x r + w_s x (w_s x r)) - g_w) + a_vib,   r = -speed_at.

use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::f64::consts::TAU;

use super::dynamics::cross;
use super::motion::{attitude, body_rate, world_to_body, BodyKinematics, BodyMotion};
use super::timefn::{self, add, mul, scale, Context, Jet, Shape, ZERO};
use crate::sim::planar::SimError;

/// One term of an angle or of the heave: a shape, optionally setting the direction of travel
/// (`path`, pitch and yaw only) and optionally scaled by v(t) / speed_ref (road-induced).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Term {
    /// The time function.
    pub shape: Shape,
    /// Part of the path's pitch or yaw (the direction of travel d). Default false.
    #[serde(default, skip_serializing_if = "is_false")]
    pub path: bool,
    /// Amplitude times v(t) / speed_ref \[m/s\]. Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_ref: Option<f64>,
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl Term {
    /// A plain term.
    pub fn new(shape: Shape) -> Self {
        Self {
            shape,
            path: false,
            speed_ref: None,
        }
    }

    /// A term of the path (direction of travel).
    pub fn path(shape: Shape) -> Self {
        Self {
            path: true,
            ..Self::new(shape)
        }
    }

    /// A term scaled by v(t) / `speed_ref`.
    pub fn per_speed(shape: Shape, speed_ref: f64) -> Self {
        Self {
            speed_ref: Some(speed_ref),
            ..Self::new(shape)
        }
    }

    fn eval(&self, t: f64, ctx: &Context) -> Jet {
        let x = self.shape.eval(t, ctx);
        match self.speed_ref {
            Some(r) => mul(x, scale(ctx.speed, 1.0 / r)),
            None => x,
        }
    }

    fn is_engine(&self) -> bool {
        matches!(self.shape, Shape::Engine { .. })
    }
}

/// A frequency modulation of the engine: df sin(2 pi fm t + phase) \[Hz\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EngineMod {
    /// Depth \[Hz\].
    pub df: f64,
    /// Modulation frequency \[Hz\].
    pub fm: f64,
    /// Phase at t = 0 \[rad\].
    pub phase: f64,
}

/// The engine: f_e(t) = f0 + k_speed v(t) + sum df sin(2 pi fm t + phase) \[Hz\],
/// psi_e = 2 pi int_0^t f_e (MODEL.md 7.7).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EngineSpec {
    /// Base frequency \[Hz\]. Default 0 (no engine).
    #[serde(default)]
    pub f0: f64,
    /// Frequency per unit speed \[Hz per m/s\]. Default 0.
    #[serde(default)]
    pub k_speed: f64,
    /// Modulations. Default none.
    #[serde(default)]
    pub mods: Vec<EngineMod>,
}

/// A body axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// Forward.
    X,
    /// Left.
    Y,
    /// Up.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// A vibration acceleration along one body axis: a sine or an engine-locked sine \[m/s^2\],
/// optionally times v(t) / speed_ref.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vibration {
    /// The body axis.
    pub axis: Axis,
    /// `sine` or `engine` \[m/s^2\].
    pub shape: Shape,
    /// Amplitude times v(t) / speed_ref \[m/s\]. Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_ref: Option<f64>,
}

/// Broadband vibration along one body axis as a sum of tones, amp sin(2 pi f_i t + ph_i)
/// each (the random frequencies and phases drawn from the seed and written out).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tones {
    /// The body axis.
    pub axis: Axis,
    /// Each tone's amplitude \[m/s^2\] (rms sqrt(2 / n) for an RMS of rms over n tones).
    pub amp: f64,
    /// Amplitude times v(t) / speed_ref \[m/s\]. Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_ref: Option<f64>,
    /// Frequencies \[Hz\].
    pub freq: Vec<f64>,
    /// Phases \[rad\], one per frequency.
    pub phase: Vec<f64>,
}

/// The prescribed motion as a scenario file gives it (MODEL.md 7.7): angles in degrees,
/// speed in m/s, heave in m, vibration in m/s^2.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// Roll terms \[deg\].
    #[serde(default)]
    pub roll: Vec<Term>,
    /// Pitch terms \[deg\].
    #[serde(default)]
    pub pitch: Vec<Term>,
    /// Yaw terms \[deg\].
    #[serde(default)]
    pub yaw: Vec<Term>,
    /// Forward speed v(t) of O \[m/s\]: const, ramp, sigmoid, bump, sine.
    #[serde(default)]
    pub speed: Vec<Shape>,
    /// Heave z_h(t), world z \[m\]: sines, optionally per speed.
    #[serde(default)]
    pub heave: Vec<Term>,
    /// The engine whose phase `engine` terms follow.
    #[serde(default)]
    pub engine: EngineSpec,
    /// Vibration, body axes.
    #[serde(default)]
    pub vibration: Vec<Vibration>,
    /// Broadband vibration, body axes.
    #[serde(default)]
    pub broadband: Vec<Tones>,
}

impl MotionSpec {
    /// Checks every term: finite values, each shape where it may be.
    pub fn validate(&self) -> Result<(), SimError> {
        let bad = |key: String, reason: String| Err(SimError::invalid(key, reason));
        for (name, terms) in [
            ("roll", &self.roll),
            ("pitch", &self.pitch),
            ("yaw", &self.yaw),
            ("heave", &self.heave),
        ] {
            for (i, term) in terms.iter().enumerate() {
                let key = format!("motion.{name}[{i}]");
                term.shape.check().or_else(|e| bad(key.clone(), e))?;
                let lateral = matches!(term.shape, Shape::Lateral { .. });
                if lateral && name != "roll" {
                    return bad(key, "a lateral term belongs to roll".into());
                }
                if term.path && !matches!(name, "pitch" | "yaw") {
                    return bad(key, "only pitch and yaw terms may be `path`".into());
                }
                if term.path && term.is_engine() {
                    return bad(key, "an engine-locked term cannot be `path`".into());
                }
                if name == "heave" && !matches!(term.shape, Shape::Sine { .. }) {
                    return bad(key, "the heave is a sum of sines".into());
                }
                check_speed_ref(&key, term.speed_ref)?;
                if lateral && term.speed_ref.is_some() {
                    return bad(key, "a lateral term already follows the speed".into());
                }
            }
        }
        for (i, s) in self.speed.iter().enumerate() {
            let key = format!("motion.speed[{i}]");
            s.check().or_else(|e| bad(key.clone(), e))?;
            if s.integral(0.0).is_none() {
                return bad(
                    key,
                    format!(
                        "a speed is const, ramp, sigmoid, bump or sine, not {}",
                        s.kind()
                    ),
                );
            }
        }
        let e = &self.engine;
        if !(e.f0.is_finite() && e.k_speed.is_finite())
            || e.mods.iter().any(|m| {
                !(m.df.is_finite() && m.fm.is_finite() && m.fm > 0.0 && m.phase.is_finite())
            })
        {
            return bad(
                "motion.engine".into(),
                "f0, k_speed, df and phase must be finite, fm > 0".into(),
            );
        }
        for (i, v) in self.vibration.iter().enumerate() {
            let key = format!("motion.vibration[{i}]");
            v.shape.check().or_else(|e| bad(key.clone(), e))?;
            if !matches!(v.shape, Shape::Sine { .. } | Shape::Engine { .. }) {
                return bad(key, "a vibration is a sine or an engine term".into());
            }
            check_speed_ref(&key, v.speed_ref)?;
        }
        for (i, b) in self.broadband.iter().enumerate() {
            let key = format!("motion.broadband[{i}]");
            if b.freq.len() != b.phase.len() {
                return bad(key, "freq and phase need one value per tone".into());
            }
            if !b.amp.is_finite() || b.freq.iter().chain(&b.phase).any(|x| !x.is_finite()) {
                return bad(key, "amp, freq and phase must be finite".into());
            }
            check_speed_ref(&key, b.speed_ref)?;
        }
        Ok(())
    }

    /// The same motion without vibration: no engine-locked angles, no vibration, no
    /// broadband (`--no-vibration`).
    pub fn without_vibration(mut self) -> Self {
        for terms in [&mut self.roll, &mut self.pitch, &mut self.yaw] {
            terms.retain(|t| !t.is_engine());
        }
        self.vibration.clear();
        self.broadband.clear();
        self
    }

    /// Whether any vibration (engine-locked angle, vibration or broadband) is present.
    pub fn has_vibration(&self) -> bool {
        [&self.roll, &self.pitch, &self.yaw]
            .iter()
            .any(|ts| ts.iter().any(Term::is_engine))
            || !self.vibration.is_empty()
            || !self.broadband.is_empty()
    }
}

fn check_speed_ref(key: &str, r: Option<f64>) -> Result<(), SimError> {
    match r {
        Some(r) if !(r.is_finite() && r > 0.0) => Err(SimError::invalid(
            key,
            format!("speed_ref must be > 0 m/s, got {r:?}"),
        )),
        _ => Ok(()),
    }
}

/// The built motion (SI units, radians): a [`BodyMotion`] with the vehicle's forward speed.
#[derive(Debug, Clone)]
pub struct VehicleMotion {
    spec: MotionSpec,
    /// O - P1, body axes \[m\].
    speed_at: [f64; 3],
    /// (dt, per broadband set the (sin, cos) of each tone's angle over dt), for
    /// [`BodyMotion::fill`].
    tone_steps: RefCell<ToneSteps>,
}

/// A node step and each broadband tone's (sin, cos) of its angle over that step.
type ToneSteps = (f64, Vec<Vec<(f64, f64)>>);

/// One angle's jets: the whole angle, the vehicle's part (no engine-locked terms) and the
/// path's part.
#[derive(Debug, Clone, Copy)]
struct AngleJets {
    full: Jet,
    vehicle: Jet,
    path: Jet,
}

fn angle_jets(terms: &[Term], t: f64, ctx: &Context) -> AngleJets {
    let mut a = AngleJets {
        full: ZERO,
        vehicle: ZERO,
        path: ZERO,
    };
    for term in terms {
        let x = term.eval(t, ctx);
        a.full = add(a.full, x);
        if !term.is_engine() {
            a.vehicle = add(a.vehicle, x);
        }
        if term.path {
            a.path = add(a.path, x);
        }
    }
    a
}

fn euler(r: Jet, p: Jet, y: Jet) -> [[f64; 3]; 3] {
    [[r[0], r[1], r[2]], [p[0], p[1], p[2]], [y[0], y[1], y[2]]]
}

/// The vehicle's state at one instant: everything [`VehicleMotion`] derives from t.
#[derive(Debug, Clone, Copy)]
pub struct VehicleState {
    /// v and its derivatives \[m/s ...\].
    pub speed: Jet,
    /// psi_e and its derivatives \[rad ...\].
    pub engine: Jet,
    /// (roll, pitch, yaw) with their derivatives, every term \[rad ...\].
    pub euler: [[f64; 3]; 3],
    /// The same without the engine-locked terms: the vehicle's attitude.
    pub vehicle_euler: [[f64; 3]; 3],
    /// Direction of travel d, world axes.
    pub direction: [f64; 3],
    /// d' \[1/s\].
    pub direction_rate: [f64; 3],
    /// z_h and its derivatives \[m ...\].
    pub heave: Jet,
}

impl VehicleState {
    /// V_O = v d + z_h' e_z, world axes \[m/s\].
    pub fn velocity(&self) -> [f64; 3] {
        let (v, d) = (self.speed[0], self.direction);
        [v * d[0], v * d[1], v * d[2] + self.heave[1]]
    }

    /// a_O = v' d + v d' + z_h'' e_z, world axes \[m/s^2\].
    pub fn acceleration(&self) -> [f64; 3] {
        let (v, d, dd) = (self.speed, self.direction, self.direction_rate);
        core::array::from_fn(|i| {
            v[1] * d[i] + v[0] * dd[i] + if i == 2 { self.heave[2] } else { 0.0 }
        })
    }
}

impl VehicleMotion {
    /// Builds `spec` (validated; degrees to radians) for a speed point O at P1 + `speed_at`
    /// (body axes, m).
    pub fn new(spec: &MotionSpec, speed_at: [f64; 3]) -> Result<Self, SimError> {
        spec.validate()?;
        if speed_at.iter().any(|x| !x.is_finite()) {
            return Err(SimError::invalid(
                "mounting.speed_at",
                format!("must be finite, got {speed_at:?}"),
            ));
        }
        let k = 1f64.to_radians();
        let mut s = spec.clone();
        for terms in [&mut s.roll, &mut s.pitch, &mut s.yaw] {
            for term in terms.iter_mut() {
                term.shape = term.shape.scaled(k);
            }
        }
        Ok(Self {
            spec: s,
            speed_at,
            tone_steps: RefCell::new((f64::NAN, Vec::new())),
        })
    }

    /// The built spec (angles in radians).
    pub fn spec(&self) -> &MotionSpec {
        &self.spec
    }

    /// v and its first three derivatives, and int_0^t v.
    fn speed_jet(&self, t: f64) -> (Jet, f64) {
        let ctx = Context::default();
        let v = timefn::eval_sum(&self.spec.speed, t, &ctx);
        let int = self
            .spec
            .speed
            .iter()
            .filter_map(|s| s.integral(t))
            .sum::<f64>();
        (v, int)
    }

    /// psi_e and its derivatives, given v's jet and integral.
    fn engine_jet(&self, t: f64, v: Jet, v_int: f64) -> Jet {
        let e = &self.spec.engine;
        let mut f = [e.f0 * t + e.k_speed * v_int, e.f0, 0.0, 0.0];
        for i in 0..3 {
            f[i + 1] += e.k_speed * v[i];
        }
        for m in &e.mods {
            let w = TAU * m.fm;
            let (s, c) = (w * t + m.phase).sin_cos();
            f[0] += m.df / w * (m.phase.cos() - c);
            f[1] += m.df * s;
            f[2] += m.df * w * c;
            f[3] -= m.df * w * w * s;
        }
        scale(f, TAU)
    }

    /// Everything derived from t (no vibration).
    pub fn state(&self, t: f64, gravity: f64) -> VehicleState {
        let (v, v_int) = self.speed_jet(t);
        let mut ctx = Context {
            speed: v,
            engine: self.engine_jet(t, v, v_int),
            lateral_g: ZERO,
        };
        let yaw = angle_jets(&self.spec.yaw, t, &ctx);
        let pitch = angle_jets(&self.spec.pitch, t, &ctx);
        // a_lat / g = v yaw_path' / g (its third derivative would need yaw_path'''').
        let yp = yaw.path;
        let mut lat = scale(mul(v, [yp[1], yp[2], yp[3], 0.0]), 1.0 / gravity);
        lat[3] = 0.0;
        ctx.lateral_g = lat;
        let roll = angle_jets(&self.spec.roll, t, &ctx);
        let (sy, cy) = yaw.path[0].sin_cos();
        let (sp, cp) = pitch.path[0].sin_cos();
        let (yd, pd) = (yaw.path[1], pitch.path[1]);
        VehicleState {
            speed: v,
            engine: ctx.engine,
            euler: euler(roll.full, pitch.full, yaw.full),
            vehicle_euler: euler(roll.vehicle, pitch.vehicle, yaw.vehicle),
            direction: [cy * cp, sy * cp, -sp],
            direction_rate: [
                -yd * sy * cp - pd * cy * sp,
                yd * cy * cp - pd * sy * sp,
                -pd * cp,
            ],
            heave: self.heave(t, &ctx),
        }
    }

    fn heave(&self, t: f64, ctx: &Context) -> Jet {
        self.spec
            .heave
            .iter()
            .fold(ZERO, |acc, h| add(acc, h.eval(t, ctx)))
    }

    /// The vibration acceleration in body axes at t \[m/s^2\]; `tones[i]` is the sum of
    /// broadband set i's sines at t.
    fn vibration(&self, t: f64, ctx: &Context, tones: &[f64]) -> [f64; 3] {
        let mut a = [0.0; 3];
        let factor = |r: Option<f64>| r.map_or(1.0, |r| ctx.speed[0] / r);
        for v in &self.spec.vibration {
            a[v.axis.index()] += factor(v.speed_ref) * v.shape.eval(t, ctx)[0];
        }
        for (b, sum) in self.spec.broadband.iter().zip(tones) {
            a[b.axis.index()] += factor(b.speed_ref) * b.amp * sum;
        }
        a
    }

    /// Each broadband set's sum of sines at t.
    fn tone_sums(&self, t: f64) -> Vec<f64> {
        self.spec
            .broadband
            .iter()
            .map(|b| {
                let mut sum = 0.0;
                for (f, p) in b.freq.iter().zip(&b.phase) {
                    sum += (TAU * f * t + p).sin();
                }
                sum
            })
            .collect()
    }

    /// Each broadband set's sums of sines at t0 + j dt, j < n (`out[i * n + j]`): one
    /// sin_cos per tone at t0, then rotations by the tone's step angle (cached for `dt`), so
    /// the value at t0 is [`Self::tone_sums`]'s to the bit and the others agree to rounding.
    fn tone_sums_grid(&self, t0: f64, dt: f64, n: usize) -> Vec<f64> {
        let mut cache = self.tone_steps.borrow_mut();
        if cache.0 != dt || cache.1.len() != self.spec.broadband.len() {
            cache.0 = dt;
            cache.1 = self
                .spec
                .broadband
                .iter()
                .map(|b| b.freq.iter().map(|f| (TAU * f * dt).sin_cos()).collect())
                .collect();
        }
        let mut out = vec![0.0; self.spec.broadband.len() * n];
        for ((b, steps), sums) in self
            .spec
            .broadband
            .iter()
            .zip(&cache.1)
            .zip(out.chunks_mut(n.max(1)))
        {
            for ((f, p), &(sd, cd)) in b.freq.iter().zip(&b.phase).zip(steps) {
                let (mut s, mut c) = (TAU * f * t0 + p).sin_cos();
                for (j, sum) in sums.iter_mut().enumerate() {
                    if j > 0 {
                        (s, c) = (s * cd + c * sd, c * cd - s * sd);
                    }
                    *sum += s;
                }
            }
        }
        out
    }

    /// The translational vibration of MODEL.md 7.7 (the engine-locked and sine terms and
    /// the broadband tones, body axes at P1) at t0 + j dt, j < n \[m/s^2\]: what a replay
    /// adds to a recorded specific force (MODEL.md 7.10). The body's own motion (its
    /// angles, speed and heave) is left out, but for the speed that scales the terms that
    /// follow it.
    pub fn vibration_grid(&self, t0: f64, dt: f64, n: usize) -> Vec<[f64; 3]> {
        let sets = self.spec.broadband.len();
        let grid = self.tone_sums_grid(t0, dt, n);
        let mut tones = vec![0.0; sets];
        (0..n)
            .map(|j| {
                let t = t0 + j as f64 * dt;
                for (i, x) in tones.iter_mut().enumerate() {
                    *x = grid[i * n + j];
                }
                let (v, v_int) = self.speed_jet(t);
                let ctx = Context {
                    speed: v,
                    engine: self.engine_jet(t, v, v_int),
                    lateral_g: ZERO,
                };
                self.vibration(t, &ctx, &tones)
            })
            .collect()
    }

    /// The kinematics at t with the broadband sums `tones` (one per set).
    fn kinematics_with(&self, t: f64, g: f64, tones: &[f64]) -> BodyKinematics {
        let s = self.state(t, g);
        let e = &s.euler;
        let r = attitude(e[0][0], e[1][0], e[2][0]);
        let ve = &s.vehicle_euler;
        let rs = attitude(ve[0][0], ve[1][0], ve[2][0]);
        let (ws, wds) = body_rate(s.vehicle_euler);
        let arm = self.speed_at.map(|x| -x);
        let lever_b = {
            let a = cross(wds, arm);
            let c = cross(ws, cross(ws, arm));
            [a[0] + c[0], a[1] + c[1], a[2] + c[2]]
        };
        let lever: [f64; 3] = core::array::from_fn(|i| (0..3).map(|j| rs[i][j] * lever_b[j]).sum());
        let a_o = s.acceleration();
        let f = world_to_body(
            &r,
            [a_o[0] + lever[0], a_o[1] + lever[1], a_o[2] + lever[2] + g],
        );
        let ctx = Context {
            speed: s.speed,
            engine: s.engine,
            lateral_g: ZERO,
        };
        let vib = self.vibration(t, &ctx, tones);
        BodyKinematics::from_euler(s.euler, [f[0] + vib[0], f[1] + vib[1], f[2] + vib[2]])
    }
}

impl BodyMotion for VehicleMotion {
    fn kinematics(&self, t: f64, g: f64) -> BodyKinematics {
        self.kinematics_with(t, g, &self.tone_sums(t))
    }

    /// The broadband tones by rotation from t0 (most of a vibrating run's cost is in them).
    fn fill(&self, t0: f64, dt: f64, g: f64, out: &mut [BodyKinematics]) {
        let n = out.len();
        let sets = self.spec.broadband.len();
        let grid = self.tone_sums_grid(t0, dt, n);
        let mut tones = vec![0.0; sets];
        for (j, o) in out.iter_mut().enumerate() {
            for (i, x) in tones.iter_mut().enumerate() {
                *x = grid[i * n + j];
            }
            *o = self.kinematics_with(t0 + j as f64 * dt, g, &tones);
        }
    }

    /// x_b . V_O with x_b the vehicle's body x (the engine-locked angles left out, like
    /// the vibration's velocity: MODEL.md 7.7).
    fn speed(&self, t: f64, g: f64) -> f64 {
        let s = self.state(t, g);
        let e = &s.vehicle_euler;
        let r = attitude(e[0][0], e[1][0], e[2][0]);
        let v = s.velocity();
        r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2]
    }
}
