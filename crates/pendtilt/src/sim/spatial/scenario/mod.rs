//! The named 3-D scenarios of MODEL.md 7.8 (`still3d`, `scooter3d`, `ship3d`, `ride3d`),
//! the variants of `ride3d`, the rig file of 7.6 (`[pendulum3d]`, `[mounting]`) and
//! the scenario file.
//!
//! `ride3d` itself carries a 1 % speed-scale error (`sensors.speed_scale = 1.01`, a tyre
//! radius 1 % off). Its variants have the same motion and noise for the same seed:
//! - `ride3d_yawbias`: a further +0.5 deg/s on the gyro's z bias (0.7 deg/s in all, on
//!   top of the noisy grade's 0.2), the yaw-rate bias that turns the centripetal term;
//! - `ride3d_slip`: two stretches of wheel slip in the speed reading
//!   ([`super::sensors::SpeedFault`]): the wheel spins when pulling away at 84 s (the
//!   reading 3.5 m/s above the truth within 0.3 s, 1.5 s there, back in 0.4 s) and locks
//!   when braking at 62 s (the reading drops to 0 within 0.15 s, 0.8 s there, back in
//!   0.2 s, while the vehicle slows from 11 to 7 m/s). [`Scenario3d::slip_intervals`]
//!   gives the true intervals.
//!
//! Random phases and the random tones are drawn from the seed when a scenario is made
//! ([`Scenario3d::named`]) and written out in full, so the scenario file alone gives the
//! motion; the seed also drives the sensor noise (one stream per source, 7.5).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

mod named;

use super::params::Pendulum3d;
use super::sensors::{LogRow3d, SensorBank3d, Sensors3d};
use super::simulator::{Simulator3d, Truth3d};
use super::vehicle::{MotionSpec, VehicleMotion};
use crate::sim::planar::{SimError, SCENARIO_NAMES};

/// The names [`Scenario3d::named`] knows (listed beside the planar ones, so that the
/// planar simulator names both without importing this one).
pub use crate::sim::SCENARIO3D_NAMES;

/// Where the sensors sit (MODEL.md 7.6 `[mounting]`): the core's type, one definition.
pub type Mounting = pendtilt_core::model::Mounting<f64>;

/// The rig file of MODEL.md 7.6 (physical form).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rig3d {
    /// The Cardan pendulum.
    pub pendulum3d: Pendulum3d,
    /// Where the sensors sit.
    #[serde(default)]
    pub mounting: Mounting,
}

impl Rig3d {
    /// The rig as TOML, every key written.
    pub fn to_toml_string(&self) -> Result<String, SimError> {
        let body = toml::to_string(self).map_err(|e| SimError::Config {
            origin: "rig".into(),
            message: e.to_string(),
        })?;
        Ok(format!(
            "# 3-D rig (MODEL.md 7.6), SI units: [pendulum3d] the Cardan pendulum, [mounting]\n\
             # the accelerometer and speed point relative to P1, body axes [m].\n{body}"
        ))
    }

    /// Reads a rig TOML; `origin` names it in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, SimError> {
        let rig: Self = toml::from_str(text).map_err(|e| SimError::Config {
            origin: origin.into(),
            message: e.to_string(),
        })?;
        rig.pendulum3d.validate()?;
        Ok(rig)
    }
}

/// One 3-D simulation set-up (MODEL.md 7.8): timing, rig, sensors and motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario3d {
    /// Length of the run \[s\]; the log has round(duration * rate) rows.
    pub duration: f64,
    /// Sample rate \[Hz\]. Default 1000.
    pub rate: f64,
    /// RK4 steps per sample. Default 2.
    pub substeps: u32,
    /// Metrics are taken over t >= score_from \[s\] (MODEL.md 7.9).
    pub score_from: f64,
    /// The rig: pendulum and mounting.
    pub rig: Rig3d,
    /// The sensors (`accel_at` comes from the rig's mounting).
    pub sensors: Sensors3d,
    /// The prescribed motion.
    pub motion: MotionSpec,
}

/// Random stream of the scenario's own draws (phases, tones); the sensors use 11-15.
const MOTION_STREAM: u64 = 21;

