//! Replay: a virtual pendulum on a recorded IMU (MODEL.md 7.10).
//!
//! The simulator's Cardan pendulum (7.3) is driven by a recording instead of a prescribed
//! motion: the gyro (bias removed, smoothed, splined), its derivative and the specific force
//! moved from the IMU to the pivot. The result is a 7.6 log: the IMU's columns as recorded,
//! the encoders the pendulum would have read, and the truth when the recording has one.
//! It answers a user's first question, *would a pendulum help on my device?*, on their own
//! recordings, before they build anything.
//!
//! As recorded, the encoders are a deterministic function of the recorded IMU: such a
//! replay tests a filter's robustness on real motion, not the pendulum's benefit (7.10).
//!
//! - [`drive`]: the recorded IMU as w, wd and f at the pivot between samples;
//! - [`source`]: reading a recording (an IMU CSV, or a BROAD MAT file);
//! - this module: the integration, the joint stops and the encoders.
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::sim::planar::integrator::{rk4_step, Node};
use crate::sim::spatial::{JointState, LogRow3d, Pendulum3d, Scenario3d, VehicleMotion};

pub mod benchmark;
pub mod drive;
pub mod output;
pub mod source;

pub use drive::{Drive, Rest};
pub use source::Recording;

/// How the virtual pendulum is built and read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplaySettings {
    /// The pendulum (MODEL.md 7.6's `[pendulum3d]`); its `pivot_offset` is r12 from the
    /// IMU. Its `gravity` is replaced by the recording's own (the mean |a| at rest).
    pub pendulum: Pendulum3d,
    /// Encoder resolution \[bits\] (0: none). Default 14, MODEL.md 7.8's encoders.
    pub encoder_bits: u32,
    /// Encoder white noise, one sigma \[rad\]. Default 0.01 deg, MODEL.md 7.8's.
    pub encoder_noise: f64,
    /// Mechanical travel of the outer and inner joints, |a| and |b| \[rad\]: a stop there
    /// (a real rig cannot swing through 180 deg). Default none.
    pub travel: Option<[f64; 2]>,
    /// Restitution at a stop: the joint rate reverses and scales by this. Default 0.3.
    pub restitution: f64,
    /// RK4 steps per sample interval (at least 4, MODEL.md 7.10). Default 4.
    pub substeps: u32,
    /// Seed of the encoder noise.
    pub seed: u64,
}

impl Default for ReplaySettings {
    fn default() -> Self {
        Self {
            pendulum: Pendulum3d::default(),
            encoder_bits: 14,
            encoder_noise: 0.01f64.to_radians(),
            travel: None,
            restitution: 0.3,
            substeps: 4,
            seed: 1,
        }
    }
}

/// A vehicle's vibration added to a recording (MODEL.md 7.10, `replay --vibration`): the
/// pendulum is driven by the recorded motion plus the vibration, at 1 kHz or more, and the
/// accelerometer columns are what a MEMS without an anti-alias filter reads at the log's
/// times, aliased and clipped. As recorded, the encoders are a function of the IMU's own
/// readings; with a vibration the pendulum's mechanical filtering before sampling shows.
#[derive(Debug, Clone)]
pub struct AddedVibration {
    /// The scenario whose translational vibration (engine-locked and broadband terms, body
    /// axes at P1; MODEL.md 7.7, 7.8) is added.
    pub scenario: String,
    /// Its motion (only the vibration terms are used).
    pub motion: VehicleMotion,
    /// Amplitude per axis of the tone [`Self::alias_offset_hz`] below the log's sampling
    /// rate \[m/s^2\]: an engine harmonic that a MEMS sampled without an anti-alias filter
    /// folds down to that offset. Default (3, 3, 2), MODEL.md 7.10.
    pub alias_tone: [f64; 3],
    /// How far below the sampling rate the tone lies \[Hz\]. Default 0.7.
    pub alias_offset_hz: f64,
    /// The accelerometer's full scale \[m/s^2\]: its readings are clipped there. Default
    /// 2 g (19.6 m/s^2), a consumer MEMS's.
    pub accel_full_scale: f64,
    /// Longest integration step \[s\]: the vibration reaches 200 Hz. Default 0.25 ms.
    pub max_step: f64,
}

