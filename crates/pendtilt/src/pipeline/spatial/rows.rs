//! One 3-D log row into one sample: units, plausibility bounds, clips, the time step and
//! the truth, with the warnings naming each place.
use std::collections::VecDeque;

use pendtilt_core::spatial::SpatialSample;
use pendtilt_core::StepGate;

use super::setup::Setup;
use super::{MAX_ACCEL, MAX_RATE, MAX_WARNINGS, ROW_ISSUES_LISTED};
use crate::bank::spatial::Clips;
use crate::io::plateau::{NewLevel, PlateauWatch};
use crate::io::plausibility::FULL_SCALE_ROUNDING;
use crate::io::Log3dRecord;
use crate::sensors::Inputs;
use crate::sensors::Sensor;
use crate::units::Pair;

/// A value as the log wrote it: 1e308, not 309 digits.
fn written(x: f64) -> String {
    if x.abs() >= 1e6 {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// Turns records into samples: units, plausibility, the time step.
pub(super) struct RowInput<'a> {
    time_scale: f64,
    angle_scale: f64,
    file: &'a str,
    header: &'a [String],
    warnings: Vec<String>,
    more: u64,
    /// The sensors of the current row with an impossible reading.
    pub(super) implausible: Inputs,
    /// The rig's gyro full scale \[rad/s\], if given: the gyro's bound instead of
    /// [`MAX_RATE`] (a reading at it, to [`FULL_SCALE_ROUNDING`], is clipped but real).
    gyro_full_scale: Option<f64>,
    /// The clips found in the current row.
    pub(super) clipped: Clips,

    /// Clips of the gyro (when the rig gives no full scale) and of the accelerometer.
    gyro_clips: PlateauWatch<3>,
    accel_clips: PlateauWatch<3>,
    /// Truth cells (roll, pitch) beyond their range, read as missing.
    truth_refused: [u64; 2],
    /// Rows with a missing sensor cell, rows whose time does not increase, and the first
    /// [`ROW_ISSUES_LISTED`] of each said (apart from [`MAX_WARNINGS`], which they would
    /// fill before a restart is said).
    row_issues: [u64; 2],
    row_notes: Vec<String>,
    /// The truth (roll, pitch) against the encoder (phi_x, phi_y), for its unit.
    truth_fit: [Pair; 2],
}

/// The truth columns, their range in radians (MODEL.md 7: roll in -pi..pi, pitch in
/// -pi/2..pi/2) and the encoder that follows each below the pendulum's frequency.
const TRUTH: [(&str, f64, &str, &str); 2] = [
    ("roll", std::f64::consts::PI, "pi", "phi_x"),
    ("pitch", std::f64::consts::FRAC_PI_2, "pi/2", "phi_y"),
];

impl<'a> RowInput<'a> {
    pub(super) fn new(setup: &Setup, file: &'a str, header: &'a [String]) -> Self {
        Self {
            time_scale: setup.time_scale,
            angle_scale: setup.angle_scale,
            file,
            header,
            warnings: Vec::new(),
            more: 0,
            implausible: Inputs::default(),
            gyro_full_scale: setup.settings.ekf.gyro.checked_full_scale(),
            clipped: Clips::default(),

            gyro_clips: PlateauWatch::new(),
            accel_clips: PlateauWatch::new(),
            truth_refused: [0; 2],
            row_issues: [0; 2],
            row_notes: Vec::new(),
            truth_fit: [Pair::default(); 2],
        }
    }

    /// True angle `x` \[rad\] of truth column `k` (0 roll, 1 pitch) when within its range,
    /// else NaN (not scored), the first one per column warned with its place. A value that
    /// would be in range in degrees says that the column looks like degrees: its cells in
    /// range would be scored as radians.
    fn truth(&mut self, line: u64, k: usize, x: f64) -> f64 {
        let (name, bound, bound_name, _) = TRUTH[k];
        if x.is_nan() || x.abs() <= bound * (1.0 + 1e-9) {
            return x;
        }
        self.truth_refused[k] += 1;
        if self.truth_refused[k] > 1 {
            return f64::NAN;
        }
        let col = self.column(name);
        let degrees = if self.angle_scale == 1.0 && x.to_radians().abs() <= bound {
            format!(
                "; the column looks like degrees, and its cells within {bound_name} would be \
                 scored as radians: the inclination errors are not to be trusted; write \
                 roll and pitch in radians (--deg reads every angular column in degrees)"
            )
        } else {
            String::new()
        };
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {} rad is beyond {bound_name}, no {name} \
             angle (MODEL.md 7): read as missing, not scored{degrees}",
            self.file,
            written(x)
        ));
        f64::NAN
    }

    fn warn(&mut self, w: String) {
        if self.warnings.len() < MAX_WARNINGS {
            self.warnings.push(w);
        } else {
            self.more += 1;
        }
    }

    /// Says that the bank restarted `n` estimators at `line`.
    pub(super) fn restart_warning(&mut self, line: u64, r: crate::sensors::GapEnd, n: usize) {
        self.warn(format!(
            "{}:{line}: {} back after a gap of {:.3} s (longer than the restart gap {} s): \
             {n} estimators reading it restart from this row",
            self.file,
            r.sensors.spatial_names(),
            r.gap,
            crate::bank::planar::RESTART_GAP
        ));
    }

    /// Degrees found from the physics: below the pendulum's frequency the encoders follow
    /// the tilt (roll ~ phi_x, pitch ~ phi_y), so a truth 57x the encoder is in degrees
    /// (and 1/57 of it read with --deg in radians), however small the tilt.
    fn truth_unit(&self) -> Vec<String> {
        let deg = crate::units::DEG;
        let mut w = Vec::new();
        for (k, (name, _, _, phi)) in TRUTH.iter().enumerate() {
            // The encoder must move (units::MIN_MOTION) for the slope to say anything.
            let Some(f) = self.truth_fit[k].fit() else {
                continue;
            };
            let (slope, r) = (f.factor, f.correlation);
            let unit = crate::units::unit_factor(&f);
            let what = if unit == Some(deg) {
                format!("{slope:.1}x the encoder's {phi}: is `{name}` in degrees?")
            } else if unit == Some(1.0 / deg) {
                format!("1/{:.1} of the encoder's {phi}: was `{name}` read in degrees (--deg) but written in radians?", 1.0 / slope)
            } else {
                continue;
            };
            w.push(format!(
                "{}: {name} is {what} The inclination errors are not to be trusted: write roll \
                 and pitch in radians (--deg reads every angular column in degrees) (least \
                 squares over {} rows, r = {r:.2})",
                self.file,
                self.truth_fit[k].samples()
            ));
        }
        w
    }

    /// The 1-based column of `name` in the header (0 if absent), for warnings.
    fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .map_or(0, |p| p + 1)
    }

    /// `x` when plausible, else NaN and a warning naming its place.
    fn plausible(&mut self, line: u64, name: &str, x: f64, sensor: Sensor) -> f64 {
        let (bound, unit) = (sensor.spec().spatial_limit, sensor.spec().unit);
        if sensor == Sensor::Gyro {
            if let Some(fs) = self.gyro_full_scale {
                return self.beyond_full_scale(line, name, x, fs);
            }
        }
        if x.abs() <= bound || x.is_nan() {
            return x;
        }
        let col = self.column(name);
        // Degrees only where the reading in degrees would be possible (1e6 is impossible
        // either way: the hint would point the user the wrong way).
        let hint = if !sensor.spec().angular || x.to_radians().abs() > bound {
            ""
        } else {
            " (in degrees? give --deg)"
        };
        let x = written(x);
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {x} {unit} is beyond {bound} {unit}, \
             impossible: read as missing{hint}",
            self.file
        ));
        f64::NAN
    }

    /// Gyro reading `x` when within the rig's full scale `fs`, else NaN and a warning.
    fn beyond_full_scale(&mut self, line: u64, name: &str, x: f64, fs: f64) -> f64 {
        if x.abs() <= fs * (1.0 + FULL_SCALE_ROUNDING) || x.is_nan() {
            return x;
        }
        let col = self.column(name);
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {} rad/s exceeds the full scale {fs} rad/s \
             (rig [gyro] full_scale): read as missing",
            self.file,
            written(x)
        ));
        f64::NAN
    }

    /// The sample, with its time \[s\] and the truth (NaN when absent); `next_t` is the
    /// next row's time stamp (in the log's unit), if there is one.
    pub(super) fn sample(
        &mut self,
        r: &Log3dRecord,
        ahead: &VecDeque<Log3dRecord>,
        gate: &mut StepGate<f64>,
    ) -> (f64, SpatialSample<f64>, f64, f64) {
        let next_t = ahead.front().map(|n| n.t);
        let t = r.t * self.time_scale;
        let k = self.angle_scale;
        let line = r.line;
        // Each sensor's readings in SI, within its bounds, as the table gives them.
        let mut s = SpatialSample::after(f64::NAN);
        self.implausible = Inputs::NONE;
        for sensor in Sensor::ALL {
            let spec = sensor.spec();
            let scale = if spec.angular { k } else { 1.0 };
            let raw = r.reading(sensor);
            let names = spec.spatial_columns;
            for (i, (x, name)) in raw.iter().zip(names).enumerate() {
                let mut v = x * scale;
                if sensor == Sensor::Encoder {
                    v = hair_beyond_pi(v);
                }
                let v = self.plausible(line, name, v, sensor);
                s.reading_mut(sensor)[i] = v;
                // NaN out of a finite cell: the bound refused it.
                if !x.is_nan() && v.is_nan() {
                    self.implausible = self.implausible.with(sensor);
                }
            }
        }
        // A reading at the rig's full scale is its known clip, not one found here.
        let (k, fs) = (self.angle_scale, self.gyro_full_scale);
        let found = self.gyro_clips.clipped(r.gyro);
        self.clipped = Clips {
            gyro: core::array::from_fn(|i| {
                found[i] && fs.is_none_or(|fs| (r.gyro[i] * k).abs() < fs)
            }),
            accel: self.accel_clips.clipped(r.accel).contains(&true),
        };
        self.row_issues(r, t, gate);
        let dt = if self.lone_stamp(t, next_t.map(|n| n * self.time_scale), gate, line) {
            f64::NAN
        } else {
            gate.step(t)
        };
        s.dt = dt;
        s.speed = r.speed.unwrap_or(f64::NAN);
        let (roll, pitch) = (r.roll.map(|v| v * k), r.pitch.map(|v| v * k));
        let roll = roll.map_or(f64::NAN, |v| self.truth(line, 0, v));
        let pitch = pitch.map_or(f64::NAN, |v| self.truth(line, 1, v));
        self.truth_fit[0].add(s.phi[0], roll);
        self.truth_fit[1].add(s.phi[1], pitch);
        (t, s, roll, pitch)
    }

    /// Looks for clips in record `r`, read
    /// [`LOOK_AHEAD_ROWS`](crate::io::plateau::LOOK_AHEAD_ROWS) before it reaches the
    /// estimators. A reading at the rig's gyro full scale is a known clip (kept, flagged by
    /// the estimators); gyro clips at an unknown full scale, or below the rig's (a range
    /// smaller than the rig says), are found in the readings.
    pub(super) fn find_clips(&mut self, r: &Log3dRecord) {
        // An impossible reading (read as missing) is no clip level: a burst of them is a
        // run of identical readings that the finder would otherwise take for one.
        let possible = |x: f64, bound: f64| if x.abs() <= bound { x } else { f64::NAN };
        let k = self.angle_scale;
        let fs = self.gyro_full_scale;
        let gyro = r.gyro.map(|x| possible(x, fs.unwrap_or(MAX_RATE) / k));
        if let Some(f) = self.gyro_clips.observe(gyro) {
            let name = ["gyro_x", "gyro_y", "gyro_z"][f.axis];
            let x = f.reading * self.angle_scale;
            // A clip at the rig's full scale is the one the rig told.
            if fs.is_none_or(|fs| x.abs() < fs) {
                self.clip_warning(r.line, name, f, x, "rad/s", "[gyro] full_scale", fs);
            }
        }
        if let Some(f) = self
            .accel_clips
            .observe(r.accel.map(|x| possible(x, MAX_ACCEL)))
        {
            let name = ["ax", "ay", "az"][f.axis];
            self.clip_warning(r.line, name, f, f.reading, "m/s^2", "", None);
        }
    }

    /// Says that a run of identical readings `x` of column `name` is a clip, at an unknown
    /// full scale or below the rig's `told`.
    #[allow(clippy::too_many_arguments)]
    fn clip_warning(
        &mut self,
        line: u64,
        name: &str,
        f: NewLevel,
        x: f64,
        unit: &str,
        rig: &str,
        told: Option<f64>,
    ) {
        let col = self.column(name);
        let hint = if rig.is_empty() {
            String::new()
        } else {
            format!("; if it is the range of the sensor, give it as the rig's {rig}")
        };
        let what = match told {
            Some(fs) => format!(
                "a clip below the rig's {rig} {fs} {unit}: the sensor's range is smaller \
                 than the rig says"
            ),
            None => "a clip at an unknown full scale".to_string(),
        };
        self.warn(format!(
            "{}:{line}: column {col} (`{name}`): {x} {unit} on {} rows in a row up to here, \
             which a sensor with noise never writes: {what}; readings at +-{} {unit} are \
             clipped (flagged saturated){hint}",
            self.file,
            f.rows,
            x.abs()
        ));
    }

    /// Says what the reader flagged on row `r` (time `t` \[s\]): a missing sensor cell, a
    /// time that does not increase; as the planar reader says it (the rows are flagged
    /// either way, but `--flags` is not every user's first look).
    fn row_issues(&mut self, r: &Log3dRecord, t: f64, gate: &StepGate<f64>) {
        if r.issues.missing {
            let cells = [
                ("t", r.t),
                ("phi_x", r.phi[0]),
                ("phi_y", r.phi[1]),
                ("gyro_x", r.gyro[0]),
                ("gyro_y", r.gyro[1]),
                ("gyro_z", r.gyro[2]),
                ("ax", r.accel[0]),
                ("ay", r.accel[1]),
                ("az", r.accel[2]),
            ];
            let names: Vec<String> = cells
                .iter()
                .filter(|(_, v)| v.is_nan())
                .map(|(n, _)| format!("`{n}`"))
                .collect();
            self.row_issues[0] += 1;
            if self.row_issues[0] <= ROW_ISSUES_LISTED {
                self.row_notes.push(format!(
                    "{}:{}: {} empty, nan, infinite or absent: read as missing, the \
                     estimators reading it hold and flag the sample",
                    self.file,
                    r.line,
                    names.join(", ")
                ));
            }
        }
        if let (true, Some(last)) = (r.issues.time_not_increasing, gate.last()) {
            // After a lone stamp (held, said) the row is behind it but not behind `last`.
            if t.is_finite() && t <= last {
                let what = if t == last { "repeated" } else { "goes back" };
                self.row_issues[1] += 1;
                if self.row_issues[1] > ROW_ISSUES_LISTED {
                    return;
                }
                self.row_notes.push(format!(
                    "{}:{}: column {} (`t`): time {what} ({last} then {t} s): the row is kept, \
                     the estimators holding their estimate, flagged bad_time_step, until the \
                     time passes {last} s again",
                    self.file,
                    r.line,
                    self.column("t")
                ));
            }
        }
    }

    /// Whether `t` is a lone glitched stamp: after the next row's, which itself follows the
    /// last accepted one (so the next row, not this one, continues the clock).
    fn lone_stamp(&mut self, t: f64, next: Option<f64>, gate: &StepGate<f64>, line: u64) -> bool {
        let (Some(next), Some(last)) = (next, gate.last()) else {
            return false;
        };
        let lone = t > next && next > last;
        if lone {
            self.warn(format!(
                "{}:{line}: column 1 (`t`): {t} s is after the next row's {next} s: a lone \
                 bad time stamp, this row is held (flagged bad_time_step)",
                self.file
            ));
        }
        lone
    }

    pub(super) fn warnings(&self) -> Vec<String> {
        let mut w = self.warnings.clone();
        w.extend(self.row_notes.iter().cloned());
        for (n, what) in self.row_issues.iter().zip([
            "with a missing sensor cell (flagged sample_missing)",
            "whose time does not increase (flagged bad_time_step)",
        ]) {
            if *n > ROW_ISSUES_LISTED {
                w.push(format!(
                    "{}: {n} rows {what}, the first {ROW_ISSUES_LISTED} listed",
                    self.file
                ));
            }
        }
        for (k, (name, _, bound_name, _)) in TRUTH.iter().enumerate() {
            if self.truth_refused[k] > 1 {
                w.push(format!(
                    "{}: {} cells of `{name}` beyond {bound_name} read as missing, not scored",
                    self.file, self.truth_refused[k]
                ));
            }
        }
        w.extend(self.truth_unit());
        if self.more > 0 {
            w.push(format!(
                "{} more warnings (impossible readings, restarts, bad time stamps)",
                self.more
            ));
        }
        w
    }
}

