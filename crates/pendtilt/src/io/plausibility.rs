//! Plausibility at the edge: which readings no sensor can give (beyond its full scale, or
//! physically impossible), and which time steps no logger would write in seconds. The log
//! reader applies these once per cell, before any estimator sees the value, so every
//! estimator (the paper's, the Kalman filters and the peers) gets the same missing (NaN)
//! value for an impossible reading instead of each reacting to it its own way.
use std::fmt;
use std::str::FromStr;

pub(crate) use crate::units::fmt_sig;
pub use crate::units::{AccelUnit, STANDARD_GRAVITY};

use super::columns::Column;
use crate::sensors::Sensor;

/// Gyro bound \[rad/s\] when the rig file gives no `[gyro] full_scale`: the sensor
/// table's (100 rad/s, 5730 deg/s, beyond any MEMS rate gyro's full scale).
pub const DEFAULT_GYRO_LIMIT: f64 = Sensor::Gyro.spec().spatial_limit;
/// Accelerometer bound \[m/s^2\] when the rig file gives no `[accel] full_scale`: the
/// sensor table's (500 m/s^2, 51 g, beyond the 16 g of common MEMS accelerometers).
pub const DEFAULT_ACCEL_LIMIT: f64 = Sensor::Accel.spec().spatial_limit;
/// A reading beyond its full scale by less than this fraction is rounding (a value written
/// with fewer digits, or converted from degrees) and counts as at full scale: clipped but
/// real, flagged `saturated` by the estimators as before.
pub const FULL_SCALE_ROUNDING: f64 = 1e-6;
/// The slowest plausible sample rate \[Hz\]: below it the log cannot follow a pendulum
/// (natural frequencies of 1 to 5 Hz), so a median step longer than 0.1 s means the time
/// is not in seconds.
pub const MIN_RATE_HZ: f64 = 10.0;
/// The fastest plausible sample rate \[Hz\] (a median step below 1 us).
pub const MAX_RATE_HZ: f64 = 1e6;

/// The bounds a reading must stay within; beyond them it is read as missing and flagged.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SensorLimits {
    /// The gyro's full scale \[rad/s\] (rig `[gyro] full_scale`); `None`: unknown, the
    /// bound is [`DEFAULT_GYRO_LIMIT`].
    pub gyro_full_scale: Option<f64>,
    /// The accelerometer's full scale \[m/s^2\] per axis (rig `[accel] full_scale`);
    /// `None`: unknown, the bound is [`DEFAULT_ACCEL_LIMIT`].
    pub accel_full_scale: Option<f64>,
}

impl SensorLimits {
    /// The bounds of a rig: its sensors' full scales (`[gyro]`, `[accel]`), or the
    /// default physical bounds where they are unset.
    pub fn of_rig(rig: &crate::config::RigConfig) -> Self {
        Self {
            gyro_full_scale: rig.gyro.full_scale,
            accel_full_scale: rig.accel.full_scale,
        }
    }

    /// Why `value` (SI, finite) in `column` is impossible, or `None` when it is plausible.
    /// `raw` is the value as written in the file (before a `--deg` conversion).
    pub fn check(&self, column: Column, value: f64, raw: f64) -> Option<String> {
        let (limit, what, known) = match column {
            Column::Gyro => match self.gyro_full_scale {
                Some(fs) => (fs, "the full scale", "rig [gyro] full_scale"),
                None => (
                    DEFAULT_GYRO_LIMIT,
                    "the physical bound",
                    "no [gyro] full_scale in the rig",
                ),
            },
            Column::Ax | Column::Ay => match self.accel_full_scale {
                Some(fs) => (fs, "the full scale", "rig [accel] full_scale"),
                None => (
                    DEFAULT_ACCEL_LIMIT,
                    "the physical bound",
                    "no [accel] full_scale in the rig",
                ),
            },
            Column::Phi => {
                let limit = pendtilt_core::estimators::PHI_LIMIT;
                return (value.abs() >= limit).then(|| {
                    format!(
                        "phi {} rad is physically impossible (beyond {limit} rad, \
                         {} turns): read as missing for every estimator, the row is \
                         flagged implausible",
                        fmt_value(raw),
                        (limit / std::f64::consts::TAU).round()
                    )
                });
            }
            // The truth is no reading: beyond the encoder's bound it is no angle in
            // radians nor in degrees, and scored it would be the whole summary.
            Column::Theta => {
                let limit = pendtilt_core::estimators::PHI_LIMIT;
                return (value.abs() >= limit).then(|| {
                    format!(
                        "theta {} rad is no tilt (beyond {limit} rad, {} turns): the true \
                         angle is read as missing, the row not scored",
                        fmt_value(raw),
                        (limit / std::f64::consts::TAU).round()
                    )
                });
            }
            Column::T => return None,
        };
        if value.abs() <= limit * (1.0 + FULL_SCALE_ROUNDING) {
            return None;
        }
        let unit = column.unit();
        // The number beside the unit is in that unit: converted (`--accel-unit g`,
        // `--deg`), it is the SI value, and the cell as written follows it.
        let shown = if raw == value {
            format!("{} {unit}", fmt_value(raw))
        } else {
            format!("{} {unit} ({} as written)", fmt_sig(value), fmt_value(raw))
        };
        Some(format!(
            "{column} {shown} exceeds {what} {} {unit} ({known}): read as missing for \
             every estimator, the row is flagged implausible",
            fmt_sig(limit)
        ))
    }
}

