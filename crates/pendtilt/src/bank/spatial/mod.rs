//! The 3-D estimator bank: every estimator `pendtilt estimate` runs on a
//! 3-D log (MODEL.md 7.6), built from the rig and the sensors, run side by side one
//! [`SpatialSample`] at a time.
//!
//! [`REGISTRY3D`] is the list of constructors, one per 3-D row of the catalogue
//! ([`crate::catalogue`], which gives each one's name, sensors and description): the bank,
//! `--only` and the list of valid names in its error all come from it. Adding a 3-D
//! estimator is a catalogue row and an entry here (and, if it has an attitude quaternion,
//! implementing [`Runner3d::quaternion`]).
//!
//! A sensor missing for longer than [`Bank3d::restart_gap`] (default the planar bank's
//! [`RESTART_GAP`]) restarts the estimators that read it ([`Entry3d::reads`]) at its next
//! good reading, with [`Estimator::resume`], as the planar bank does.
//!
//! - [`rig`]: the rig file's `[pendulum3d]` (physical or normalised) and `[mounting]`;
//! - [`score`]: the inclination error of MODEL.md 7.9 accumulated per estimator.
use pendtilt_core::spatial::accel::{Accel, AccelSettings};
use pendtilt_core::spatial::cardan::CardanParams;
use pendtilt_core::spatial::ekf::{self, Ekf, Ukf};
use pendtilt_core::spatial::inv::{Inv3d, Inv3dSettings};
use pendtilt_core::spatial::pendulum::{Pendulum, PendulumSettings};
use pendtilt_core::spatial::{Attitude, Mounting, SpatialSample};
use pendtilt_core::{Estimator, Flags};

use crate::catalogue::{self, Listing};
use crate::peers::fusion::FusionSettings;
use crate::peers::spatial::{
    fusion3d, madgwick3d, mahony3d, vqf, Imu6, ImuFilter, MADGWICK3D_BETA, MAHONY3D_GAINS,
    VQF_TAU_ACC,
};
use crate::sensors::{GapEnd, GapWatch, Inputs, Sensor, RESTART_GAP};
use crate::sim::spatial::Sensors3d;

pub mod ride;
pub mod rig;
pub mod score;

/// What the 3-D estimators are built from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings3d {
    /// The spatial filter's settings; its `params` are the rig's pendulum (normalised),
    /// which `inv3d` uses too.
    pub ekf: ekf::Settings<f64>,
    /// `accel3d`'s settings.
    pub accel: AccelSettings<f64>,
}

impl Default for Settings3d {
    /// MODEL.md 7.6's rig and the core's defaults.
    fn default() -> Self {
        Self::new(CardanParams::default(), Mounting::default(), None)
    }
}

impl Settings3d {
    /// The settings for the pendulum `params`, where the sensors sit (`[mounting]`) and,
    /// when known, the sensors' figures (MODEL.md 7.5; a scenario file's `[sensors]`).
    /// Without them the spatial filter keeps its default noise figures.
    pub fn new(
        params: CardanParams<f64>,
        mounting: Mounting<f64>,
        sensors: Option<&Sensors3d>,
    ) -> Self {
        let mut ekf = ekf::Settings {
            params,
            mounting,
            ..ekf::Settings::default()
        };
        if let Some(s) = sensors {
            let n = &mut ekf.sensors;
            n.encoder_bits = s.encoder_bits;
            n.encoder_noise = s.encoder_noise;
            n.gyro_density = s.gyro_noise_density;
            n.gyro_bias_walk = s.gyro_bias_walk;
            n.accel_density = s.accel_noise_density;
            ekf.speed.noise = s.speed_noise;
        }
        Self {
            ekf,
            accel: AccelSettings::default(),
        }
    }

