//! The columns of a sensor log (MODEL.md section 5), how other names map onto them
//! (`--map`), which ones are in degrees (`--deg`), and what was found in a header.
use std::fmt;
use std::str::FromStr;

use crate::sensors::Sensor;

/// A column of the sensor log contract (MODEL.md section 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Column {
    /// `t`: time \[s\], strictly increasing. Required.
    T,
    /// `phi`: encoder, pendulum angle relative to the body \[rad\].
    Phi,
    /// `gyro`: body rate about the tilt axis \[rad/s\].
    Gyro,
    /// `ax`: accelerometer specific force along body x \[m/s^2\].
    Ax,
    /// `ay`: accelerometer specific force along body y \[m/s^2\].
    Ay,
    /// `theta`: true tilt \[rad\] (potentiometer), optional.
    Theta,
}

impl Column {
    /// Every column, in the contract's order.
    pub const ALL: [Column; 6] = [
        Column::T,
        Column::Phi,
        Column::Gyro,
        Column::Ax,
        Column::Ay,
        Column::Theta,
    ];

    /// The contract name (`t`, `phi`, `gyro`, `ax`, `ay`, `theta`).
    pub fn name(self) -> &'static str {
        match self {
            Column::T => "t",
            Column::Phi => "phi",
            Column::Gyro => "gyro",
            Column::Ax => "ax",
            Column::Ay => "ay",
            Column::Theta => "theta",
        }
    }

    /// The column with this contract name, if any (exact, case-sensitive).
    pub fn from_name(name: &str) -> Option<Column> {
        Column::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The SI unit the contract uses for this column.
    pub fn unit(self) -> &'static str {
        match self {
            Column::T => "s",
            Column::Phi | Column::Theta => "rad",
            Column::Gyro => "rad/s",
            Column::Ax | Column::Ay => "m/s^2",
        }
    }

    /// True for the columns `--deg` can convert: the angles `phi`, `theta` and the rate `gyro`.
    pub fn is_angular(self) -> bool {
        matches!(self, Column::Phi | Column::Gyro | Column::Theta)
    }

    pub(crate) fn index(self) -> usize {
        self as usize
    }

    /// The sensor whose reading this column holds (`None`: the time and the truth). A
    /// `match`, not a search of the table by name: the planar pass asks it per row.
    pub fn sensor(self) -> Option<Sensor> {
        match self {
            Column::Phi => Some(Sensor::Encoder),
            Column::Gyro => Some(Sensor::Gyro),
            Column::Ax | Column::Ay => Some(Sensor::Accel),
            Column::T | Column::Theta => None,
        }
    }

    /// True when `present` holds every column of `sensor`: a planar log provides it
    /// (never a sensor a planar log has no column of).
    pub fn provides(sensor: Sensor, present: impl Fn(Column) -> bool) -> bool {
        let columns = sensor.spec().planar_columns;
        !columns.is_empty()
            && (columns.iter()).all(|name| Column::from_name(name).is_some_and(&present))
    }
}

impl fmt::Display for Column {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A bad `--map` or `--deg` option.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OptionError {
    /// A name that is not a column of the contract.
    #[error(
        "`{0}` is not a log column; the columns are t, phi, gyro, ax, ay, theta (planar), or \
         t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az, speed, roll, pitch (3-D)"
    )]
    UnknownColumn(String),
    /// A `--map` entry without `=`, or with an empty side.
    #[error("`{0}` is not of the form column=header_name (e.g. phi=enc_angle)")]
    BadMapEntry(String),
    /// The same contract column mapped twice.
    #[error("`{0}` is mapped twice")]
    MappedTwice(String),
    /// Two contract columns mapped onto the same header name.
    #[error("`{source_name}` is mapped onto both `{first}` and `{second}`")]
    SameSource {
        /// The header name.
        source_name: String,
        /// The first column mapped onto it.
        first: String,
        /// The second column mapped onto it.
        second: String,
    },
    /// `--deg` names a column that is not an angle or angular rate.
    #[error("`{0}` is not an angle or angular rate; --deg takes phi, gyro, theta (or all)")]
    NotAngular(String),
    /// `--negate` names the time.
    #[error("`t` has no sign to reverse; --negate takes phi, gyro, ax, ay, theta")]
    NegatedTime,
}

