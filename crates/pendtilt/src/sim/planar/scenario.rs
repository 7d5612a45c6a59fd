//! Scenarios: everything a run needs except the seed, with named defaults and TOML.
//!
//! A scenario TOML overrides a named base scenario key by key; only the keys you write
//! change. Example (every key optional):
//!
//! ```toml
//! scenario = "scooter"     # base; `--scenario` on the command line takes precedence
//! seed = 7                 # used when `--seed` is not given
//! duration = 120.0         # [s]
//! rate = 1000.0            # sample rate [Hz]
//! substeps = 2             # RK4 steps per sample
//!
//! [pendulum]               # the rig, same keys as the rig TOML of MODEL.md section 5
//! pivot_offset = 0.1       # l12 [m]
//!
//! [motion]                 # writing a different `kind` replaces the whole table
//! kind = "sine"
//! amplitude = 0.1          # [rad]
//! frequency = 1.0          # [Hz]
//!
//! [[vibration.harmonics]]  # an array replaces the base's array
//! frequency = 35.0         # [Hz]
//! amplitude = 2.0          # [m/s^2]
//! axis = [0.0, 1.0]        # body axes
//! phase = 0.0              # [rad]
//!
//! [vibration.broadband]
//! rms = [1.0, 2.0]         # [m/s^2] on body x, y
//! band = [5.0, 200.0]      # [Hz]
//!
//! [sensors.gyro]
//! bias = 0.0               # [rad/s]
//! ```
//!
//! Angles are in rad, as everywhere in pendtilt (10 deg = 0.1745 rad).

use pendtilt_core::model::PhysicalParams;
use serde::{Deserialize, Serialize};

use crate::config::RigConfig;
use std::path::Path;

use super::motion::{Chirp, Manoeuvres, Motion, Sigmoid, Sine, Step, Still};
use super::sensors::Sensors;
use super::vibration::{AngularHarmonic, Broadband, Harmonic, Vibration};
use super::SimError;

/// The names [`Scenario::named`] knows.
pub const SCENARIO_NAMES: &[&str] = &["still", "sigmoid", "step", "sine", "chirp", "scooter"];

/// The `[pendulum]` table of the rig TOML (MODEL.md section 5), SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PendulumTable {
    /// m_p \[kg\]. Default 0.05.
    pub mass: f64,
    /// l_p, pivot to CG \[m\]. Default 0.05.
    pub length: f64,
    /// I_p about the pivot \[kg m^2\], at least m_p l_p^2. Default 1.3e-4.
    pub inertia: f64,
    /// C \[N m s/rad\]. Default 1.07e-3.
    pub damping: f64,
    /// l12 \[m\]. Default 0.
    pub pivot_offset: f64,
    /// g \[m/s^2\]. Default 9.80665.
    pub gravity: f64,
}

impl Default for PendulumTable {
    fn default() -> Self {
        PhysicalParams::default().into()
    }
}

impl From<PhysicalParams<f64>> for PendulumTable {
    fn from(p: PhysicalParams<f64>) -> Self {
        Self {
            mass: p.mass,
            length: p.length,
            inertia: p.inertia,
            damping: p.damping,
            pivot_offset: p.pivot_offset,
            gravity: p.gravity,
        }
    }
}

impl From<PendulumTable> for PhysicalParams<f64> {
    fn from(p: PendulumTable) -> Self {
        Self {
            mass: p.mass,
            length: p.length,
            inertia: p.inertia,
            damping: p.damping,
            pivot_offset: p.pivot_offset,
            gravity: p.gravity,
        }
    }
}