/// A value as a reader would write it: `1e6`, `-1e308`, `0.25`.
fn fmt_value(x: f64) -> String {
    let a = x.abs();
    if a >= 1e6 || (a < 1e-3 && a > 0.0) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The unit of the time column (`--time-unit`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeUnit {
    /// Seconds (the contract's unit).
    S,
    /// Milliseconds.
    Ms,
    /// Microseconds.
    Us,
    /// Nanoseconds.
    Ns,
}

impl TimeUnit {
    /// Every unit, largest first.
    pub const ALL: [TimeUnit; 4] = [TimeUnit::S, TimeUnit::Ms, TimeUnit::Us, TimeUnit::Ns];

    /// Seconds per unit.
    pub fn seconds(self) -> f64 {
        match self {
            TimeUnit::S => 1.0,
            TimeUnit::Ms => 1e-3,
            TimeUnit::Us => 1e-6,
            TimeUnit::Ns => 1e-9,
        }
    }

    /// The option value (`s`, `ms`, `us`, `ns`).
    pub fn name(self) -> &'static str {
        match self {
            TimeUnit::S => "s",
            TimeUnit::Ms => "ms",
            TimeUnit::Us => "us",
            TimeUnit::Ns => "ns",
        }
    }
}

impl fmt::Display for TimeUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for TimeUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "s" => Ok(TimeUnit::S),
            "ms" => Ok(TimeUnit::Ms),
            "us" | "µs" => Ok(TimeUnit::Us),
            "ns" => Ok(TimeUnit::Ns),
            other => Err(format!("`{other}` is not a time unit (s, ms, us, ns)")),
        }
    }
}

/// Why a median time step `dt` \[s\] (time read as seconds) is not a plausible sensor rate,
/// with the fix; `None` when it is.
pub fn implausible_step(dt: f64) -> Option<String> {
    let rate = 1.0 / dt;
    if (MIN_RATE_HZ..=MAX_RATE_HZ).contains(&rate) {
        return None;
    }
    let fix = TimeUnit::ALL.into_iter().skip(1).find(|u| {
        let r = 1.0 / (dt * u.seconds());
        (MIN_RATE_HZ..=MAX_RATE_HZ).contains(&r)
    });
    let mut msg = format!(
        "the median time step is {dt} s, a rate of {} Hz, outside the plausible \
         {MIN_RATE_HZ} Hz to {} MHz of a sensor log",
        fmt_sig(rate),
        MAX_RATE_HZ / 1e6
    );
    match fix {
        Some(u) => msg.push_str(&format!(
            "; if `t` is in {}, read it with --time-unit {} ({} Hz)",
            match u {
                TimeUnit::Ms => "milliseconds",
                TimeUnit::Us => "microseconds",
                _ => "nanoseconds",
            },
            u.name(),
            fmt_sig(1.0 / (dt * u.seconds()))
        )),
        None => msg.push_str("; `t` must be in seconds"),
    }
    msg.push_str(" (--time-unit s reads it as seconds without this check)");
    Some(msg)
}

/// The fastest plausible rate \[Hz\] of a log whose time unit the user gave: the fastest
/// MEMS IMUs sample at 32 kHz. Tighter than [`MAX_RATE_HZ`] because a 1 kHz log in seconds
/// read with `--time-unit ms` comes out at exactly 1 MHz.
pub const MAX_GIVEN_RATE_HZ: f64 = 1e5;