/// Which header name feeds each contract column (`--map phi=enc_angle,gyro=gz`).
///
/// A column that is not mapped is read from the header column of its own name, if there
/// is one. Mapping a column onto a name that is not in the header is an error (the user
/// asked for it explicitly), not a silent miss.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ColumnMap {
    sources: [Option<String>; 6],
    /// `(column, source)` for the 3-D log's columns (MODEL.md 7.6; `t`, `ax`, `ay` are
    /// in both contracts and land in both).
    spatial: Vec<(String, String)>,
}

impl ColumnMap {
    /// No mapping: every column is read under its own name.
    pub fn new() -> Self {
        Self::default()
    }

    /// Reads `column` from the header column named `source`.
    pub fn set(&mut self, column: Column, source: impl Into<String>) {
        self.sources[column.index()] = Some(source.into());
    }

    /// The header name mapped onto `column`, if it was mapped.
    pub fn source(&self, column: Column) -> Option<&str> {
        self.sources[column.index()].as_deref()
    }

    /// True when nothing is mapped.
    pub fn is_empty(&self) -> bool {
        self.sources.iter().all(Option::is_none) && self.spatial.is_empty()
    }

    /// The entries naming a 3-D log's columns (MODEL.md 7.6), `(column, source)`: a 3-D
    /// log's header is read with each source renamed to its column.
    pub fn spatial(&self) -> &[(String, String)] {
        &self.spatial
    }

    /// The columns mapped that only a 3-D log has (`phi_x`, `gyro_z`, ...): an error on a
    /// planar log.
    pub fn spatial_only(&self) -> Vec<&str> {
        (self.spatial.iter())
            .map(|(c, _)| c.as_str())
            .filter(|c| Column::from_name(c).is_none())
            .collect()
    }

    /// The columns mapped that only a planar log has (`phi`, `gyro`, `theta`): an error on
    /// a 3-D log.
    pub fn planar_only(&self) -> Vec<&str> {
        (Column::ALL.into_iter())
            .filter(|c| self.source(*c).is_some())
            .map(|c| c.name())
            .filter(|c| !super::LOG3D_COLUMNS.contains(c))
            .collect()
    }

    /// `header` with each mapped 3-D source renamed to its column.
    pub fn rename_spatial(&self, header: &[String]) -> Vec<String> {
        header
            .iter()
            .map(|h| {
                (self.spatial.iter())
                    .find(|(_, s)| s == h)
                    .map_or_else(|| h.clone(), |(c, _)| c.clone())
            })
            .collect()
    }
}

impl FromStr for ColumnMap {
    type Err = OptionError;

    /// Parses `phi=enc_angle,gyro=gz` (entries separated by commas; spaces around names
    /// are ignored; an empty string maps nothing).
    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        let mut map = ColumnMap::new();
        for entry in spec.split(',').map(str::trim).filter(|e| !e.is_empty()) {
            let (col, source) = entry
                .split_once('=')
                .map(|(c, s)| (c.trim(), s.trim()))
                .filter(|(c, s)| !c.is_empty() && !s.is_empty())
                .ok_or_else(|| OptionError::BadMapEntry(entry.to_string()))?;
            let planar = Column::from_name(col);
            let spatial = super::LOG3D_COLUMNS.contains(&col);
            if planar.is_none() && !spatial {
                return Err(OptionError::UnknownColumn(col.into()));
            }
            let mapped = planar.and_then(|c| map.source(c)).is_some()
                || map.spatial.iter().any(|(c, _)| c == col);
            if mapped {
                return Err(OptionError::MappedTwice(col.to_string()));
            }
            let other = (Column::ALL.into_iter())
                .filter(|c| map.source(*c) == Some(source))
                .map(|c| c.name().to_string())
                .chain(
                    (map.spatial.iter())
                        .filter(|(_, s)| s == source)
                        .map(|(c, _)| c.clone()),
                )
                .next();
            if let Some(other) = other {
                return Err(OptionError::SameSource {
                    source_name: source.to_string(),
                    first: other,
                    second: col.to_string(),
                });
            }
            if let Some(column) = planar {
                map.set(column, source);
            }
            if spatial {
                map.spatial.push((col.to_string(), source.to_string()));
            }
        }
        Ok(map)
    }
}