impl AddedVibration {
    /// The vibration of the named 3-D scenario (its random tones from `seed`), with MODEL.md
    /// 7.10's tone and a 2 g accelerometer.
    pub fn of_scenario(name: &str, seed: u64) -> Result<Self, ReplayError> {
        let s = Scenario3d::named(name, seed).map_err(|e| ReplayError::Setting(e.to_string()))?;
        let motion = VehicleMotion::new(&s.motion, s.rig.mounting.speed_at)
            .map_err(|e| ReplayError::Setting(e.to_string()))?;
        Ok(Self {
            scenario: name.to_string(),
            motion,
            alias_tone: [3.0, 3.0, 2.0],
            alias_offset_hz: 0.7,
            accel_full_scale: 2.0 * 9.80665,
            max_step: 2.5e-4,
        })
    }

    /// The vibration at `t0 + j dt`, j < n, for a log sampled at `fs` Hz: the scenario's and
    /// the tone \[m/s^2\].
    fn grid(&self, t0: f64, dt: f64, n: usize, fs: f64) -> Vec<[f64; 3]> {
        let w = std::f64::consts::TAU * (fs - self.alias_offset_hz);
        let mut v = self.motion.vibration_grid(t0, dt, n);
        for (j, x) in v.iter_mut().enumerate() {
            let s = (w * (t0 + j as f64 * dt)).sin();
            for (xi, a) in x.iter_mut().zip(self.alias_tone) {
                *xi += a * s;
            }
        }
        v
    }
}

/// What the added vibration did to the accelerometer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VibrationReport {
    /// The tone's frequency \[Hz\] and where it folds to in the log \[Hz\].
    pub tone_hz: [f64; 2],
    /// Rows with an accelerometer axis clipped at the full scale.
    pub clipped_rows: usize,
    /// RMS per axis of what was added to the accelerometer's readings \[m/s^2\].
    pub added_rms: [f64; 3],
}

/// The largest change of a joint angle when the substeps are doubled that the replay
/// accepts without a word \[rad\] (MODEL.md 7.10).
pub const SUBSTEP_TOLERANCE: f64 = 1e-4;

/// What a replay found and did, for the user.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayReport {
    /// The initial rest (bias, gravity, first movement), when the recording has one.
    pub rest: Option<Rest>,
    /// The g that drove the pendulum \[m/s^2\].
    pub gravity: f64,
    /// Gyro and accelerometer values that were missing and interpolated across.
    pub filled: [usize; 2],
    /// Largest change of a or b when the substeps were doubled \[rad\].
    pub substep_change: f64,
    /// Times each joint hit its stop.
    pub stop_hits: [u64; 2],
    /// Largest |a| and |b| reached \[rad\].
    pub largest_swing: [f64; 2],
    /// The gyro's zero-phase low-pass cutoff \[Hz\].
    pub cutoff_hz: f64,
    /// RK4 steps per sample interval used.
    pub substeps: u32,
    /// What an added vibration did, when one was added.
    pub vibration: Option<VibrationReport>,
}

/// A replay: one 7.6 log row per recorded row, and the report.
#[derive(Debug, Clone)]
pub struct Replay {
    /// The log rows (`speed` is NaN: a replay has none).
    pub rows: Vec<LogRow3d>,
    /// What was found.
    pub report: ReplayReport,
    /// The pendulum as it was driven (its `gravity` the recording's).
    pub pendulum: Pendulum3d,
}