impl PendulumTable {
    /// Checks the values are physical; errors name `pendulum.<key>`.
    pub fn validate(&self) -> Result<(), SimError> {
        let pos = |x: f64, key: &str| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(SimError::invalid(key, format!("must be > 0, got {x:?}")))
            }
        };
        pos(self.mass, "pendulum.mass")?;
        pos(self.length, "pendulum.length")?;
        pos(self.inertia, "pendulum.inertia")?;
        pos(self.gravity, "pendulum.gravity")?;
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(SimError::invalid(
                "pendulum.damping",
                format!("must be >= 0, got {:?}", self.damping),
            ));
        }
        if !self.pivot_offset.is_finite() {
            return Err(SimError::invalid(
                "pendulum.pivot_offset",
                format!("must be finite, got {:?}", self.pivot_offset),
            ));
        }
        let point_mass = self.mass * self.length * self.length;
        if self.inertia < point_mass * (1.0 - 1e-9) {
            return Err(SimError::invalid(
                "pendulum.inertia",
                // Debug prints 1e300 as written, Display as 301 digits.
                format!(
                    "{:?} kg m^2 is below mass * length^2 = {:?} kg m^2: the inertia \
                     about the pivot includes m_p l_p^2 (check the units)",
                    self.inertia,
                    crate::config::plain(point_mass)
                ),
            ));
        }
        Ok(())
    }
}

/// One simulation set-up: timing, rig, body motion, vibration and sensors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Length of the run \[s\]; the log has round(duration * rate) rows.
    pub duration: f64,
    /// Sample rate \[Hz\]. Default 1000.
    pub rate: f64,
    /// RK4 steps per sample (the integration step is 1 / (rate * substeps)). Default 2:
    /// on the `scooter` scenario (broadband off, 60 s) the largest error of phi against 32
    /// steps per sample is 7e-9 rad with 1 step, 4e-10 rad with 2, 3e-11 rad with 4, far
    /// below the 12-bit encoder's 1.5e-3 rad. Broadband vibration is generated at
    /// rate x substeps, which must exceed 2.2 x its upper band edge.
    pub substeps: u32,
    /// The pendulum.
    #[serde(default)]
    pub pendulum: PendulumTable,
    /// The prescribed tilt of the body.
    pub motion: Motion,
    /// Floor vibration. Default none.
    #[serde(default)]
    pub vibration: Vibration,
    /// Sensor settings. Default as documented on each field of [`Sensors`].
    #[serde(default)]
    pub sensors: Sensors,
}

impl Scenario {
    /// A scenario with the default rig and sensors, no vibration, 1 kHz, 2 substeps.
    pub fn with_motion(motion: Motion, duration: f64) -> Self {
        Self {
            duration,
            rate: 1000.0,
            substeps: 2,
            pendulum: PendulumTable::default(),
            motion,
            vibration: Vibration::default(),
            sensors: Sensors::default(),
        }
    }

    /// A named reference scenario (MODEL.md section 6):
    /// - `still`: held level, 10 s.
    /// - `sigmoid`: the paper's Fig. 5, 10 deg, t0 = 2 s, tau = 0.2 s, 5 s.
    /// - `step`: a steep sigmoid, 10 deg at 1 s, tau = 5 ms, 5 s.
    /// - `sine`: 10 deg at 0.5 Hz, 10 s.
    /// - `chirp`: 5 deg, 0.1 -> 5 Hz over 20 s, 20 s.
    /// - `scooter`: the paper's experiment, 60 s: [`Manoeuvres`] defaults (slow leaning in
    ///   0.05-0.8 Hz, RMS 7 deg, soft limit 15 deg) on a floor shaken by a 40 Hz engine
    ///   (3 m/s^2 vertical and 1.5 m/s^2 fore-aft at 40 Hz, 1.5 m/s^2 vertical at 80 Hz),
    ///   broadband vibration of 1.5 / 2.5 m/s^2 RMS (x / y) in 5-200 Hz, and an angular
    ///   vibration of 1 mrad (0.057 deg) at 40 Hz.
    ///
    /// All use the default rig ([`PhysicalParams::default`]), default sensors
    /// ([`Sensors::default`]), 1 kHz and 2 RK4 substeps.
    pub fn named(name: &str) -> Result<Self, SimError> {
        Ok(match name {
            "still" => Self::with_motion(Motion::Still(Still::default()), 10.0),
            "sigmoid" => Self::with_motion(Motion::Sigmoid(Sigmoid::default()), 5.0),
            "step" => Self::with_motion(Motion::Step(Step::default()), 5.0),
            "sine" => Self::with_motion(Motion::Sine(Sine::default()), 10.0),
            "chirp" => Self::with_motion(Motion::Chirp(Chirp::default()), 20.0),
            "scooter" => Self {
                vibration: Vibration {
                    harmonics: vec![
                        Harmonic {
                            frequency: 40.0,
                            amplitude: 3.0,
                            axis: [0.0, 1.0],
                            phase: 0.0,
                        },
                        Harmonic {
                            frequency: 40.0,
                            amplitude: 1.5,
                            axis: [1.0, 0.0],
                            phase: 0.8,
                        },
                        Harmonic {
                            frequency: 80.0,
                            amplitude: 1.5,
                            axis: [0.0, 1.0],
                            phase: 1.9,
                        },
                    ],
                    broadband: Broadband {
                        rms: [1.5, 2.5],
                        band: [5.0, 200.0],
                    },
                    angular: vec![AngularHarmonic {
                        frequency: 40.0,
                        amplitude: 1e-3,
                        phase: 0.3,
                    }],
                },
                ..Self::with_motion(Motion::Manoeuvres(Manoeuvres::default()), 60.0)
            },
            _ => {
                return Err(SimError::UnknownScenario {
                    name: name.to_string(),
                    known: SCENARIO_NAMES.join(", "),
                })
            }
        })
    }

