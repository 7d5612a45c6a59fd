//! The accelerometer's units (`--accel-unit`) and standard gravity: the scale between a
//! log's numbers and the contract's m/s^2. The reader applies it; the unit checks name it
//! in their fixes.
use std::fmt;
use std::str::FromStr;

/// Standard gravity \[m/s^2\]: what an accelerometer's `g` means (ISO 80000-3).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The unit of the accelerometer columns (`--accel-unit`): the contract's m/s^2, or the
/// g and mg that many IMUs write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelUnit {
    /// m/s^2 (the contract's unit).
    MetresPerSecondSquared,
    /// Standard gravity, [`STANDARD_GRAVITY`] m/s^2.
    G,
    /// Thousandths of standard gravity.
    MilliG,
}

impl AccelUnit {
    /// Every unit.
    pub const ALL: [AccelUnit; 3] = [
        AccelUnit::MetresPerSecondSquared,
        AccelUnit::G,
        AccelUnit::MilliG,
    ];

    /// m/s^2 per unit.
    pub fn metres_per_second_squared(self) -> f64 {
        match self {
            AccelUnit::MetresPerSecondSquared => 1.0,
            AccelUnit::G => STANDARD_GRAVITY,
            AccelUnit::MilliG => STANDARD_GRAVITY * 1e-3,
        }
    }

    /// The option value (`m/s2`, `g`, `mg`).
    pub fn name(self) -> &'static str {
        match self {
            AccelUnit::MetresPerSecondSquared => "m/s2",
            AccelUnit::G => "g",
            AccelUnit::MilliG => "mg",
        }
    }
}

impl fmt::Display for AccelUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for AccelUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "m/s2" | "m/s^2" | "mps2" => Ok(AccelUnit::MetresPerSecondSquared),
            "g" => Ok(AccelUnit::G),
            "mg" => Ok(AccelUnit::MilliG),
            other => Err(format!(
                "`{other}` is not an accelerometer unit (m/s2, g, mg)"
            )),
        }
    }
}

/// Three significant digits for a bound in a message (8.726646 -> 8.73).
pub(crate) fn fmt_sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.digits$}")
}