/// Which angular columns of the log are in degrees (`--deg`); they are converted to
/// radians (or rad/s) as they are read.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DegreeColumns(u8);

impl DegreeColumns {
    /// Every column in SI units (the default).
    pub fn none() -> Self {
        Self(0)
    }

    /// `phi`, `gyro` and `theta` all in degrees (deg/s for `gyro`): plain `--deg`.
    pub fn all() -> Self {
        let mut d = Self(0);
        for c in Column::ALL.into_iter().filter(|c| c.is_angular()) {
            d.0 |= 1 << c.index();
        }
        d
    }

    /// Marks one angular column as degrees. Errors for `t`, `ax`, `ay`.
    pub fn insert(&mut self, column: Column) -> Result<(), OptionError> {
        if !column.is_angular() {
            return Err(OptionError::NotAngular(column.name().to_string()));
        }
        self.0 |= 1 << column.index();
        Ok(())
    }

    /// True when `column` is read in degrees.
    pub fn contains(self, column: Column) -> bool {
        self.0 & (1 << column.index()) != 0
    }
}

impl FromStr for DegreeColumns {
    type Err = OptionError;

    /// Parses `all` (or an empty string) as every angular column, else a comma-separated
    /// list such as `phi,theta`.
    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        let spec = spec.trim();
        if spec.is_empty() || spec == "all" {
            return Ok(Self::all());
        }
        let mut d = Self::none();
        for name in spec.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let column =
                Column::from_name(name).ok_or_else(|| OptionError::UnknownColumn(name.into()))?;
            d.insert(column)?;
        }
        Ok(d)
    }
}

/// Which columns of the log count the other way from MODEL.md section 1's signs
/// (`--negate`: an encoder or a gyro mounted the other way round, an accelerometer axis
/// reversed); they are negated as they are read.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NegatedColumns(u8);

impl NegatedColumns {
    /// No column negated (the default).
    pub fn none() -> Self {
        Self(0)
    }

    /// True when `column` is negated.
    pub fn contains(self, column: Column) -> bool {
        self.0 & (1 << column.index()) != 0
    }
}

impl FromStr for NegatedColumns {
    type Err = OptionError;

    /// Parses a comma-separated list such as `phi,gyro`.
    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        let mut n = Self::none();
        for name in spec.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let column =
                Column::from_name(name).ok_or_else(|| OptionError::UnknownColumn(name.into()))?;
            if column == Column::T {
                return Err(OptionError::NegatedTime);
            }
            n.0 |= 1 << column.index();
        }
        Ok(n)
    }
}

/// How one contract column was found in the header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ColumnStatus {
    /// The contract column.
    pub column: Column,
    /// The header name it is read from, when present.
    pub source: Option<String>,
    /// 0-based position of that header field.
    pub position: Option<usize>,
    /// True when the source came from `--map` rather than the contract name.
    pub mapped: bool,
    /// True when the column is read in degrees and converted.
    pub degrees: bool,
    /// For a missing column: a header name that matches it but for case or spaces
    /// (`Phi`, ` phi `), or that is its name and a unit (`gyro[deg/s]`, `phi_rad`),
    /// offered as a `--map` suggestion (with `--deg` for degrees); never used on its own.
    pub suggestion: Option<String>,
}