    /// The rig as [`PhysicalParams`].
    pub fn physical(&self) -> PhysicalParams<f64> {
        self.pendulum.into()
    }

    /// The rig file for this scenario's logs: the pendulum in physical form and the
    /// sensors' full scales (`[accel]`, `[gyro]`) when they saturate, so that `estimate`
    /// flags saturated samples.
    pub fn rig(&self) -> Result<RigConfig, SimError> {
        let mut rig = RigConfig::from_physical(self.physical()).map_err(|e| SimError::Config {
            origin: "rig".into(),
            message: e.to_string(),
        })?;
        let fs = |x: f64| (x > 0.0).then_some(x);
        rig.accel.full_scale = fs(self.sensors.accel.full_scale);
        rig.gyro.full_scale = fs(self.sensors.gyro.full_scale);
        Ok(rig)
    }

    /// Number of log rows: round(duration * rate).
    pub fn rows(&self) -> u64 {
        (self.duration * self.rate).round() as u64
    }

    /// Integration nodes per second: rate * substeps \[Hz\].
    pub fn node_rate(&self) -> f64 {
        self.rate * self.substeps as f64
    }

    /// Checks every value; errors name the key and why.
    pub fn validate(&self) -> Result<(), SimError> {
        if !(self.duration.is_finite() && self.duration >= 0.0) {
            return Err(SimError::invalid(
                "duration",
                format!("must be >= 0 s, got {:?}", self.duration),
            ));
        }
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(SimError::invalid(
                "rate",
                format!("must be > 0 Hz, got {:?}", self.rate),
            ));
        }
        if self.duration * self.rate > 1e11 {
            return Err(SimError::invalid(
                "duration",
                format!(
                    "{} s at {} Hz is more than 1e11 rows",
                    self.duration, self.rate
                ),
            ));
        }
        if !(1..=10_000).contains(&self.substeps) {
            return Err(SimError::invalid(
                "substeps",
                format!("must be 1 ..= 10000, got {}", self.substeps),
            ));
        }
        self.pendulum.validate()?;
        let p = &self.pendulum;
        super::integrator::check_step(
            super::integrator::fastest_mode(
                p.mass * p.gravity * p.length / p.inertia,
                p.damping / p.inertia,
            ),
            self.rate,
            self.substeps,
        )?;
        self.motion.validate()?;
        self.vibration.validate(self.node_rate())?;
        self.sensors.validate()
    }

    /// Applies a scenario TOML (text) on top of `self`; returns the new scenario and the
    /// file's `seed`, if any. `origin` names the source in errors (a path, `--set`, ...).
    /// The file's `scenario` key is ignored here (see [`load_config`]).
    pub fn merged(&self, text: &str, origin: &str) -> Result<(Self, Option<u64>), SimError> {
        let mut table: toml::Table = toml::from_str(text).map_err(|e| SimError::Config {
            origin: origin.to_string(),
            message: e.to_string(),
        })?;
        table.remove("scenario");
        let seed = seed_of(&table, origin)?;
        table.remove("seed");
        Ok((self.merged_from(table, Some(text), origin)?, seed))
    }

    fn merged_table(&self, table: toml::Table, origin: &str) -> Result<Self, SimError> {
        self.merged_from(table, None, origin)
    }

    /// [`Self::merged_table`] of the table read from `text`, which places a bad key.
    fn merged_from(
        &self,
        table: toml::Table,
        text: Option<&str>,
        origin: &str,
    ) -> Result<Self, SimError> {
        let base = toml::Table::try_from(self).map_err(|e| SimError::Config {
            origin: origin.to_string(),
            message: format!("cannot represent the base scenario: {e}"),
        })?;
        let out: Self = merge_into(base, table, text).map_err(|message| SimError::Config {
            origin: origin.to_string(),
            message,
        })?;
        out.validate().map_err(|e| SimError::Config {
            origin: origin.to_string(),
            message: e.to_string(),
        })?;
        Ok(out)
    }

    /// Sets one key from `path.to.key=value` (value in TOML syntax; a bare word is taken as
    /// a string), as `--set` does. Example: `vibration.broadband.rms=[0.5, 1.0]`.
    pub fn set(&mut self, assignment: &str) -> Result<(), SimError> {
        let origin = format!("--set {assignment}");
        let Some((path, value)) = assignment.split_once('=') else {
            return Err(SimError::Config {
                origin,
                message: "expected KEY=VALUE, e.g. pendulum.pivot_offset=0.1".into(),
            });
        };
        let value = value.trim();
        let value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
            Ok(mut t) => t.remove("v").unwrap_or(toml::Value::String(value.into())),
            Err(_) => toml::Value::String(value.to_string()),
        };
        let mut leaf = value;
        let keys: Vec<&str> = path.trim().split('.').map(str::trim).collect();
        if keys.iter().any(|k| k.is_empty()) {
            return Err(SimError::Config {
                origin,
                message: format!("'{}' is not a key path like a.b.c", path.trim()),
            });
        }
        for k in keys.iter().rev() {
            let mut t = toml::Table::new();
            t.insert((*k).to_string(), leaf);
            leaf = toml::Value::Table(t);
        }
        let toml::Value::Table(table) = leaf else {
            unreachable!("the loop above always wraps the value in a table")
        };
        *self = self.merged_table(table, &origin)?;
        Ok(())
    }

    /// The scenario as TOML text (every key), loadable by [`load_config`].
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_else(|e| format!("# cannot write the scenario: {e}\n"))
    }
}