/// Why a recording cannot be replayed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ReplayError {
    /// Fewer than 2 rows.
    #[error("{0}: fewer than 2 rows: nothing to replay")]
    TooShort(String),
    /// A whole sensor column is missing.
    #[error("{origin}: no finite {what} value in the whole recording")]
    NoValues {
        /// The recording.
        origin: String,
        /// Which sensor.
        what: &'static str,
    },
    /// A setting out of range.
    #[error("{0}")]
    Setting(String),
}

/// The joint state (a, b, a', b') as RK4 integrates it.
fn to_joint(y: &[f64; 4]) -> JointState {
    JointState {
        a: y[0],
        b: y[1],
        a_dot: y[2],
        b_dot: y[3],
    }
}

/// Integrates the pendulum over the drive; `substeps` RK4 steps per interval. Returns the
/// joint state at every sample, the stop hits and the largest swing.
fn integrate(
    drive: &Drive,
    pend: &Pendulum3d,
    start: JointState,
    substeps: u32,
    stops: Option<([f64; 2], f64)>,
    vib: Option<(&AddedVibration, f64)>,
) -> (Vec<JointState>, [u64; 2], [f64; 2]) {
    let t = drive.times();
    let n = t.len();
    let mut out = Vec::with_capacity(n);
    let mut y = [start.a, start.b, start.a_dot, start.b_dot];
    let mut hits = [0u64; 2];
    let mut swing = [0f64; 2];
    let rhs = |k: usize, tau: f64, extra: [f64; 3], y: [f64; 4]| -> [f64; 4] {
        let d = drive.at(k, tau);
        let f = [d.f[0] + extra[0], d.f[1] + extra[1], d.f[2] + extra[2]];
        let [add, bdd] = pend.joint_accelerations(&to_joint(&y), d.w, d.wd, f);
        [y[2], y[3], add, bdd]
    };
    let mut grid = Vec::new();
    for k in 0..n {
        out.push(to_joint(&y));
        swing[0] = swing[0].max(y[0].abs());
        swing[1] = swing[1].max(y[1].abs());
        if k + 1 == n {
            break;
        }
        let h = (t[k + 1] - t[k]) / f64::from(substeps);
        if let Some((v, fs)) = vib {
            // The vibration at every RK4 node of the interval (start, middle, end of each
            // step).
            grid = v.grid(t[k], 0.5 * h, 2 * substeps as usize + 1, fs);
        }
        for j in 0..substeps {
            let t0 = f64::from(j) * h;
            y = rk4_step(y, h, |node, y| {
                let (tau, i) = match node {
                    Node::Start => (t0, 2 * j as usize),
                    Node::Mid => (t0 + 0.5 * h, 2 * j as usize + 1),
                    Node::End => (t0 + h, 2 * j as usize + 2),
                };
                rhs(k, tau, grid.get(i).copied().unwrap_or([0.0; 3]), y)
            });
            if let Some((travel, e)) = stops {
                for i in 0..2 {
                    let lim = travel[i];
                    if y[i].abs() > lim {
                        // The stop: back inside by the overshoot, the rate reversed and
                        // scaled by the restitution (only when moving into the stop).
                        let s = y[i].signum();
                        y[i] = s * lim - (y[i] - s * lim) * e;
                        if y[2 + i] * s > 0.0 {
                            y[2 + i] *= -e;
                        }
                        hits[i] += 1;
                    }
                }
            }
        }
    }
    (out, hits, swing)
}

/// Wraps an angle to (-pi, pi].
pub fn wrap_pi(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let mut v = x.rem_euclid(TAU);
    if v > PI {
        v -= TAU;
    }
    v
}

/// The encoders' reading of the joint angles: (-a, -b) + white noise, rounded to the
/// resolution, wrapped to (-pi, pi] (MODEL.md 7.5, 7.10).
fn read_encoders(s: &JointState, settings: &ReplaySettings, rng: &mut ChaCha8Rng) -> [f64; 2] {
    let q = (settings.encoder_bits > 0)
        .then(|| std::f64::consts::TAU / 2f64.powi(settings.encoder_bits as i32));
    s.encoders().map(|v| {
        let noise: f64 = rng.sample(StandardNormal);
        let v = v + settings.encoder_noise * noise;
        wrap_pi(q.map_or(v, |q| (v / q).round() * q))
    })
}

