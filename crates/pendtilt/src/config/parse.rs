//! Reading a rig file: the `[pendulum]` table's forms, and the parser that checks every
//! table and key and names the place of each error.
use serde::{Deserialize, Serialize};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

use pendtilt_core::estimators::equations::Alg3Gains;
use pendtilt_core::{PendulumParams, PhysicalParams};

use super::{checks, tables};
use super::{ConfigError, ConfigErrorKind, Location, PendulumConfig, RigConfig, TABLES_3D};

/// The `[pendulum]` table as written: every key optional, the form decided by the keys.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct RawPendulum {
    #[serde(skip_serializing_if = "Option::is_none")]
    mass: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    length: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    inertia: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    damping: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pivot_offset: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    gravity: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    a: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    b: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    c: Option<f64>,
}

impl RawPendulum {
    /// The physical keys given and the normalised keys given.
    fn forms(&self) -> (Vec<&'static str>, Vec<&'static str>) {
        let present = |list: &[(&'static str, Option<f64>)]| -> Vec<&'static str> {
            list.iter()
                .filter(|(_, v)| v.is_some())
                .map(|(k, _)| *k)
                .collect()
        };
        let physical = present(&[
            ("mass", self.mass),
            ("length", self.length),
            ("inertia", self.inertia),
            ("damping", self.damping),
            ("pivot_offset", self.pivot_offset),
            ("gravity", self.gravity),
        ]);
        let normalised = present(&[("a", self.a), ("b", self.b), ("c", self.c)]);
        (physical, normalised)
    }

    /// The error of a table that mixes the two forms, if it does.
    fn mixed(&self) -> Option<ConfigErrorKind> {
        let (physical, normalised) = self.forms();
        (!physical.is_empty() && !normalised.is_empty()).then(|| {
            ConfigErrorKind::MixedPendulumForms {
                physical: physical.join(", "),
                normalised: normalised.join(", "),
            }
        })
    }
}

impl TryFrom<RawPendulum> for PendulumConfig {
    type Error = ConfigErrorKind;

    fn try_from(raw: RawPendulum) -> Result<Self, ConfigErrorKind> {
        if let Some(mixed) = raw.mixed() {
            return Err(mixed);
        }
        Ok(if raw.a.or(raw.b).or(raw.c).is_none() {
            let d = PhysicalParams::<f64>::default();
            PendulumConfig::Physical(PhysicalParams {
                mass: raw.mass.unwrap_or(d.mass),
                length: raw.length.unwrap_or(d.length),
                inertia: raw.inertia.unwrap_or(d.inertia),
                damping: raw.damping.unwrap_or(d.damping),
                pivot_offset: raw.pivot_offset.unwrap_or(d.pivot_offset),
                gravity: raw.gravity.unwrap_or(d.gravity),
            })
        } else {
            let d = PendulumParams::<f64>::default();
            PendulumConfig::Normalised(PendulumParams {
                a: raw.a.unwrap_or(d.a),
                b: raw.b.unwrap_or(d.b),
                c: raw.c.unwrap_or(d.c),
            })
        })
    }
}

impl From<PendulumConfig> for RawPendulum {
    fn from(p: PendulumConfig) -> Self {
        match p {
            PendulumConfig::Physical(p) => Self {
                mass: Some(p.mass),
                length: Some(p.length),
                inertia: Some(p.inertia),
                damping: Some(p.damping),
                pivot_offset: Some(p.pivot_offset),
                gravity: Some(p.gravity),
                ..Self::default()
            },
            PendulumConfig::Normalised(p) => Self {
                a: Some(p.a),
                b: Some(p.b),
                c: Some(p.c),
                ..Self::default()
            },
        }
    }
}

/// 1-based (line, column in characters) of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let mut start = offset;
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// One parse of a rig text: the values (`toml::Table`) and their positions (`DeTable`).
pub(super) struct Parser<'a> {
    text: &'a str,
    origin: &'a str,
    spans: Spanned<DeTable<'a>>,
    values: toml::Table,
}

type Span = std::ops::Range<usize>;

impl<'a> Parser<'a> {
    pub(super) fn new(text: &'a str, origin: &'a str) -> Result<Self, ConfigError> {
        let syntax = |e: toml::de::Error| {
            let (line, column) = match e.span() {
                Some(span) => {
                    let (l, c) = line_column(text, span.start);
                    (Some(l), Some(c))
                }
                None => (None, None),
            };
            ConfigError::new(
                Location {
                    file: origin.to_string(),
                    line,
                    column,
                    key: None,
                },
                ConfigErrorKind::Syntax(e.message().trim().to_string()),
            )
        };
        let spans = DeTable::parse(text).map_err(syntax)?;
        let values: toml::Table = text.parse().map_err(syntax)?;
        Ok(Self {
            text,
            origin,
            spans,
            values,
        })
    }