pub(crate) fn seed_of(table: &toml::Table, origin: &str) -> Result<Option<u64>, SimError> {
    match table.get("seed") {
        None => Ok(None),
        Some(toml::Value::Integer(s)) if *s >= 0 => Ok(Some(*s as u64)),
        Some(v) => Err(SimError::Config {
            origin: origin.to_string(),
            message: format!("seed: must be a non-negative integer, got {v}"),
        }),
    }
}

/// `over` merged onto `base` (a scenario as a table, [`merge`]) and read as `T`. A key
/// that `T` cannot take (a value of the wrong type, a name it does not know) is named, and
/// placed in `text` (what `over` was read from) by line and column: the error alone said
/// `invalid type: string "abc", expected f64`, no key, no line.
pub(crate) fn merge_into<T: serde::de::DeserializeOwned>(
    base: toml::Table,
    over: toml::Table,
    text: Option<&str>,
) -> Result<T, String> {
    let read = |over: toml::Table| {
        let mut m = base.clone();
        merge(&mut m, over, "");
        toml::Value::Table(m).try_into::<T>()
    };
    let message = match read(over.clone()) {
        Ok(t) => return Ok(t),
        Err(e) => e.message().to_string(),
    };
    // The key: the first leaf that, merged alone, fails the same way.
    let mut leaves = Vec::new();
    leaf_paths(&over, &mut Vec::new(), &mut leaves);
    for (path, value) in leaves {
        let single = path.iter().rev().fold(value, |v, k| {
            let mut t = toml::Table::new();
            t.insert(k.clone(), v);
            toml::Value::Table(t)
        });
        let toml::Value::Table(single) = single else {
            continue;
        };
        if read(single).is_err_and(|e| e.message() == message) {
            let at = text
                .and_then(|t| key_position(t, &path))
                .map(|(line, col)| format!(" (line {line}, column {col})"))
                .unwrap_or_default();
            return Err(format!("`{}`{at}: {message}", path.join(".")));
        }
    }
    Err(message)
}