/// Roll and pitch \[rad\] from the mean specific force over the first `secs` seconds
/// (MODEL.md 7.1: roll = atan2(f_y, f_z), pitch = atan2(-f_x, sqrt(f_y^2 + f_z^2))).
fn initial_tilt(t: &[f64], accel: &[[f64; 3]], secs: f64) -> (f64, f64) {
    let mut m = [0.0; 3];
    let mut c = 0.0;
    for (k, a) in accel.iter().enumerate() {
        if k > 0 && t[k] - t[0] > secs {
            break;
        }
        for i in 0..3 {
            m[i] += a[i];
        }
        c += 1.0;
    }
    let f = m.map(|x| x / c);
    (f[1].atan2(f[2]), (-f[0]).atan2(f[1].hypot(f[2])))
}

impl ReplaySettings {
    fn validate(&self) -> Result<(), ReplayError> {
        let bad = |m: String| Err(ReplayError::Setting(m));
        if !(4..=10_000).contains(&self.substeps) {
            return bad(format!(
                "substeps: must be 4 to 10000 (MODEL.md 7.10), got {}",
                self.substeps
            ));
        }
        if self.encoder_bits > 32 {
            return bad(format!(
                "encoder bits: must be 0 to 32, got {}",
                self.encoder_bits
            ));
        }
        if !(self.encoder_noise.is_finite() && self.encoder_noise >= 0.0) {
            return bad(format!(
                "encoder noise: must be >= 0, got {}",
                self.encoder_noise
            ));
        }
        if let Some(tr) = self.travel {
            if tr
                .iter()
                .any(|x| !(x.is_finite() && *x > 0.0 && *x < std::f64::consts::PI))
            {
                return bad(format!(
                    "travel: must be between 0 and 180 deg, got {:.1}, {:.1} deg",
                    tr[0].to_degrees(),
                    tr[1].to_degrees()
                ));
            }
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return bad(format!(
                "restitution: must be 0 to 1, got {}",
                self.restitution
            ));
        }
        self.pendulum
            .validate()
            .map_err(|e| ReplayError::Setting(e.to_string()))
    }
}

/// Replays `rec` through the pendulum of `settings` (MODEL.md 7.10), as recorded.
pub fn replay(rec: &Recording, settings: &ReplaySettings) -> Result<Replay, ReplayError> {
    replay_with(rec, settings, None)
}