/// What the header gave: for every contract column, found (and how) or missing; and the
/// other columns, which are ignored.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ColumnReport {
    /// One entry per contract column, in [`Column::ALL`] order.
    pub columns: Vec<ColumnStatus>,
    /// Header names not used by any contract column, in file order.
    pub ignored: Vec<String>,
}

impl ColumnReport {
    /// The status of one contract column.
    pub fn status(&self, column: Column) -> &ColumnStatus {
        &self.columns[column.index()]
    }

    /// True when the log has this column.
    pub fn has(&self, column: Column) -> bool {
        self.status(column).position.is_some()
    }

    /// The contract columns the log lacks.
    pub fn missing(&self) -> Vec<Column> {
        Column::ALL.into_iter().filter(|c| !self.has(*c)).collect()
    }
}

impl fmt::Display for ColumnReport {
    /// One line: `columns: t, phi <- enc_angle (deg), gyro; missing: ax, ay, theta; ignored: temp`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("columns: ")?;
        let mut first = true;
        for s in self.columns.iter().filter(|s| s.position.is_some()) {
            if !first {
                f.write_str(", ")?;
            }
            first = false;
            f.write_str(s.column.name())?;
            if s.mapped {
                write!(f, " <- {}", s.source.as_deref().unwrap_or(""))?;
            }
            if s.degrees {
                f.write_str(" (deg)")?;
            }
        }
        let missing = self.missing();
        if !missing.is_empty() {
            let names: Vec<String> = missing
                .iter()
                .map(|c| match &self.status(*c).suggestion {
                    Some(s) => {
                        // A name that states degrees wants --deg too (see
                        // [`header_unit_warning`]).
                        let deg = match unit_in_name(s) {
                            Some(NamedUnit::Degrees) => format!(" --deg {c}"),
                            _ => String::new(),
                        };
                        format!(
                            "{c} (the header has `{s}`: --map {}{deg}?)",
                            shell_word(&format!("{c}={s}"))
                        )
                    }
                    None => c.name().to_string(),
                })
                .collect();
            write!(f, "; missing: {}", names.join(", "))?;
        }
        if !self.ignored.is_empty() {
            write!(f, "; ignored: {}", self.ignored.join(", "))?;
        }
        Ok(())
    }
}

/// The angular unit a header name states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NamedUnit {
    /// Degrees or degrees per second (`phi_deg`, `gyro[deg/s]`, `gyro_dps`, `theta (°)`).
    Degrees,
    /// Radians or radians per second (`phi_rad`, `gyro[rad/s]`, `gyro_rads`).
    Radians,
}

impl NamedUnit {
    /// `deg`/`deg/s` or `rad`/`rad/s`, as `column` takes it.
    fn unit(self, column: Column) -> &'static str {
        match (self, column) {
            (NamedUnit::Degrees, Column::Gyro) => "deg/s",
            (NamedUnit::Degrees, _) => "degrees",
            (NamedUnit::Radians, Column::Gyro) => "rad/s",
            (NamedUnit::Radians, _) => "radians",
        }
    }
}

/// The words of a header name, lower case, split at anything but letters, digits and `°`
/// (`gyro[deg/s]` -> gyro, deg, s).
fn name_words(name: &str) -> Vec<String> {
    name.to_lowercase()
        .split(|ch: char| !(ch.is_alphanumeric() || ch == '°'))
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect()
}

/// The angular unit header name `name` states as a word of its own (`deg`, `degs`,
/// `degree(s)`, `dps`, `°`; `rad`, `rads`, `radian(s)`), if it states one and not both.
/// A name that says nothing about units (`gyro`, `enc_angle`, `gradient`) gives `None`.
pub fn unit_in_name(name: &str) -> Option<NamedUnit> {
    let words = name_words(name);
    let has = |set: &[&str]| words.iter().any(|w| set.contains(&w.as_str()));
    let deg = has(&["deg", "degs", "degree", "degrees", "dps", "°"]);
    let rad = has(&["rad", "rads", "radian", "radians"]);
    match (deg, rad) {
        (true, false) => Some(NamedUnit::Degrees),
        (false, true) => Some(NamedUnit::Radians),
        _ => None,
    }
}