impl Scenario3d {
    /// The named scenario of MODEL.md 7.8 with its random parts drawn from `seed`.
    pub fn named(name: &str, seed: u64) -> Result<Self, SimError> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(MOTION_STREAM);
        Ok(match name {
            "still3d" => named::still3d(),
            "scooter3d" => named::scooter3d(&mut rng),
            "ship3d" => named::ship3d(&mut rng),
            "ride3d" => named::ride3d(&mut rng),
            "ride3d_yawbias" => named::ride3d_yawbias(&mut rng),
            "ride3d_slip" => named::ride3d_slip(&mut rng),
            _ => {
                return Err(SimError::UnknownScenario {
                    name: name.into(),
                    known: SCENARIO3D_NAMES.join(", "),
                })
            }
        })
    }

    /// Checks every value; errors name the key.
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
        if !self.score_from.is_finite() {
            return Err(SimError::invalid("score_from", "must be finite"));
        }
        self.rig.pendulum3d.validate()?;
        check_mounting(&self.rig.mounting, "rig.mounting")?;
        self.sensors.validate()?;
        VehicleMotion::new(&self.motion, self.rig.mounting.speed_at)?;
        Ok(())
    }

    /// The true wheel-slip intervals of the speed reading \[s\] (its
    /// [`Sensors3d::speed_faults`]; empty for a scenario without slip).
    pub fn slip_intervals(&self) -> Vec<[f64; 2]> {
        self.sensors.slip_intervals()
    }

    /// Number of rows: round(duration * rate).
    pub fn rows(&self) -> u64 {
        (self.duration * self.rate).round() as u64
    }

    /// The built motion.
    pub fn motion(&self) -> Result<VehicleMotion, SimError> {
        VehicleMotion::new(&self.motion, self.rig.mounting.speed_at)
    }

    /// The truth of the run, without sensors.
    pub fn simulator(&self) -> Result<Simulator3d<VehicleMotion>, SimError> {
        self.validate()?;
        Simulator3d::new(
            self.rig.pendulum3d,
            self.motion()?,
            self.rate,
            self.substeps,
            self.duration,
        )
    }

    /// The run: each row's truth and its sensor readings, noise drawn from `seed`.
    pub fn run(&self, seed: u64) -> Result<Run3d, SimError> {
        let sensors = Sensors3d {
            accel_at: self.rig.mounting.accel_at,
            ..self.sensors.clone()
        };
        Ok(Run3d {
            sim: self.simulator()?,
            bank: SensorBank3d::new(sensors, self.rate, seed),
        })
    }

    /// The scenario as TOML (every key; angles in degrees).
    pub fn to_toml(&self) -> Result<String, SimError> {
        toml::to_string(self).map_err(|e| SimError::Config {
            origin: "scenario".into(),
            message: e.to_string(),
        })
    }

    /// Reads a scenario written by [`Scenario3d::to_toml`] (top-level `scenario` and `seed`
    /// keys allowed, the seed returned); `origin` names the text in errors, which give the
    /// line and column.
    pub fn from_toml(text: &str, origin: &str) -> Result<(Self, Option<u64>), SimError> {
        // A planar scenario file: say so, not "unknown field `amplitude`".
        if let Ok(t) = text.parse::<toml::Table>() {
            let name = t.get("scenario").and_then(|v| v.as_str());
            if t.contains_key("pendulum") || name.is_some_and(|n| SCENARIO_NAMES.contains(&n)) {
                return Err(SimError::Config {
                    origin: origin.into(),
                    message: format!(
                        "a planar scenario file (scenario = \"{}\", [pendulum]), read as a 3-D \
                         one (MODEL.md 7.8): give the scenario file `pendtilt simulate` wrote \
                         beside the 3-D log (e.g. --scenario scooter3d)",
                        name.unwrap_or("?")
                    ),
                });
            }
        }
        let f: ScenarioFile = toml::from_str(text).map_err(|e| SimError::Config {
            origin: origin.into(),
            message: e.to_string(),
        })?;
        let s = Self {
            duration: f.duration,
            rate: f.rate,
            substeps: f.substeps,
            score_from: f.score_from,
            rig: f.rig,
            sensors: f.sensors,
            motion: f.motion,
        };
        // Name the file: `rate: must be > 0 Hz` alone did not say which.
        s.validate().map_err(|e| SimError::Config {
            origin: origin.into(),
            message: e.to_string(),
        })?;
        Ok((s, f.seed))
    }
}

/// Refuses a mounting position that is not finite (`accel_at = [0, 0, nan]` was read
/// and the accelerometer's lever arm silently dropped); `table` names it in the error.
pub fn check_mounting(m: &Mounting, table: &str) -> Result<(), SimError> {
    for (key, v) in [("accel_at", m.accel_at), ("speed_at", m.speed_at)] {
        if v.iter().any(|x| !x.is_finite()) {
            return Err(SimError::invalid(
                format!("{table}.{key}"),
                format!("must be finite [m], got {v:?}"),
            ));
        }
    }
    Ok(())
}

