//! Reading a 3-D rig file: its form (physical or normalised `[pendulum3d]`), its tables,
//! and errors naming the file, line and column.
use std::path::Path;

use pendtilt_core::params::GyroSettings;
use pendtilt_core::spatial::cardan::CardanParams;
use serde::Deserialize;

use super::{
    Ekf3dConfig, Pendulum3dConfig, Rig3dConfig, NORMALISED_KEYS, NORMALISED_UNITS, TABLES_PLANAR,
};
use crate::sim::spatial::scenario::check_mounting;
use crate::sim::spatial::{Mounting, Pendulum3d};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File<P> {
    pendulum3d: P,
    #[serde(default)]
    mounting: Mounting,
    #[serde(default)]
    ekf3d: Ekf3dConfig,
    #[serde(default)]
    gyro: GyroSettings<f64>,
}

/// `file:line:column: message` from a TOML error (the position when it has a span).
fn toml_error(origin: &str, text: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim_end();
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("{origin}:{line}:{column}: {message}")
        }
        None => format!("{origin}: {message}"),
    }
}

impl Rig3dConfig {
    /// Reads a rig file.
    pub fn load(path: &Path) -> Result<Self, String> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{origin}: cannot read the rig file: {e}"))?;
        Self::from_toml_str(&text, &origin)
    }

    /// Reads a rig from TOML text; `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, String> {
        let table: toml::Table = toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        // A planar rig file given for a 3-D log: say so, not "unknown field `accel`".
        if !table.contains_key("pendulum3d") {
            refuse_planar(&table, text, origin)?;
        }
        let keys: Vec<String> = match table.get("pendulum3d") {
            Some(toml::Value::Table(t)) => t.keys().cloned().collect(),
            _ => Vec::new(),
        };
        let mounting_given = table.contains_key("mounting");
        if !is_normalised(&keys, origin)? {
            let f: File<Pendulum3d> =
                toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
            f.pendulum3d
                .validate()
                .map_err(|e| format!("{origin}: {e}"))?;
            return f.rig(
                Pendulum3dConfig::Physical(f.pendulum3d),
                origin,
                mounting_given,
            );
        }
        refuse_missing(&keys, origin)?;
        let f: File<CardanParams<f64>> =
            toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        check_normalised(&f.pendulum3d).map_err(|e| format!("{origin}: pendulum3d.{e}"))?;
        f.rig(
            Pendulum3dConfig::Normalised(f.pendulum3d),
            origin,
            mounting_given,
        )
    }
}

impl<P> File<P> {
    /// The rig of `pendulum3d` and this file's other tables, checked.
    fn rig(
        &self,
        pendulum3d: Pendulum3dConfig,
        origin: &str,
        mounting_given: bool,
    ) -> Result<Rig3dConfig, String> {
        check_mounting(&self.mounting, "mounting").map_err(|e| format!("{origin}: {e}"))?;
        self.ekf3d.check().map_err(|e| format!("{origin}: {e}"))?;
        check_gyro(&self.gyro).map_err(|e| format!("{origin}: {e}"))?;
        Ok(Rig3dConfig {
            pendulum3d,
            mounting: self.mounting,
            ekf3d: self.ekf3d,
            gyro: self.gyro,
            mounting_given,
        })
    }
}

/// The error for a planar rig file (a planar table, no `[pendulum3d]`), if `table` is one.
fn refuse_planar(table: &toml::Table, text: &str, origin: &str) -> Result<(), String> {
    if let Some(name) = TABLES_PLANAR.iter().find(|n| table.contains_key(**n)) {
        let line = text
            .lines()
            .position(|l| l.trim_start().starts_with(&format!("[{name}]")))
            .map_or(String::new(), |i| format!("{}:1:", i + 1));
        return Err(format!(
            "{origin}:{line} [{name}]: a planar rig file (MODEL.md 5), and this log is \
             3-D: give a 3-D rig file ([pendulum3d], MODEL.md 7.6), as `pendtilt \
             simulate --scenario scooter3d` writes beside its log"
        ));
    }
    Ok(())
}

/// Whether `[pendulum3d]`'s `keys` are the normalised form; an error when they mix both.
fn is_normalised(keys: &[String], origin: &str) -> Result<bool, String> {
    let normalised: Vec<&str> = (keys.iter().map(String::as_str))
        .filter(|k| NORMALISED_KEYS.contains(k) && *k != "gravity")
        .collect();
    let physical: Vec<&str> = (keys.iter().map(String::as_str))
        .filter(|k| !NORMALISED_KEYS.contains(k))
        .collect();
    if !normalised.is_empty() && !physical.is_empty() {
        return Err(format!(
            "{origin}: pendulum3d: mixes the physical form ({}) with the normalised form \
             ({}); give one",
            physical.join(", "),
            normalised.join(", ")
        ));
    }
    Ok(!normalised.is_empty())
}

/// Every key of the normalised form is needed: all the missing ones in one message.
fn refuse_missing(keys: &[String], origin: &str) -> Result<(), String> {
    let missing: Vec<String> = NORMALISED_KEYS
        .iter()
        .zip(NORMALISED_UNITS)
        .filter(|(k, _)| !keys.iter().any(|g| g == *k))
        .map(|(k, u)| format!("{k} [{u}]"))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "{origin}: [pendulum3d] in the normalised form (MODEL.md 7.3) needs every key; \
             missing: {}. Or give the physical form (mass, length, inertia_xx, ...); \
             `pendtilt rig --template 3d` prints a rig file with every key",
            missing.join(", ")
        ));
    }
    Ok(())
}

/// `key: why` for a gyro full scale no gyro has (the planar rig's rule).
fn check_gyro(g: &GyroSettings<f64>) -> Result<(), String> {
    match g.full_scale {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(format!(
            "gyro.full_scale: the full scale must be > 0 [rad/s] (leave it out when unknown), \
             got {:?}",
            v
        )),
        _ => Ok(()),
    }
}

/// `key: why` for a normalised value no pendulum has.
fn check_normalised(c: &CardanParams<f64>) -> Result<(), String> {
    let positive = [
        ("b_x", c.b_x),
        ("b_y", c.b_y),
        ("b_z", c.b_z),
        ("gravity", c.gravity),
    ];
    for (k, v) in positive {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{k}: must be finite and > 0, got {v:?}"));
        }
    }
    for (k, v) in [("a_x", c.a_x), ("a_y", c.a_y), ("b_ring", c.b_ring)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!("{k}: must be finite and >= 0, got {v:?}"));
        }
    }
    if c.c.iter().any(|v| !v.is_finite()) {
        return Err(format!("c: must be finite, got {:?}", c.c));
    }
    Ok(())
}