/// The warning for angular column `column`, read from header name `name` in degrees
/// (`degrees`) or not, when the name states the other unit: the column, what the name
/// says, how it is read, and the fix, worded as the unit check's
/// ([`crate::units::UnitCheck`]): `read it with --deg gyro` / `leave gyro out of --deg`.
pub fn header_unit_warning(column: Column, name: &str, degrees: bool) -> Option<String> {
    if !column.is_angular() {
        return None;
    }
    let named = unit_in_name(name)?;
    let read = if degrees {
        NamedUnit::Degrees
    } else {
        NamedUnit::Radians
    };
    (named != read).then(|| {
        let fix = if degrees {
            format!("leave {column} out of --deg")
        } else {
            format!("read it with --deg {column}")
        };
        format!(
            "its name says {}, and it is read in {}{}: {fix}",
            named.unit(column),
            read.unit(column),
            if degrees { " (--deg)" } else { " (no --deg)" }
        )
    })
}

/// `word` as one shell word: as it is when plain, else in single quotes.
pub(crate) fn shell_word(word: &str) -> String {
    if word
        .chars()
        .all(|ch| ch.is_ascii_alphanumeric() || "_-.=,/:".contains(ch))
    {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

/// For a missing angular column: a header name that is the column's name and a unit
/// (`gyro[deg/s]`, `phi_rad`), offered as a `--map` suggestion.
pub(crate) fn unit_named_suggestion(column: Column, header: &[String]) -> Option<String> {
    if !column.is_angular() {
        return None;
    }
    header
        .iter()
        .find(|h| is_name_and_unit(h, column.name()))
        .cloned()
}

/// True when header name `h` is the name `column` (`gyro`, `gyro_x`) followed by an
/// angular unit ([`unit_in_name`]): `gyro[deg/s]`, `gyro_x_rad`, `roll (°)`.
fn is_name_and_unit(h: &str, column: &str) -> bool {
    let words = name_words(h);
    let col = name_words(column);
    words.len() > col.len() && words.starts_with(&col) && unit_in_name(h).is_some()
}

/// `text` as a literal in a sed pattern (`gyro_x[deg/s]` -> `gyro_x\[deg\/s\]`).
fn sed_literal(text: &str) -> String {
    text.chars()
        .flat_map(|ch| {
            let esc = "[]/.*^$\\".contains(ch);
            esc.then_some('\\').into_iter().chain(std::iter::once(ch))
        })
        .collect()
}

/// For a 3-D log (MODEL.md 7.6), whose columns are read by their names alone (no
/// `--map`, and `--deg` for every angular column or none): the header names in
/// `header` that are one of `columns` and an angular unit (`gyro_x[deg/s]`, `roll_deg`,
/// the planar reader's `unit_named_suggestion` rule), said with the fix: the `sed`
/// command that renames them in `file` on the header's `line` (1-based: a logger's
/// comment lines may come before it), and `--deg` when a name says degrees. `None` when
/// there is none.
pub fn unit_named_3d_hint(
    columns: &[&str],
    header: &[String],
    file: &str,
    line: u64,
) -> Option<String> {
    let found: Vec<(&str, &String)> = columns
        .iter()
        .filter(|c| !header.iter().any(|h| h == *c))
        .filter_map(|c| Some((*c, header.iter().find(|h| is_name_and_unit(h, c))?)))
        .collect();
    if found.is_empty() {
        return None;
    }
    let named: Vec<String> = found
        .iter()
        .map(|(c, h)| format!("`{h}` is `{c}`"))
        .collect();
    let sed: Vec<String> = found
        .iter()
        .map(|(c, h)| format!("{line}s/{}/{c}/", sed_literal(h)))
        .collect();
    let deg = found
        .iter()
        .any(|(_, h)| unit_in_name(h) == Some(NamedUnit::Degrees));
    let deg = if deg {
        "; then read it with --deg, which reads every angular column (phi_x, phi_y, gyro_*, \
         roll, pitch) in degrees (convert any in radians first)"
    } else {
        ""
    };
    Some(format!(
        "{} with {} in the name, and a 3-D log's columns are read by their MODEL.md 7.6 \
         names alone (no --map): rename {}: `sed -i '{}' {file}`{deg}",
        named.join(", "),
        if found.len() == 1 {
            "its unit"
        } else {
            "their units"
        },
        if found.len() == 1 { "it" } else { "them" },
        sed.join(";")
    ))
}

/// Words that name a time column on their own (`time`, `Timestamp`, `seconds`).
const TIME_WORDS: [&str; 9] = [
    "time",
    "timestamp",
    "times",
    "ts",
    "stamp",
    "elapsed",
    "seconds",
    "secs",
    "sec",
];

/// The time unit a header name states as a word of its own, as `--time-unit` takes it
/// (`s`, `ms`, `us`, `ns`): `Time [s]`, `t_ms`, `time (usec)`, `millis`.
pub(crate) fn time_unit_in_name(name: &str) -> Option<&'static str> {
    name_words(name).iter().find_map(|w| match w.as_str() {
        "s" | "sec" | "secs" | "second" | "seconds" => Some("s"),
        "ms" | "msec" | "millis" | "millisecond" | "milliseconds" => Some("ms"),
        "us" | "µs" | "usec" | "micros" | "microsecond" | "microseconds" => Some("us"),
        "ns" | "nsec" | "nanos" | "nanosecond" | "nanoseconds" => Some("ns"),
        _ => None,
    })
}

/// For a missing `t`: the header name that is most likely the time column, offered as a
/// `--map` suggestion: its first word names time (`time`, `Timestamp`, `Time [s]`,
/// `seconds`), or it is `t` with a time unit (`t_s`, `t[ms]`). `temp`, `theta`, `t_env`:
/// none.
pub(crate) fn time_named_suggestion(header: &[String]) -> Option<String> {
    header
        .iter()
        .find(|h| {
            let words = name_words(h);
            match words.first().map(String::as_str) {
                Some("t") => {
                    words.len() > 1 && words[1..].iter().all(|w| time_unit_in_name(w).is_some())
                }
                Some(w) => {
                    TIME_WORDS.contains(&w)
                        || (time_unit_in_name(w).is_some() && words.len() == 1 && w.len() > 2)
                }
                None => false,
            }
        })
        .cloned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_parses_and_rejects() {
        let m: ColumnMap = "phi=enc_angle, gyro = gz".parse().unwrap();
        assert_eq!(m.source(Column::Phi), Some("enc_angle"));
        assert_eq!(m.source(Column::Gyro), Some("gz"));
        assert_eq!(m.source(Column::T), None);
        assert!("".parse::<ColumnMap>().unwrap().is_empty());
        assert_eq!(
            "psi=x".parse::<ColumnMap>(),
            Err(OptionError::UnknownColumn("psi".into()))
        );
        assert_eq!(
            "phi".parse::<ColumnMap>(),
            Err(OptionError::BadMapEntry("phi".into()))
        );
        assert_eq!(
            "phi=a,phi=b".parse::<ColumnMap>(),
            Err(OptionError::MappedTwice("phi".into()))
        );
        assert!(matches!(
            "phi=a,theta=a".parse::<ColumnMap>(),
            Err(OptionError::SameSource { .. })
        ));
    }

    #[test]
    fn degrees_parse() {
        let all: DegreeColumns = "all".parse().unwrap();
        assert!(all.contains(Column::Phi) && all.contains(Column::Gyro));
        assert!(all.contains(Column::Theta) && !all.contains(Column::T));
        let some: DegreeColumns = "phi,theta".parse().unwrap();
        assert!(some.contains(Column::Phi) && !some.contains(Column::Gyro));
        assert_eq!(
            "ax".parse::<DegreeColumns>(),
            Err(OptionError::NotAngular("ax".into()))
        );
    }
}