impl Scenario3d {
    /// Applies a scenario TOML (text) of some keys on top of `self`, key by key as a planar
    /// scenario file is (`[rig.pendulum3d] inertia_xx = 0.0026` alone changes that);
    /// returns the new scenario and the file's `seed`, if any. The file's `scenario` key is
    /// the caller's (it names the base). `origin` names the text in errors.
    pub fn merged(&self, text: &str, origin: &str) -> Result<(Self, Option<u64>), SimError> {
        let config = |message: String| SimError::Config {
            origin: origin.into(),
            message,
        };
        let mut over: toml::Table = toml::from_str(text).map_err(|e| config(e.to_string()))?;
        over.remove("scenario");
        let seed = crate::sim::planar::scenario::seed_of(&over, origin)?;
        over.remove("seed");
        let base = toml::Table::try_from(self)
            .map_err(|e| config(format!("cannot represent the base scenario: {e}")))?;
        let s: Self =
            crate::sim::planar::scenario::merge_into(base, over, Some(text)).map_err(config)?;
        s.validate().map_err(|e| config(e.to_string()))?;
        Ok((s, seed))
    }
}

/// A scenario file: [`Scenario3d`]'s keys and the name and seed it was made with.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    #[serde(rename = "scenario")]
    _name: Option<String>,
    seed: Option<u64>,
    duration: f64,
    rate: f64,
    substeps: u32,
    score_from: f64,
    rig: Rig3d,
    sensors: Sensors3d,
    motion: MotionSpec,
}

/// A running 3-D simulation with its sensors: (truth, log row) per sample.
#[derive(Debug, Clone)]
pub struct Run3d {
    sim: Simulator3d<VehicleMotion>,
    bank: SensorBank3d,
}

impl Run3d {
    /// Rows left.
    pub fn remaining(&self) -> u64 {
        self.sim.size_hint().0 as u64
    }
}

impl Iterator for Run3d {
    type Item = (Truth3d, LogRow3d);

    fn next(&mut self) -> Option<Self::Item> {
        let x = self.sim.next()?;
        let r = self.bank.read(&x);
        Some((x, r))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.sim.size_hint()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scenario file reads back to the scenario; a typo is an error with its line.
    #[test]
    fn scenario_file_round_trip_and_errors() {
        let s = Scenario3d::named("ship3d", 4).unwrap();
        let text = format!("scenario = \"ship3d\"\nseed = 4\n{}", s.to_toml().unwrap());
        assert_eq!(
            Scenario3d::from_toml(&text, "f").unwrap(),
            (s.clone(), Some(4))
        );
        let bad = text.replace("score_from =", "score_form =");
        let e = Scenario3d::from_toml(&bad, "f.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.toml: TOML parse error at line 6"), "{e}");
        assert!(e.contains("score_form"), "{e}");
        let bad = text.replace("rate = 1000.0", "rate = -1.0");
        let e = Scenario3d::from_toml(&bad, "f.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("rate: must be > 0 Hz"), "{e}");
    }

    /// `ride3d_slip`'s speed faults are written to its scenario file and read back; a
    /// negative duration names the fault.
    #[test]
    fn speed_faults_round_trip() {
        let s = Scenario3d::named("ride3d_slip", 3).unwrap();
        let text = s.to_toml().unwrap();
        assert!(text.contains("[[sensors.speed_faults]]"), "{text}");
        assert_eq!(Scenario3d::from_toml(&text, "f").unwrap(), (s, None));
        let bad = text.replacen("hold = 0.8", "hold = -0.8", 1);
        let e = Scenario3d::from_toml(&bad, "f").unwrap_err().to_string();
        assert!(e.contains("sensors.speed_faults[0]"), "{e}");
        let plain = Scenario3d::named("ride3d", 3).unwrap().to_toml().unwrap();
        assert!(!plain.contains("speed_faults"), "{plain}");
    }

    /// The rig file reads back; a bad value names its key.
    #[test]
    fn rig_file_round_trip() {
        let s = Scenario3d::named("ride3d", 1).unwrap();
        let text = s.rig.to_toml_string().unwrap();
        assert_eq!(Rig3d::from_toml(&text, "r").unwrap(), s.rig);
        let e = Rig3d::from_toml(&text.replace("mass = 0.05", "mass = 0.0"), "r")
            .unwrap_err()
            .to_string();
        assert!(e.contains("pendulum3d.mass"), "{e}");
    }
}