    fn at(&self, span: Option<Span>, key: Option<String>) -> Location {
        let (line, column) = match span {
            Some(s) => {
                let (l, c) = line_column(self.text, s.start);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        Location {
            file: self.origin.to_string(),
            line,
            column,
            key,
        }
    }

    /// The (key span, value span) of each key of `table` (or of the top level when
    /// `table` is `None`), in file order.
    fn entries(&self, table: Option<&str>) -> Vec<(String, Span, Span)> {
        let top = self.spans.get_ref();
        let map = match table {
            None => Some(top),
            Some(name) => top
                .iter()
                .find(|(k, _)| k.get_ref().as_ref() == name)
                .and_then(|(_, v)| match v.get_ref() {
                    DeValue::Table(t) => Some(t),
                    _ => None,
                }),
        };
        let mut out: Vec<_> = map
            .into_iter()
            .flat_map(|m| m.iter())
            .map(|(k, v)| (k.get_ref().to_string(), k.span(), v.span()))
            .collect();
        out.sort_by_key(|(_, k, _)| k.start);
        out
    }

    fn key_span(&self, table: &str, key: &str) -> Option<Span> {
        let entries = self.entries(Some(table));
        entries.into_iter().find(|e| e.0 == key).map(|e| e.1)
    }

    fn value_span(&self, table: &str, key: &str) -> Option<Span> {
        let entries = self.entries(Some(table));
        entries.into_iter().find(|e| e.0 == key).map(|e| e.2)
    }

    /// The file's values for `name` alone read as a whole rig file (the serde form of
    /// [`RigConfig`]).
    fn read_alone(name: &str, table: toml::Table) -> Result<RigConfig, toml::de::Error> {
        let mut file = toml::Table::new();
        file.insert(name.to_string(), toml::Value::Table(table));
        RigConfig::deserialize(toml::Value::Table(file))
    }

    /// Checks one top-level entry: a known table name, a table, and then its keys one more
    /// at a time in file order, so that an error names the key that made the table
    /// unreadable and its position.
    fn check_table(
        &self,
        name: &str,
        name_span: Span,
        value_span: Span,
    ) -> Result<(), ConfigError> {
        if let Err(e) = Self::read_alone(name, toml::Table::new()) {
            // The only error an empty table can give: a name that is not a table's.
            // A 3-D rig's table: the file, not the key, is the mistake.
            let hint = if TABLES_3D.contains(&name) {
                format!(
                    "; [{name}] is a table of a 3-D rig file (MODEL.md 7.6), and a planar rig is \
                     read here: give a planar rig file ([pendulum], MODEL.md 5), or \
                     check that the log is the one meant"
                )
            } else {
                String::new()
            };
            return Err(ConfigError::new(
                self.at(Some(name_span), Some(name.to_string())),
                ConfigErrorKind::UnknownKey {
                    allowed: allowed(e.message(), true),
                    hint,
                },
            ));
        }
        let Some(value) = self.values.get(name) else {
            return Ok(());
        };
        let toml::Value::Table(table) = value else {
            return Err(ConfigError::new(
                self.at(Some(value_span), Some(name.to_string())),
                ConfigErrorKind::WrongType(format!(
                    "`{name}` must be a table ([{name}]), found a {}",
                    value.type_str()
                )),
            ));
        };
        let mut read = toml::Table::new();
        for (key, _, _) in self.entries(Some(name)) {
            let Some(v) = table.get(&key) else { continue };
            read.insert(key.clone(), v.clone());
            if let Err(e) = Self::read_alone(name, read.clone()) {
                return Err(self.key_error(name, &key, &read, e.message().trim()));
            }
        }
        Ok(())
    }

    /// The error of `table.key`, the key whose addition to `read` gave `message`.
    fn key_error(&self, table: &str, key: &str, read: &toml::Table, message: &str) -> ConfigError {
        let dotted = format!("{table}.{key}");
        let at_value = self.at(self.value_span(table, key), Some(dotted.clone()));
        let kind = if message.starts_with("unknown field") {
            return ConfigError::new(
                self.at(self.key_span(table, key), Some(dotted)),
                ConfigErrorKind::UnknownKey {
                    allowed: allowed(message, false),
                    hint: String::new(),
                },
            );
        } else if message.starts_with("unknown variant") {
            ConfigErrorKind::BadChoice(message.to_string())
        } else if ["invalid ", "missing ", "duplicate "]
            .iter()
            .any(|p| message.starts_with(p))
        {
            ConfigErrorKind::WrongType(message.to_string())
        } else if let Some(mixed) = (table == "pendulum")
            .then(|| RawPendulum::deserialize(toml::Value::Table(read.clone())).ok())
            .flatten()
            .and_then(|raw| raw.mixed())
        {
            let location = self.at(self.key_span(table, key), Some(table.to_string()));
            return ConfigError::new(location, mixed);
        } else {
            // A rule of the table's file form (tables.rs): an impossible value.
            let v = read.get(key);
            match v.and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64))) {
                Some(value) => ConfigErrorKind::Impossible {
                    value,
                    why: message.to_string(),
                },
                None => ConfigErrorKind::WrongType(message.to_string()),
            }
        };
        ConfigError::new(at_value, kind)
    }

