//! The accelerometer's unit from the median magnitude of its readings against gravity.
use super::*;

/// The accelerometer's median magnitude over gravity within these bounds is in m/s^2:
/// a body's specific force is gravity's most of the time (the vibrating scooter's median
/// is 1.03 g; a car's turns and braking, a ship's heave stay well inside).
pub const ACCEL_MAGNITUDE_BAND: [f64; 2] = [0.5, 2.0];
/// The least readings for a verdict on the accelerometer's unit.
pub const MIN_ACCEL_READINGS: u64 = 100;
/// Bins of the magnitude's log10 per decade, and the decades kept (1e-4 to 1e6 m/s^2).
const ACCEL_BINS_PER_DECADE: f64 = 100.0;
const ACCEL_DECADES: [f64; 2] = [-4.0, 6.0];

/// The median magnitude of the accelerometer's readings over a log, against gravity: a
/// column in g (0.1 of what m/s^2 gives) or mg (102x) is found, named, and given its fix.
/// The median of a histogram of log10 of the magnitude (1 % bins), so one absurd reading
/// does not move it and no row is kept.
#[derive(Debug, Clone)]
pub struct AccelMagnitude {
    bins: Vec<u64>,
    n: u64,
}

impl Default for AccelMagnitude {
    fn default() -> Self {
        let n = ((ACCEL_DECADES[1] - ACCEL_DECADES[0]) * ACCEL_BINS_PER_DECADE) as usize;
        Self {
            bins: vec![0; n],
            n: 0,
        }
    }
}

impl AccelMagnitude {
    /// The magnitudes of 3-axis readings \[m/s^2 as read, after `--accel-unit`\] (each as
    /// [`Self::add`] takes it).
    pub fn of_vectors<'a>(readings: impl IntoIterator<Item = &'a [f64; 3]>) -> Self {
        let mut m = Self::default();
        for a in readings {
            m.add(a.iter().map(|v| v * v).sum::<f64>().sqrt());
        }
        m
    }

    /// One reading's magnitude \[m/s^2 as read, after `--accel-unit`\]; zero, non-finite
    /// or beyond the histogram is left out (a missing reading, a logger's zero fill).
    pub fn add(&mut self, magnitude: f64) {
        if !(magnitude.is_finite() && magnitude > 0.0) {
            return;
        }
        let x = (magnitude.log10() - ACCEL_DECADES[0]) * ACCEL_BINS_PER_DECADE;
        if x >= 0.0 && (x as usize) < self.bins.len() {
            self.bins[x as usize] += 1;
            self.n += 1;
        }
    }

    /// The readings counted.
    pub fn readings(&self) -> u64 {
        self.n
    }

    /// The median magnitude \[m/s^2\] (to 1 %), once there are readings.
    pub fn median(&self) -> Option<f64> {
        if self.n == 0 {
            return None;
        }
        let mut seen = 0;
        for (i, c) in self.bins.iter().enumerate() {
            seen += c;
            if 2 * seen >= self.n {
                let log = ACCEL_DECADES[0] + (i as f64 + 0.5) / ACCEL_BINS_PER_DECADE;
                return Some(10f64.powf(log));
            }
        }
        None
    }

    /// A finding when the median is not gravity's (outside [`ACCEL_MAGNITUDE_BAND`] of
    /// [`crate::units::STANDARD_GRAVITY`]), for the accelerometer `columns` read with `given`
    /// (`--accel-unit`, `None`: m/s^2): the unit that explains it, or the question. `None`
    /// for a log that is right or has fewer than [`MIN_ACCEL_READINGS`] readings.
    pub fn finding(
        &self,
        columns: &'static str,
        given: Option<crate::units::AccelUnit>,
    ) -> Option<Finding> {
        use crate::units::{AccelUnit, STANDARD_GRAVITY};
        if self.n < MIN_ACCEL_READINGS {
            return None;
        }
        let median = self.median()?;
        let ratio = median / STANDARD_GRAVITY;
        let inside = |r: f64| (ACCEL_MAGNITUDE_BAND[0]..=ACCEL_MAGNITUDE_BAND[1]).contains(&r);
        if inside(ratio) {
            return None;
        }
        let given = given.unwrap_or(AccelUnit::MetresPerSecondSquared);
        // The unit the columns are in if the median is gravity's.
        let raw = median / given.metres_per_second_squared();
        let unit = AccelUnit::ALL
            .into_iter()
            .find(|u| inside(raw * u.metres_per_second_squared() / STANDARD_GRAVITY));
        let read = if given == AccelUnit::MetresPerSecondSquared {
            String::new()
        } else {
            format!(" (read with --accel-unit {given})")
        };
        let fix = match unit {
            Some(AccelUnit::MetresPerSecondSquared) => {
                format!("is it already in m/s^2? leave out --accel-unit {given}")
            }
            Some(u) => format!("is the accelerometer in {u}? read it with --accel-unit {u}"),
            None => "is the accelerometer in m/s^2 (MODEL.md section 5)? g and mg are read \
                     with --accel-unit g or mg"
                .to_string(),
        };
        let message = format!(
            "{columns}: the specific force's median magnitude is {} m/s^2{read}, where \
             gravity alone gives {STANDARD_GRAVITY} m/s^2 ({} g): {fix} (median over \
             {} readings; a body's specific force is gravity's most of the time)",
            crate::units::fmt_sig(median),
            crate::units::fmt_sig(ratio),
            self.n
        );
        Some(Finding {
            column: columns,
            comparison: Comparison::AccelGravity,
            fit: Fit {
                factor: ratio,
                correlation: f64::NAN,
                samples: self.n,
            },
            message,
        })
    }
}