    /// `inv3d`'s settings: the spatial filter's pendulum, mounting and gyro full scale (its
    /// front end's), inv3d's own defaults otherwise.
    pub fn inv3d(&self) -> Inv3dSettings<f64> {
        let mut s = Inv3dSettings {
            mounting: self.ekf.mounting,
            ..Inv3dSettings::from_params(self.ekf.params)
        };
        s.front_end.gyro = self.ekf.gyro;
        s
    }

    /// The settings for a simulated scenario: its rig's pendulum and mounting and its
    /// sensors' figures, as `pendtilt estimate --scenario FILE` takes them.
    pub fn of_scenario(s: &crate::sim::spatial::Scenario3d) -> Self {
        let rig = rig::Pendulum3dConfig::Physical(s.rig.pendulum3d);
        Self::new(rig.params(), s.rig.mounting, Some(&s.sensors))
    }
}

/// A running 3-D estimator as the bank drives it: the spatial [`Estimator`] interface and,
/// where the estimator has one, its attitude quaternion.
pub trait Runner3d {
    /// One sample in, roll and pitch out (see [`Estimator::update`]).
    fn step(&mut self, s: &SpatialSample<f64>) -> Attitude<f64>;
    /// The attitude quaternion `[w, x, y, z]` (world <- body) after the last step, `None`
    /// when the estimator has none or has not started.
    fn quaternion(&self) -> Option<[f64; 4]> {
        None
    }
    /// Prepares to go on after a long gap ([`Estimator::resume`]).
    fn resume(&mut self);
    /// [`Self::step`] with a sample whose gyro `axes` read at a clip found in the log
    /// ([`Clips`]). Default: the clipped reading as it is (the closest bound to the rate).
    fn step_clipped(&mut self, s: &SpatialSample<f64>, _axes: [bool; 3]) -> Attitude<f64> {
        self.step(s)
    }
}

/// Clipping found in one row of the log, by the reader ([`crate::io::plateau`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Clips {
    /// The gyro axes read at a clip ([`Runner3d::step_clipped`]).
    pub gyro: [bool; 3],
    /// Whether the accelerometer reads at a clip (kept: its direction is still the one
    /// the filters have).
    pub accel: bool,
}

impl Clips {
    /// The sensors it concerns.
    pub fn sensors(&self) -> Inputs {
        let mut clipped = Inputs::NONE;
        if self.gyro.contains(&true) {
            clipped = clipped.with(Sensor::Gyro);
        }
        if self.accel {
            clipped = clipped.with(Sensor::Accel);
        }
        clipped
    }
}

/// The estimators without a quaternion of their own: roll and pitch only.
macro_rules! attitude_only {
    ($($t:ty),*) => {$(
        impl Runner3d for $t {
            fn step(&mut self, s: &SpatialSample<f64>) -> Attitude<f64> {
                self.update(s)
            }
            fn resume(&mut self) {
                Estimator::resume(self)
            }
        }
    )*};
}
attitude_only!(Pendulum<f64>, Accel<f64>, Inv3d<f64>);

impl<F: ImuFilter> Runner3d for Imu6<F> {
    fn step(&mut self, s: &SpatialSample<f64>) -> Attitude<f64> {
        self.update(s)
    }
    /// The clipped reading as it is; a long clip restarts the filter when it ends
    /// ([`Imu6::update_clipped`]).
    fn step_clipped(&mut self, s: &SpatialSample<f64>, _axes: [bool; 3]) -> Attitude<f64> {
        self.update_clipped(s, true)
    }
    fn resume(&mut self) {
        Estimator::resume(self)
    }
}

/// The model-based filters: their quaternion state.
macro_rules! with_quaternion {
    ($($t:ty),*) => {$(
        impl Runner3d for $t {
            fn step(&mut self, s: &SpatialSample<f64>) -> Attitude<f64> {
                self.update(s)
            }
            fn quaternion(&self) -> Option<[f64; 4]> {
                self.quaternion().map(|q| [q.w, q.i, q.j, q.k])
            }
            fn resume(&mut self) {
                Estimator::resume(self)
            }
            /// A clipped gyro axis is read as missing: the filter bridges it with its
            /// low-passed gyro and grows the attitude's variance, so the encoders carry
            /// the attitude (see `Clips` in docs/reliability.md section 8 for what this
            /// gave against the clipped rate).
            fn step_clipped(&mut self, s: &SpatialSample<f64>, axes: [bool; 3]) -> Attitude<f64> {
                self.update_clipped(s, axes)
            }
        }
    )*};
}
with_quaternion!(Ekf<f64>, Ukf<f64>);