    pub(super) fn parse(self) -> Result<RigConfig, ConfigError> {
        for (name, name_span, value_span) in self.entries(None) {
            self.check_table(&name, name_span, value_span)?;
        }
        let mut cfg =
            RigConfig::deserialize(toml::Value::Table(self.values.clone())).map_err(|e| {
                ConfigError::new(
                    self.at(None, None),
                    ConfigErrorKind::WrongType(e.message().trim().to_string()),
                )
            })?;
        // Gains left out are the Eq (21) equivalent of this file's pendulum (tables::alg3).
        let eq21 = Alg3Gains::from_params(&cfg.params());
        let given = |key: &str| self.values.get("alg3").and_then(|t| t.get(key)).is_some();
        let g = &mut cfg.alg3.gains;
        for ((gain, key), value) in [&mut g.k, &mut g.l, &mut g.m, &mut g.n]
            .into_iter()
            .zip(tables::alg3::GAINS)
            .zip([eq21.k, eq21.l, eq21.m, eq21.n])
        {
            if !given(key) {
                *gain = value;
            }
        }
        if let Some((key, value, why)) = checks::issues(&cfg).into_iter().next() {
            let (table, k) = key.split_once('.').unwrap_or((key.as_str(), ""));
            let span = self.value_span(table, k);
            let why = if span.is_none() {
                format!("{why} (the value is the default: set it in [{table}])")
            } else {
                why
            };
            return Err(ConfigError::new(
                self.at(span, Some(key.clone())),
                ConfigErrorKind::Impossible { value, why },
            ));
        }
        Ok(cfg)
    }
}

/// The names serde's "unknown field `x`, expected one of `a`, `b`" allows, as `a, b`
/// (`[a], [b]` for the tables of the top level).
fn allowed(message: &str, tables: bool) -> String {
    let list = message
        .split_once("expected ")
        .map_or("", |(_, rest)| rest.trim_start_matches("one of "));
    let names = list
        .split(", ")
        .map(|n| n.trim().trim_matches('`'))
        .filter(|n| !n.is_empty());
    if tables {
        names
            .map(|n| format!("[{n}]"))
            .collect::<Vec<_>>()
            .join(", ")
    } else {
        names
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_column_counts_characters() {
        let text = "ab\n\u{e9}x = 1\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 3), (2, 1));
        // 'x' is after a 2-byte character: byte 5, column 2.
        assert_eq!(line_column(text, 5), (2, 2));
    }
}