/// Every non-table value of `t` with its key path.
fn leaf_paths(
    t: &toml::Table,
    prefix: &mut Vec<String>,
    out: &mut Vec<(Vec<String>, toml::Value)>,
) {
    for (k, v) in t {
        prefix.push(k.clone());
        match v {
            toml::Value::Table(sub) => leaf_paths(sub, prefix, out),
            v => out.push((prefix.clone(), v.clone())),
        }
        prefix.pop();
    }
}

/// Line and column (from 1) of the key `path` in the TOML `text`.
fn key_position(text: &str, path: &[String]) -> Option<(usize, usize)> {
    let doc = toml::de::DeTable::parse(text).ok()?;
    let mut table = doc.get_ref();
    for (i, k) in path.iter().enumerate() {
        let (key, value) = table.iter().find(|(key, _)| key.get_ref().as_ref() == k)?;
        if i + 1 == path.len() {
            let at = key.span().start;
            let before = &text[..at];
            let line = before.matches('\n').count() + 1;
            let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            return Some((line, col));
        }
        match value.get_ref() {
            toml::de::DeValue::Table(t) => table = t,
            _ => return None,
        }
    }
    None
}

/// Deep merge of `over` into `base`: tables merge key by key, anything else replaces.
/// A `[motion]` with a different `kind` replaces the whole motion table, so that the new
/// kind starts from its own defaults.
fn merge(base: &mut toml::Table, over: toml::Table, prefix: &str) {
    for (k, v) in over {
        let here = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match (base.get_mut(&k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => {
                let kind_changes = here == "motion"
                    && o.get("kind")
                        .is_some_and(|kind| b.get("kind") != Some(kind));
                if kind_changes {
                    *b = o;
                } else {
                    merge(b, o, &here);
                }
            }
            (_, v) => {
                base.insert(k, v);
            }
        }
    }
}

/// Reads a scenario TOML file: its base is `name` if given, else the file's `scenario`
/// key, else an error. Returns the scenario and the file's `seed`, if any.
pub fn load_config(path: &Path, name: Option<&str>) -> Result<(Scenario, Option<u64>), SimError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SimError::Io {
        path: origin.clone(),
        error: e,
    })?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| SimError::Config {
        origin: origin.clone(),
        message: e.to_string(),
    })?;
    let file_name = match table.get("scenario") {
        None => None,
        Some(toml::Value::String(s)) => Some(s.clone()),
        Some(v) => {
            return Err(SimError::Config {
                origin,
                message: format!("scenario: must be a name like \"scooter\", got {v}"),
            })
        }
    };
    let Some(base_name) = name.map(str::to_string).or(file_name) else {
        return Err(SimError::Config {
            origin,
            message: format!(
                "no base scenario: give --scenario NAME or a top-level `scenario = \"NAME\"` \
                 (one of {}, or a 3-D one: {})",
                SCENARIO_NAMES.join(", "),
                crate::sim::SCENARIO3D_NAMES.join(", ")
            ),
        });
    };
    Scenario::named(&base_name)?.merged(&text, &origin)
}

/// Reads the pendulum of a rig TOML (MODEL.md section 5) with [`crate::config::RigConfig`];
/// the `[pendulum]` table must give the physical form (the simulator needs mass, length,
/// inertia, damping; the normalised a, b of a fit are not enough).
pub fn load_rig(path: &Path) -> Result<PendulumTable, SimError> {
    let origin = path.display().to_string();
    let rig = RigConfig::load(path).map_err(|e| SimError::Config {
        origin: origin.clone(),
        message: e.to_string(),
    })?;
    let p = rig.physical().ok_or_else(|| SimError::Config {
        origin: origin.clone(),
        message: "[pendulum] gives the normalised a, b, c; the simulator needs the physical \
                  mass, length, inertia, damping"
            .into(),
    })?;
    let p = PendulumTable::from(p);
    p.validate().map_err(|e| SimError::Config {
        origin,
        message: e.to_string(),
    })?;
    Ok(p)
}