/// One estimator of [`REGISTRY3D`].
#[derive(Debug, Clone, Copy)]
pub struct Entry3d {
    /// Its name, the prefix of its output columns.
    pub name: &'static str,
    /// Whether it gives an attitude quaternion (`--quaternion` columns).
    pub quaternion: bool,
    /// Builds it.
    pub build: fn(&Settings3d) -> Box<dyn Runner3d>,
}

/// The rig's gyro full scale, for the peers' `saturated` flag (ekf3d, ukf3d and inv3d's
/// front end read it from their settings).
fn full_scale(s: &Settings3d) -> Option<f64> {
    s.ekf.gyro.checked_full_scale()
}

impl Entry3d {
    /// Its row of the catalogue.
    pub fn listing(&self) -> &'static Listing {
        catalogue::expect(self.name)
    }

    /// The sensors it reads (`phi`: phi_x, phi_y; `gyro`: gyro_x..z; `accel`: ax..az): a
    /// long gap of one of them restarts it, an implausible reading flags it.
    pub fn reads(&self) -> Inputs {
        self.listing().reads
    }

    /// One line on what it is.
    pub fn about(&self) -> &'static str {
        self.listing().about
    }
}

/// Every 3-D estimator, in output column order (the catalogue's 3-D rows').
pub static REGISTRY3D: &[Entry3d] = &[
    Entry3d {
        name: "pendulum3d",
        quaternion: false,
        build: |_| Box::new(Pendulum::<f64>::new(PendulumSettings {})),
    },
    Entry3d {
        name: "accel3d",
        quaternion: false,
        build: |s| Box::new(Accel::new(s.accel)),
    },
    Entry3d {
        name: "inv3d",
        quaternion: false,
        build: |s| Box::new(Inv3d::<f64>::new(s.inv3d())),
    },
    Entry3d {
        name: "ekf3d",
        quaternion: true,
        build: |s| Box::new(Ekf::new(s.ekf)),
    },
    Entry3d {
        name: "ukf3d",
        quaternion: true,
        build: |s| Box::new(Ukf::new(s.ekf)),
    },
    Entry3d {
        name: "imu3d",
        quaternion: true,
        build: |s| Box::new(Ekf::new(s.ekf.imu_only())),
    },
    Entry3d {
        name: "vqf",
        quaternion: false,
        build: |s| Box::new(vqf(VQF_TAU_ACC).with_gyro_full_scale(full_scale(s))),
    },
    Entry3d {
        name: "madgwick3d",
        quaternion: false,
        build: |s| Box::new(madgwick3d(MADGWICK3D_BETA).with_gyro_full_scale(full_scale(s))),
    },
    Entry3d {
        name: "mahony3d",
        quaternion: false,
        build: |s| {
            Box::new(
                mahony3d(MAHONY3D_GAINS[0], MAHONY3D_GAINS[1]).with_gyro_full_scale(full_scale(s)),
            )
        },
    },
    Entry3d {
        name: "fusion3d",
        quaternion: false,
        build: |s| {
            Box::new(fusion3d(FusionSettings::default()).with_gyro_full_scale(full_scale(s)))
        },
    },
];

