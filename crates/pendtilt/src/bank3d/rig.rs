//! The 3-D rig file (MODEL.md 7.6) as `estimate` reads it: `[pendulum3d]` in the physical
//! form ([`Pendulum3d`], what `simulate` writes) or the normalised one
//! ([`CardanParams`]: `a_x, a_y, b_x, b_y, b_z, b_ring, c, gravity`, every key given),
//! never both; `[mounting]` optional. Errors name the file, and the line and column when
//! the TOML parser gives a position.
use std::path::Path;

use pendtilt_core::spatial::cardan::CardanParams;
use serde::Deserialize;

use crate::sim3d::{Mounting, Pendulum3d};

/// The keys of the normalised form.
const NORMALISED_KEYS: [&str; 8] = ["a_x", "a_y", "b_x", "b_y", "b_z", "b_ring", "c", "gravity"];

/// The pendulum of a 3-D rig file, in the form the file gave it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pendulum3dConfig {
    /// Physical values.
    Physical(Pendulum3d),
    /// Normalised values (MODEL.md 7.3).
    Normalised(CardanParams<f64>),
}

impl Pendulum3dConfig {
    /// The normalised parameters the estimators use.
    pub fn params(&self) -> CardanParams<f64> {
        match self {
            Self::Physical(p) => p.normalised(),
            Self::Normalised(c) => *c,
        }
    }
}

/// A 3-D rig file: the pendulum and where the sensors sit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rig3dConfig {
    /// `[pendulum3d]`.
    pub pendulum3d: Pendulum3dConfig,
    /// `[mounting]` (default: every sensor at P1).
    pub mounting: Mounting,
}

impl Default for Rig3dConfig {
    /// MODEL.md 7.6's rig.
    fn default() -> Self {
        Self {
            pendulum3d: Pendulum3dConfig::Physical(Pendulum3d::default()),
            mounting: Mounting::default(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File<P> {
    pendulum3d: P,
    #[serde(default)]
    mounting: Mounting,
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
        let keys: Vec<String> = match table.get("pendulum3d") {
            Some(toml::Value::Table(t)) => t.keys().cloned().collect(),
            _ => Vec::new(),
        };
        let normalised: Vec<&String> = keys
            .iter()
            .filter(|k| NORMALISED_KEYS.contains(&k.as_str()) && *k != "gravity")
            .collect();
        let physical: Vec<&String> = keys
            .iter()
            .filter(|k| !NORMALISED_KEYS.contains(&k.as_str()))
            .collect();
        if !normalised.is_empty() && !physical.is_empty() {
            return Err(format!(
                "{origin}: pendulum3d: mixes the physical form ({}) with the normalised form \
                 ({}); give one",
                physical
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                normalised
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if normalised.is_empty() {
            let f: File<Pendulum3d> =
                toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
            f.pendulum3d
                .validate()
                .map_err(|e| format!("{origin}: {e}"))?;
            return Ok(Self {
                pendulum3d: Pendulum3dConfig::Physical(f.pendulum3d),
                mounting: f.mounting,
            });
        }
        let f: File<CardanParams<f64>> =
            toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        check_normalised(&f.pendulum3d).map_err(|e| format!("{origin}: pendulum3d.{e}"))?;
        Ok(Self {
            pendulum3d: Pendulum3dConfig::Normalised(f.pendulum3d),
            mounting: f.mounting,
        })
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
            return Err(format!("{k}: must be finite and > 0, got {v}"));
        }
    }
    for (k, v) in [("a_x", c.a_x), ("a_y", c.a_y), ("b_ring", c.b_ring)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!("{k}: must be finite and >= 0, got {v}"));
        }
    }
    if c.c.iter().any(|v| !v.is_finite()) {
        return Err(format!("c: must be finite, got {:?}", c.c));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The physical and the normalised form of one pendulum give the same parameters.
    #[test]
    fn both_forms_give_the_same_parameters() {
        let p = Pendulum3d {
            ring_inertia: 2e-5,
            pivot_offset: [0.01, 0.0, 0.1],
            ..Pendulum3d::default()
        };
        let phys = crate::sim3d::Rig3d {
            pendulum3d: p,
            mounting: Mounting::default(),
        }
        .to_toml_string()
        .unwrap();
        let a = Rig3dConfig::from_toml_str(&phys, "p.toml").unwrap();
        let n = p.normalised();
        let norm = format!(
            "[pendulum3d]\na_x = {}\na_y = {}\nb_x = {}\nb_y = {}\nb_z = {}\nb_ring = {}\n\
             c = [{}, {}, {}]\ngravity = {}\n",
            n.a_x, n.a_y, n.b_x, n.b_y, n.b_z, n.b_ring, n.c[0], n.c[1], n.c[2], n.gravity
        );
        let b = Rig3dConfig::from_toml_str(&norm, "n.toml").unwrap();
        assert!(matches!(b.pendulum3d, Pendulum3dConfig::Normalised(_)));
        assert_eq!(a.pendulum3d.params(), b.pendulum3d.params());
        // 1 / sqrt(b_x + b_ring) is the outer axis' natural frequency (MODEL.md 7.2).
        let w = p.natural_frequencies(0.0)[0];
        let c = b.pendulum3d.params();
        assert!((w - 1.0 / (c.b_x + c.b_ring).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let e =
            Rig3dConfig::from_toml_str("[pendulum3d]\nmass = \"heavy\"\n", "r.toml").unwrap_err();
        assert!(e.starts_with("r.toml:2:8: "), "{e}");
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\nmas = 0.05\n", "r.toml").unwrap_err();
        assert!(e.starts_with("r.toml:2:1: ") && e.contains("mass"), "{e}");
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\nmass = 0.05\nb_x = 1\n", "r.toml")
            .unwrap_err();
        assert!(e.contains("mixes the physical form (mass)"), "{e}");
        let e = Rig3dConfig::from_toml_str("[pendulum3d]\nmass = -1\n", "r.toml").unwrap_err();
        assert!(e.contains("pendulum3d.mass"), "{e}");
    }
}