/// Replays `rec` through the pendulum of `settings` with a vehicle's vibration added
/// ([`AddedVibration`]), or as recorded.
pub fn replay_with(
    rec: &Recording,
    settings: &ReplaySettings,
    vibration: Option<&AddedVibration>,
) -> Result<Replay, ReplayError> {
    settings.validate()?;
    let n = rec.t.len();
    if n < 2 {
        return Err(ReplayError::TooShort(rec.origin.clone()));
    }
    let t = &rec.t;
    let (mut gyro, mut accel) = (rec.gyro.clone(), rec.accel.clone());
    let no_values = |what| ReplayError::NoValues {
        origin: rec.origin.clone(),
        what,
    };
    let filled = [
        drive::fill_gaps(t, &mut gyro).ok_or_else(|| no_values("gyro"))?,
        drive::fill_gaps(t, &mut accel).ok_or_else(|| no_values("accelerometer"))?,
    ];
    let rest = Rest::find(t, &gyro, &accel, rec.movement);
    let gravity = rest.map_or(settings.pendulum.gravity, |r| r.gravity);
    let pend = Pendulum3d {
        gravity,
        ..settings.pendulum
    };
    let fs = (n - 1) as f64 / (t[n - 1] - t[0]);
    let cutoff_hz = drive::GYRO_CUTOFF_HZ.min(0.4 * fs);
    let bias = rest.map_or([0.0; 3], |r| r.gyro_bias);
    let drive = Drive::new(t, &gyro, &accel, bias, cutoff_hz, pend.pivot_offset);
    let (roll0, pitch0) = initial_tilt(t, &accel, 0.5);
    let start = JointState::hanging_still(roll0, pitch0, drive.rate(0));
    let stops = settings.travel.map(|tr| (tr, settings.restitution));
    let substeps = substeps(settings, vibration, t);
    let vib = vibration.map(|v| (v, fs));
    let (joints, stop_hits, largest_swing) = integrate(&drive, &pend, start, substeps, stops, vib);
    let (fine, _, _) = integrate(&drive, &pend, start, 2 * substeps, stops, vib);
    let substep_change = joints
        .iter()
        .zip(&fine)
        .map(|(a, b)| (a.a - b.a).abs().max((a.b - b.b).abs()))
        .fold(0.0, f64::max);
    let mut rng = ChaCha8Rng::seed_from_u64(settings.seed);
    // The accelerometer: as recorded, or with the vibration read at the log's times and
    // clipped at the full scale.
    let mut accel_out = rec.accel.clone();
    let vibration_report = vibration.map(|v| add_vibration(&mut accel_out, v, t, fs));
    let rows = (0..n)
        .map(|k| {
            let truth = rec.truth.as_ref().map(|r| r[k]);
            LogRow3d {
                t: t[k],
                phi: read_encoders(&joints[k], settings, &mut rng),
                gyro: rec.gyro[k],
                accel: accel_out[k],
                speed: f64::NAN,
                roll: truth.map_or(f64::NAN, |r| r[0]),
                pitch: truth.map_or(f64::NAN, |r| r[1]),
            }
        })
        .collect();
    Ok(Replay {
        rows,
        report: ReplayReport {
            rest,
            gravity,
            filled,
            substep_change,
            stop_hits,
            largest_swing,
            cutoff_hz,
            substeps,
            vibration: vibration_report,
        },
        pendulum: pend,
    })
}

/// The integrator's substeps per row: the settings', or with a vibration 1 kHz or more,
/// fine enough for its tones.
fn substeps(settings: &ReplaySettings, vibration: Option<&AddedVibration>, t: &[f64]) -> u32 {
    match vibration {
        Some(v) => {
            let longest = (1..t.len()).map(|k| t[k] - t[k - 1]).fold(0.0, f64::max);
            settings
                .substeps
                .max((longest / v.max_step).ceil().min(10_000.0) as u32)
        }
        None => settings.substeps,
    }
}

/// Adds vibration `v`, read at the log's times `t` (rate `fs`), to the accelerometer
/// readings `accel`, clipped at its full scale.
fn add_vibration(
    accel: &mut [[f64; 3]],
    v: &AddedVibration,
    t: &[f64],
    fs: f64,
) -> VibrationReport {
    let (mut clipped, mut sq) = (0usize, [0.0; 3]);
    for (k, a) in accel.iter_mut().enumerate() {
        let add = v.grid(t[k], 0.0, 1, fs)[0];
        let mut clip = false;
        for i in 0..3 {
            sq[i] += add[i] * add[i];
            let x = a[i] + add[i];
            a[i] = x.clamp(-v.accel_full_scale, v.accel_full_scale);
            clip |= x.abs() > v.accel_full_scale;
        }
        clipped += usize::from(clip);
    }
    let tone = fs - v.alias_offset_hz;
    VibrationReport {
        tone_hz: [tone, (tone - fs * (tone / fs).round()).abs()],
        clipped_rows: clipped,
        added_rms: sq.map(|s| (s / t.len() as f64).sqrt()),
    }
}

#[cfg(test)]
mod tests;