/// The names of [`REGISTRY3D`], comma-separated (for errors and help).
pub fn names3d() -> String {
    REGISTRY3D
        .iter()
        .map(|e| e.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The chosen 3-D estimators, run side by side.
pub struct Bank3d {
    entries: Vec<&'static Entry3d>,
    /// The sensors each entry reads, looked up in the catalogue once.
    reads: Vec<Inputs>,
    runners: Vec<Box<dyn Runner3d>>,
    out: Vec<Attitude<f64>>,
    /// A sensor missing for longer than this \[s\] restarts the estimators reading it at
    /// its next good reading. Default [`RESTART_GAP`].
    pub restart_gap: f64,
    gaps: GapWatch,
    restart: Option<(GapEnd, usize)>,
}

impl std::fmt::Debug for Bank3d {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bank3d")
            .field("names", &self.names())
            .finish_non_exhaustive()
    }
}

impl Bank3d {
    /// Every estimator of [`REGISTRY3D`], or only those named in `only` (in registry
    /// order); an unknown name is an error that lists the valid ones.
    pub fn new(settings: &Settings3d, only: Option<&[String]>) -> Result<Self, String> {
        if let Some(only) = only {
            let unknown: Vec<&str> = only
                .iter()
                .map(|n| n.trim())
                .filter(|n| !REGISTRY3D.iter().any(|e| e.name == *n))
                .collect();
            if !unknown.is_empty() {
                return Err(format!(
                    "--only: unknown 3-D estimator {}; the 3-D estimators are {}",
                    unknown.join(", "),
                    names3d()
                ));
            }
        }
        let entries: Vec<&'static Entry3d> = REGISTRY3D
            .iter()
            .filter(|e| only.is_none_or(|o| o.iter().any(|n| n.trim() == e.name)))
            .collect();
        if entries.is_empty() {
            return Err("--only: no estimator named".into());
        }
        Ok(Self {
            runners: entries.iter().map(|e| (e.build)(settings)).collect(),
            out: Vec::with_capacity(entries.len()),
            reads: entries.iter().map(|e| e.reads()).collect(),
            entries,
            restart_gap: RESTART_GAP,
            gaps: GapWatch::new(),
            restart: None,
        })
    }

    /// The names of the estimators it runs, in column order.
    pub fn names(&self) -> Vec<&'static str> {
        self.entries.iter().map(|e| e.name).collect()
    }

    /// Whether estimator `i` (in [`Self::names`] order) has a quaternion.
    pub fn has_quaternion(&self, i: usize) -> bool {
        self.entries[i].quaternion
    }

    /// One sample through every estimator: their outputs in [`Self::names`] order. A
    /// sensor back after a gap longer than [`Self::restart_gap`] first restarts the
    /// estimators that read it ([`Self::restarted`]).
    pub fn update(&mut self, s: &SpatialSample<f64>) -> &[Attitude<f64>] {
        self.update_clipped(s, Clips::default())
    }

    /// [`Self::update`] with sample `s`, some of whose readings are at a clip found in the
    /// log (`clips`): the estimators reading a clipped sensor flag [`Flags::SATURATED`],
    /// and those reading the gyro take a clipped axis their own way
    /// ([`Runner3d::step_clipped`]); a clip, however long, is no gap (it restarts nothing).
    pub fn update_clipped(&mut self, s: &SpatialSample<f64>, clips: Clips) -> &[Attitude<f64>] {
        self.restart = None;
        let clipped = clips.sensors();
        let good = Inputs::from_fn(|sensor| clipped.has(sensor) || s.complete(sensor));
        if let Some(r) = self.gaps.observe(s.dt, good, self.restart_gap) {
            let mut n = 0;
            for (reads, run) in self.reads.iter().zip(&mut self.runners) {
                if reads.intersects(r.sensors) {
                    run.resume();
                    n += 1;
                }
            }
            self.restart = Some((r, n));
        }
        self.out.clear();
        for r in &mut self.runners {
            let a = if clipped.has(Sensor::Gyro) {
                r.step_clipped(s, clips.gyro)
            } else {
                r.step(s)
            };
            self.out.push(a);
        }
        self.flag(clipped, Flags::SATURATED);
        // Beyond the restart gap a sensor's estimators have nothing to go on: what they
        // would give (a held or an integrated attitude, ukf3d 173 deg off during a 10 s
        // gap) is no estimate. They restart when it is back.
        let stale = self.gaps.stale();
        if !stale.is_empty() {
            for (o, reads) in self.out.iter_mut().zip(&self.reads) {
                if reads.intersects(stale) {
                    o.roll = f64::NAN;
                    o.pitch = f64::NAN;
                    o.flags |= Flags::SAMPLE_MISSING;
                }
            }
        }
        &self.out
    }

    /// The restart the last [`Self::update`] made, if any, and how many estimators it
    /// restarted.
    pub fn restarted(&self) -> Option<(GapEnd, usize)> {
        self.restart
    }

    /// Flags [`Flags::IMPLAUSIBLE`] on the last outputs of the estimators reading one of
    /// `sensors` (those whose readings of this row were impossible and read as missing).
    pub fn flag_implausible(&mut self, sensors: Inputs) {
        self.flag(sensors, Flags::IMPLAUSIBLE);
    }

    /// Adds `flag` to the last outputs of the estimators reading one of `sensors`.
    pub fn flag(&mut self, sensors: Inputs, flag: Flags) {
        if sensors.is_empty() {
            return;
        }
        for (o, reads) in self.out.iter_mut().zip(&self.reads) {
            if reads.intersects(sensors) {
                o.flags |= flag;
            }
        }
    }

    /// The outputs of the last [`Self::update`], in [`Self::names`] order.
    pub fn outputs(&self) -> &[Attitude<f64>] {
        &self.out
    }

    /// Estimator `i`'s quaternion after the last [`Self::update`].
    pub fn quaternion(&self, i: usize) -> Option<[f64; 4]> {
        self.runners[i].quaternion()
    }
}