/// The rig TOML of MODEL.md section 5 for `p`, written by [`crate::config::RigConfig`]: the
/// `[pendulum]` table in physical form (and the default `[kalman]` table), which
/// `pendtilt estimate --params` reads unedited.
pub fn rig_toml(p: &PhysicalParams<f64>) -> Result<String, SimError> {
    RigConfig::from_physical(*p)
        .map(|c| c.to_toml_string())
        .map_err(|e| SimError::Config {
            origin: "rig".into(),
            message: e.to_string(),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_scenario_is_valid_and_round_trips() {
        for name in SCENARIO_NAMES {
            let s = Scenario::named(name).unwrap();
            s.validate().unwrap();
            let (back, seed) = s.merged(&s.to_toml(), "test").unwrap();
            assert_eq!(back, s, "{name}");
            assert_eq!(seed, None);
        }
        assert!(Scenario::named("bicycle").is_err());
    }

    #[test]
    fn partial_file_overrides_only_its_keys() {
        let base = Scenario::named("scooter").unwrap();
        let (s, seed) = base
            .merged(
                "seed = 5\nduration = 3.0\n[pendulum]\npivot_offset = 0.1\n",
                "x.toml",
            )
            .unwrap();
        assert_eq!(seed, Some(5));
        assert_eq!(s.duration, 3.0);
        assert_eq!(s.pendulum.pivot_offset, 0.1);
        assert_eq!(s.pendulum.mass, base.pendulum.mass);
        assert_eq!(s.vibration, base.vibration);
    }

    #[test]
    fn changing_motion_kind_starts_from_its_defaults() {
        let base = Scenario::named("scooter").unwrap();
        let (s, _) = base
            .merged("[motion]\nkind = \"sine\"\nfrequency = 2.0\n", "x.toml")
            .unwrap();
        assert_eq!(
            s.motion,
            Motion::Sine(Sine {
                frequency: 2.0,
                ..Sine::default()
            })
        );
    }

    #[test]
    fn errors_name_the_key() {
        let base = Scenario::named("sine").unwrap();
        let e = base
            .merged("[pendulum]\nmass = -1.0\n", "rig.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("rig.toml") && e.contains("pendulum.mass"), "{e}");
        let e = base
            .merged("[pendulum]\nmas = 1.0\n", "rig.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("mas"), "{e}");
        let e = base
            .merged("[pendulum]\ninertia = 1e-6\n", "rig.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("pendulum.inertia"), "{e}");
    }

    #[test]
    fn set_assigns_one_key() {
        let mut s = Scenario::named("scooter").unwrap();
        s.set("vibration.broadband.rms=[0.5, 1.0]").unwrap();
        assert_eq!(s.vibration.broadband.rms, [0.5, 1.0]);
        s.set("motion.kind=still").unwrap();
        assert_eq!(s.motion, Motion::Still(Still::default()));
        assert!(s.set("rate=-3").is_err());
        assert!(s.set("nonsense").is_err());
    }

    #[test]
    fn rig_toml_reads_back_through_the_rig_config() {
        let p = PhysicalParams {
            pivot_offset: 0.12,
            ..PhysicalParams::default()
        };
        let text = rig_toml(&p).unwrap();
        let t: toml::Table = toml::from_str(&text).unwrap();
        let pend = t["pendulum"].as_table().unwrap();
        let mut keys: Vec<_> = pend.keys().cloned().collect();
        keys.sort();
        assert_eq!(
            keys,
            [
                "damping",
                "gravity",
                "inertia",
                "length",
                "mass",
                "pivot_offset"
            ]
        );
        let back = RigConfig::from_toml_str(&text, "rig").unwrap();
        assert_eq!(back.physical(), Some(p));
    }
}
