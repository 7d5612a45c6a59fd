//! What a rig file error says: where ([`Location`]) and why ([`ConfigErrorKind`]).
use std::fmt;

use super::doubts::shown;

/// Where a configuration error is: the file, the position in it, and the dotted key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file name (or the origin name given to
    /// [`RigConfig::from_toml_str`](super::RigConfig::from_toml_str)).
    pub file: String,
    /// 1-based line of the offending key or value, when it was in the file.
    pub line: Option<usize>,
    /// 1-based column (in characters) of the offending key or value, when it was in the file.
    pub column: Option<usize>,
    /// Dotted path of the key, e.g. `pendulum.mass`; `None` for file-level errors.
    pub key: Option<String>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        if let Some(key) = &self.key {
            write!(f, ": {key}")?;
        }
        Ok(())
    }
}

/// Why a rig file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum ConfigErrorKind {
    /// The file could not be read.
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
    /// The text is not valid TOML.
    #[error("TOML syntax error: {0}")]
    Syntax(String),
    /// A key (or table) that the rig file does not have.
    #[error("unknown key; allowed here: {allowed}{hint}")]
    UnknownKey {
        /// The keys allowed in this table, comma-separated.
        allowed: String,
        /// What the key says about the file (`; a 3-D rig file's table ...`), or empty.
        hint: String,
    },
    /// A string that is not one of the allowed choices (e.g. `response = "chebyshev"`).
    #[error("not one of the choices: {0}")]
    BadChoice(String),
    /// A value of the wrong TOML type (e.g. a string where a number is expected).
    #[error("wrong type: {0}")]
    WrongType(String),
    /// The `[pendulum]` table mixes physical and normalised keys.
    #[error(
        "mixes the physical form ({physical}) with the normalised form ({normalised}); \
         give either mass/length/inertia/damping/pivot_offset/gravity or a/b/c"
    )]
    MixedPendulumForms {
        /// The physical keys present.
        physical: String,
        /// The normalised keys present.
        normalised: String,
    },
    /// A value that no real rig can have.
    #[error("impossible value {}: {why}", shown(*.value))]
    Impossible {
        /// The value as given (or defaulted).
        value: f64,
        /// The rule it breaks.
        why: String,
    },
}

/// An error in a rig file: where it is ([`Location`]) and why ([`ConfigErrorKind`]).
///
/// Displays as `rig.toml:3:8: pendulum.mass: impossible value -1: mass must be > 0 [kg]`.
#[derive(Debug, thiserror::Error)]
#[error("{location}: {kind}")]
pub struct ConfigError {
    /// File, line, column and key.
    pub location: Location,
    /// What is wrong (boxed to keep `Result<_, ConfigError>` small).
    pub kind: Box<ConfigErrorKind>,
}

impl ConfigError {
    pub(super) fn new(location: Location, kind: ConfigErrorKind) -> Self {
        Self {
            location,
            kind: Box::new(kind),
        }
    }
}