/// How far beyond +-pi \[rad\] an encoder reading is taken for +-pi as a logger rounded
/// it (`-3.1416` is 7e-6 beyond; `3.142`, 4e-4): such a reading is wrapped into (-pi, pi],
/// not read as missing.
const PI_ROUNDING: f64 = 1e-3;

/// An encoder angle a hair beyond +-pi (within [`PI_ROUNDING`]) wrapped into (-pi, pi];
/// any other value as it is.
fn hair_beyond_pi(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if x.abs() > PI && x.abs() <= PI + PI_ROUNDING {
        x - x.signum() * TAU
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// -pi printed to four decimals is wrapped, not dropped; a reading well beyond stays
    /// beyond (the plausibility check reads it as missing and says so).
    #[test]
    fn an_encoder_a_hair_beyond_pi_is_wrapped() {
        let pi = std::f64::consts::PI;
        // As a logger prints -pi and pi rounded.
        let (four, three): (f64, f64) = ("-3.1416".parse().unwrap(), "3.142".parse().unwrap());
        let w = hair_beyond_pi(four);
        assert!(w > pi - 1e-4 && w <= pi, "{w}");
        let w = hair_beyond_pi(three);
        assert!(w < -pi + 1e-3 && w > -pi, "{w}");
        assert_eq!(hair_beyond_pi(pi), pi);
        assert_eq!(hair_beyond_pi(0.5), 0.5);
        assert_eq!(hair_beyond_pi(pi + 0.1), pi + 0.1);
        assert!(hair_beyond_pi(f64::NAN).is_nan());
    }
}