/// Why a median time step of `raw_dt` in the file's numbers, read in the unit the user
/// `given`, is not a plausible sensor rate, with the unit that fits; `None` when it is.
/// `--time-unit s` is the way to read any rate as seconds, and is never questioned.
pub fn implausible_given_unit(raw_dt: f64, given: TimeUnit) -> Option<String> {
    let plausible = |r: f64| (MIN_RATE_HZ..=MAX_GIVEN_RATE_HZ).contains(&r);
    let rate = 1.0 / (raw_dt * given.seconds());
    let positive = raw_dt > 0.0 && raw_dt.is_finite();
    if given == TimeUnit::S || !positive || plausible(rate) {
        return None;
    }
    let mut msg = format!(
        "read with --time-unit {given}, the median time step is {} s, a rate of {} Hz, \
         outside the plausible {MIN_RATE_HZ} Hz to {} kHz of a sensor log",
        {
            let dt = raw_dt * given.seconds();
            if dt < 1e-3 {
                format!("{dt:.2e}")
            } else {
                fmt_sig(dt)
            }
        },
        fmt_sig(rate),
        MAX_GIVEN_RATE_HZ / 1e3
    );
    let fix = TimeUnit::ALL
        .into_iter()
        .find(|u| plausible(1.0 / (raw_dt * u.seconds())));
    match fix {
        Some(TimeUnit::S) => msg.push_str(&format!(
            "; read as seconds it is {} Hz: drop --time-unit {given}",
            fmt_sig(1.0 / raw_dt)
        )),
        Some(u) => msg.push_str(&format!(
            "; read as {u} it is {} Hz: give --time-unit {u}",
            fmt_sig(1.0 / (raw_dt * u.seconds()))
        )),
        None => msg.push_str("; no time unit makes it one (--time-unit s reads it as seconds)"),
    }
    Some(msg)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 kHz log in seconds read with `--time-unit ms` (1 MHz) or `us` (1 GHz) is
    /// refused with the fix; the right unit, and `s` whatever the rate, pass.
    #[test]
    fn a_time_unit_given_is_checked_too() {
        let ms = implausible_given_unit(1e-3, TimeUnit::Ms).unwrap();
        assert!(
            ms.starts_with(
                "read with --time-unit ms, the median time step is 1.00e-6 s, a rate of \
                 1000000 Hz, outside the plausible 10 Hz to 100 kHz of a sensor log"
            ),
            "{ms}"
        );
        assert!(
            ms.ends_with("read as seconds it is 1000 Hz: drop --time-unit ms"),
            "{ms}"
        );
        let us = implausible_given_unit(1e-3, TimeUnit::Us).unwrap();
        assert!(us.contains("drop --time-unit us"), "{us}");
        // Microseconds read as milliseconds: 1 kHz stamps 1000 apart.
        let wrong = implausible_given_unit(1000.0, TimeUnit::Ms).unwrap();
        assert!(
            wrong.ends_with("read as us it is 1000 Hz: give --time-unit us"),
            "{wrong}"
        );
        assert!(implausible_given_unit(1.0, TimeUnit::Ms).is_none());
        assert!(implausible_given_unit(1000.0, TimeUnit::Us).is_none());
        assert!(implausible_given_unit(1e-7, TimeUnit::S).is_none());
    }

    #[test]
    fn at_full_scale_is_plausible_beyond_it_is_not() {
        let l = SensorLimits {
            gyro_full_scale: Some(8.726646259971648),
            accel_full_scale: Some(78.4532),
        };
        assert!(l
            .check(Column::Gyro, 8.726646259971648, 8.726646259971648)
            .is_none());
        assert!(l
            .check(Column::Gyro, -8.7266462599716, -8.7266462599716)
            .is_none());
        let m = l.check(Column::Gyro, 1e6, 1e6).unwrap();
        assert!(
            m.starts_with(
                "gyro 1e6 rad/s exceeds the full scale 8.73 rad/s (rig [gyro] full_scale): \
                 read as missing for every estimator"
            ),
            "{m}"
        );
        assert!(!m.contains("--deg"), "{m}");
        // One cell gets no unit hint (a column in deg/s is found from the physics).
        assert!(!l
            .check(Column::Gyro, 400.0, 400.0)
            .unwrap()
            .contains("--deg"));
        assert!(l
            .check(Column::Ax, -1e308, -1e308)
            .unwrap()
            .contains("78.5 m/s^2"));
        assert!(l.check(Column::Ay, 78.4532, 78.4532).is_none());
        // Read with `--accel-unit g`: 13.65 g is 133.9 m/s^2, and the message says so (it
        // printed "13.65 m/s^2 exceeds 78.5 m/s^2").
        let m = l.check(Column::Ay, 13.65 * 9.80665, 13.65).unwrap();
        assert!(
            m.starts_with("ay 134 m/s^2 (13.65 as written) exceeds the full scale 78.5 m/s^2"),
            "{m}"
        );
        let d = SensorLimits::default();
        assert!(d.check(Column::Gyro, 99.0, 99.0).is_none());
        assert!(d
            .check(Column::Gyro, 101.0, 101.0)
            .unwrap()
            .contains("physical bound 100"));
        assert!(d
            .check(Column::Phi, 2e4, 2e4)
            .unwrap()
            .contains("impossible"));
        // The truth: beyond the encoder's bound no angle (not scored); 45 may be degrees.
        assert!(d
            .check(Column::Theta, 1e300, 1e300)
            .unwrap()
            .contains("not scored"));
        assert!(d.check(Column::Theta, 45.0, 45.0).is_none());
    }

    #[test]
    fn time_steps_in_ms_and_us_are_named_with_the_fix() {
        assert!(implausible_step(1e-3).is_none());
        assert!(implausible_step(0.05).is_none());
        let ms = implausible_step(1.0).unwrap();
        assert!(ms.contains("--time-unit ms (1000 Hz)"), "{ms}");
        let us = implausible_step(1000.0).unwrap();
        assert!(us.contains("--time-unit us (1000 Hz)"), "{us}");
        let ns = implausible_step(1e6).unwrap();
        assert!(ns.contains("--time-unit ns"), "{ns}");
        let tiny = implausible_step(1e-8).unwrap();
        assert!(tiny.contains("must be in seconds"), "{tiny}");
    }
}