/// The roll and pitch of one estimator (or of the truth) \[rad\], one value per row.
#[derive(Debug, Clone, PartialEq)]
pub struct RollPitch {
    /// Its name (the estimator's, a file stem and palette key).
    pub name: String,
    /// Roll \[rad\].
    pub roll: Vec<f64>,
    /// Pitch \[rad\].
    pub pitch: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_keeps_registry_order_and_refuses_unknown_names() {
        let s = Settings3d::default();
        let b = Bank3d::new(&s, Some(&["vqf".into(), "ekf3d".into()])).unwrap();
        assert_eq!(b.names(), ["ekf3d", "vqf"]);
        assert!(b.has_quaternion(0) && !b.has_quaternion(1));
        let e = Bank3d::new(&s, Some(&["ekf3d".into(), "kalman9".into()])).unwrap_err();
        assert!(e.contains("kalman9") && e.contains(&names3d()), "{e}");
        assert_eq!(
            Bank3d::new(&s, None).unwrap().names().len(),
            REGISTRY3D.len()
        );
    }

    /// The flag says what the runner gives: a quaternion once started, for those marked.
    #[test]
    fn quaternion_flag_matches_the_runner() {
        let s = Settings3d::default();
        let mut b = Bank3d::new(&s, None).unwrap();
        let g = 9.80665;
        for k in 0..50 {
            let x = SpatialSample::new(
                if k == 0 { 0.0 } else { 1e-3 },
                [0.1, -0.05],
                [0.0; 3],
                pendtilt_core::spatial::attitude::up_from_roll_pitch(0.1, -0.05).map(|u| u * g),
            );
            b.update(&x);
        }
        for (i, e) in REGISTRY3D.iter().enumerate() {
            assert_eq!(b.quaternion(i).is_some(), e.quaternion, "{}", e.name);
        }
        // ekf3d's quaternion is the up direction it reports (world <- body).
        let q = b.quaternion(3).unwrap();
        let up_z = q[0] * q[0] - q[1] * q[1] - q[2] * q[2] + q[3] * q[3];
        let want = 0.1f64.cos() * 0.05f64.cos();
        assert!((up_z - want).abs() < 1e-3, "{up_z} {want}");
    }
}
