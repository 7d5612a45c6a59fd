//! Unit checks from the physics rather than from magnitudes, and settings checked against
//! the log's rate.
//!
//! **Degrees read as radians.** Below the pendulum's natural frequency the pendulum hangs
//! along the specific force, so the encoder angle follows the tilt: `phi ~ theta`, hence
//! `phi' ~ theta' = gyro`, and `phi ~ atan2(ax, ay)` (the accelerometer angle, whose
//! units nothing can change). [`UnitCheck`] low-passes every signal well below f_n (two
//! second-order Butterworth sections at f_n / 4, started at rest on the mean of the first
//! 50 ms and read from one period of their cutoff on), fits each pair by least squares with
//! an intercept (a gyro bias, an encoder zero) over the whole log, and reports a pair whose
//! factor is 180/pi (57.3) or pi/180 with a good fit: that is a column in degrees, named
//! with the factor found. A correct log gives factors near 1 whatever its motion, and a
//! log without motion (less than [`MIN_MOTION`] in the reference) gives no fit; neither
//! reports anything.
//!
//! **The accelerometer in g or mg read as m/s^2.** Whatever a body does, the specific
//! force an accelerometer reads is gravity's most of the time: its median magnitude is
//! within a factor 2 of g on any vehicle, rig or ship. [`AccelMagnitude`] keeps the median
//! of the readings' magnitude over the whole log (a histogram of its logarithm, no row
//! kept) and reports one that g (or mg) explains, with the fix (`--accel-unit`).
//!
//! **Settings against the rate** are the bank's to check
//! ([`crate::bank::planar::check_settings_against_rate`], with [`MIN_DIFF_CUTOFF_TIMES_NATURAL`]).
use pendtilt_core::estimators::equations::accel_angle;
use pendtilt_core::filters::biquad::LowPass2;
use pendtilt_core::Sample;

use crate::sensors::{Inputs, Sensor};

/// 180 / pi: a column in degrees read as radians is this many times too large.
pub const DEG: f64 = 180.0 / std::f64::consts::PI;
/// A factor within this ratio of [`DEG`] (or of 1 / [`DEG`]) counts as a degree mistake.
pub const FACTOR_TOLERANCE: f64 = 1.5;
/// The least correlation of a pair for its factor to be believed.
pub const MIN_CORRELATION: f64 = 0.8;
/// The least duration of usable samples \[s\] for a verdict.
pub const MIN_DURATION: f64 = 1.0;
/// The low-pass of the comparison, as a fraction of the natural frequency.
pub const CUTOFF_TIMES_NATURAL: f64 = 0.25;
/// A reading this large (or NaN) is absurd in any unit and not used by [`UnitCheck`].
pub const ABSURD: f64 = 1e5;
/// How long the first rows after a (re)start are averaged \[s\] for the filters to start
/// at rest on their mean.
pub const WARM_START: f64 = 0.05;
/// The least standard deviation of a pair's reference (the accelerometer's angle, the
/// encoder's, or their rates) for its factor to be believed: 0.5 deg, or 0.5 deg/s (the
/// issue's small motion, 2.3 deg and 8 deg/s, is well above it).
pub const MIN_MOTION: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// How long after a (re)start the comparison waits, in periods of its cutoff: 1, 1.8 s for
/// the default pendulum. With the filters started on the mean of the first 50 ms this is
/// enough: over 126 correct logs (six scenarios, 2-12 s, with and without sensor noise) no
/// finding, and every 4 s log with phi or the gyro in degrees, or read with `--deg` while
/// in radians, is found (with 2 periods, and the filters started on one reading, the 4 s
/// logs' gyro in deg/s and `--deg` on radians went unsaid: 35 of 45 found).
pub const SETTLE_PERIODS: f64 = 1.0;
/// `u`, or 0 for a missing (non-finite) reading.
fn or0(u: f64) -> f64 {
    if u.is_finite() {
        u
    } else {
        0.0
    }
}
/// A differentiator cutoff below this multiple of the natural frequency is refused.
pub const MIN_DIFF_CUTOFF_TIMES_NATURAL: f64 = 0.5;

mod accel;
mod fit;
mod scale;
pub use accel::*;
pub use fit::*;
pub(crate) use scale::fmt_sig;
pub use scale::{AccelUnit, STANDARD_GRAVITY};

/// Which pair a finding comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Comparison {
    /// The gyro against the encoder's derivative.
    GyroEncoderRate,
    /// The encoder against the accelerometer angle.
    EncoderAccel,
    /// The gyro against the accelerometer angle's derivative.
    GyroAccelRate,
    /// The true angle against the encoder.
    TruthEncoder,
    /// The true angle against the accelerometer angle.
    TruthAccel,
    /// The accelerometer's median magnitude against gravity ([`AccelMagnitude`]; its
    /// [`Fit::factor`] is that ratio, its correlation NaN: no regression).
    AccelGravity,
}

/// A column found in degrees (or converted twice).
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    /// The column (`phi`, `gyro`, `theta`), or the accelerometer's (`ax, ay`).
    pub column: &'static str,
    /// The pair it was found with.
    pub comparison: Comparison,
    /// The fit.
    pub fit: Fit,
    /// One sentence with the factor and the fix.
    pub message: String,
}

/// The degree detector: feed it every row ([`UnitCheck::add`]), then ask
/// [`UnitCheck::findings`].
#[derive(Debug, Clone)]
pub struct UnitCheck {
    inputs: Inputs,
    // phi, gyro, accel angle, theta
    smooth: [Smooth; 4],
    prev: Option<(f64, f64)>,
    /// Time since the first sample after the last restart [s].
    since_start: f64,
    settle: f64,
    pairs: [Pair; 5],
    /// The encoder's rate on the gyro and its second derivative ([`Lever`]).
    lever: Option<Lever>,
    /// The last two low-passed gyro readings, for its second derivative.
    gyro_before: Option<(f64, f64)>,
    duration: f64,
    /// The first rows after a (re)start, until [`WARM_START`] of them are in: the filters
    /// start at rest on their mean.
    warm: Vec<(Sample<f64>, f64)>,
    /// The accelerometer's magnitude against gravity, and the unit it was read in.
    accel: AccelMagnitude,
    accel_unit: Option<AccelUnit>,
}

impl UnitCheck {
    /// A check for a log with `inputs`, for a pendulum of natural frequency `f_n` \[Hz\]
    /// (one axis of a 3-D pendulum: each has its own).
    pub fn with_natural_frequency(f_n: f64, inputs: Inputs) -> Self {
        let cutoff = if f_n.is_finite() && f_n > 0.0 {
            CUTOFF_TIMES_NATURAL * f_n
        } else {
            0.5
        };
        Self {
            inputs,
            smooth: [Smooth::new(cutoff); 4],
            prev: None,
            since_start: f64::NAN,
            settle: SETTLE_PERIODS / cutoff,
            pairs: [Pair::default(); 5],
            lever: None,
            gyro_before: None,
            duration: 0.0,
            warm: Vec::new(),
            accel: AccelMagnitude::default(),
            accel_unit: None,
        }
    }

    /// The check of a log whose accelerometer was read with `--accel-unit unit`, so that a
    /// finding names what was given.
    pub fn with_accel_unit(mut self, unit: Option<AccelUnit>) -> Self {
        self.accel_unit = unit;
        self
    }

    fn restart(&mut self) {
        for s in &mut self.smooth {
            s.reset();
        }
        self.prev = None;
        self.gyro_before = None;
        self.warm.clear();
    }

    /// Adds one row (`theta`: the true angle, `None` or NaN when absent).
    pub fn add(&mut self, s: &Sample<f64>, theta: Option<f64>) {
        if self.inputs.has(Sensor::Accel) {
            self.accel.add(s.ax.hypot(s.ay));
        }
        let th = theta.unwrap_or(f64::NAN);
        // Readings beyond the sensors' bounds still count here (a gyro in deg/s is beyond
        // a rad/s full scale), unless absurd in any unit.
        let ok = |v: f64| v.abs() < ABSURD;
        let usable = s.dt.is_finite()
            && (!self.inputs.has(Sensor::Encoder) || ok(s.phi))
            && (!self.inputs.has(Sensor::Gyro) || ok(s.gyro))
            && (!self.inputs.has(Sensor::Accel) || (ok(s.ax) && ok(s.ay)));
        let dt = self.prev.map_or(f64::NAN, |_| s.dt);
        // A missing reading or a gap starts the filters again.
        if !usable || (self.prev.is_some() && !(dt > 0.0 && dt < 0.1)) {
            self.restart();
            if !usable {
                return;
            }
        }
        if self.prev.is_none() {
            // Starting: the filters start at rest on the mean of the first readings, not on
            // one (a vibrating reading would take them seconds to forget).
            if !(self.warm.is_empty() || s.dt > 0.0 && s.dt < 0.1) {
                self.warm.clear();
            }
            self.warm.push((*s, th));
            let span: f64 = self.warm.iter().skip(1).map(|(r, _)| r.dt).sum();
            if span < WARM_START {
                return;
            }
            let n = self.warm.len() as f64;
            let mut start = [0.0; 4];
            for (r, t) in &self.warm {
                let row = [or0(r.phi), or0(r.gyro), self.accel_angle(r), or0(*t)];
                for (m, v) in start.iter_mut().zip(row) {
                    *m += v / n;
                }
            }
            for (f, u) in self.smooth.iter_mut().zip(start) {
                f.update(u, 1e-3);
            }
            self.prev = Some((start[0], start[2]));
            self.since_start = 0.0;
            for (r, t) in std::mem::take(&mut self.warm) {
                self.step(&r, t);
            }
            return;
        }
        self.step(s, th);
    }

    fn accel_angle(&self, s: &Sample<f64>) -> f64 {
        if self.inputs.has(Sensor::Accel) {
            accel_angle(s.ax, s.ay)
        } else {
            0.0
        }
    }

    /// One row through the filters, once they have started.
    fn step(&mut self, s: &Sample<f64>, th: f64) {
        let step = if s.dt > 0.0 && s.dt < 0.1 { s.dt } else { 1e-3 };
        let alpha = self.accel_angle(s);
        let phi = self.smooth[0].update(or0(s.phi), step);
        let gyro = self.smooth[1].update(or0(s.gyro), step);
        let acc = self.smooth[2].update(alpha, step);
        let truth = self.smooth[3].update(or0(th), step);
        let before = self
            .gyro_before
            .replace((self.gyro_before.map_or(gyro, |b| b.1), gyro));
        let Some((last_phi, last_acc)) = self.prev.replace((phi, acc)) else {
            return;
        };
        self.since_start += step;
        if self.since_start < self.settle {
            return;
        }
        self.duration += step;
        let dphi = (phi - last_phi) / step;
        let dacc = (acc - last_acc) / step;
        let (p, g, a) = (
            self.inputs.has(Sensor::Encoder),
            self.inputs.has(Sensor::Gyro),
            self.inputs.has(Sensor::Accel),
        );
        if p && g {
            self.pairs[Comparison::GyroEncoderRate as usize].add(dphi, gyro);
            // gyro'' at the previous row, against the rate between it and this one.
            if let (Some(lever), Some((g2, g1))) = (&mut self.lever, before) {
                let curvature = (gyro - 2.0 * g1 + g2) / (step * step);
                lever.add(0.5 * (gyro + g1), curvature, dphi);
            }
        }
        if p && a {
            self.pairs[Comparison::EncoderAccel as usize].add(acc, phi);
        }
        if g && a {
            self.pairs[Comparison::GyroAccelRate as usize].add(dacc, gyro);
        }
        if th.is_finite() {
            if p {
                self.pairs[Comparison::TruthEncoder as usize].add(phi, truth);
            }
            if a {
                self.pairs[Comparison::TruthAccel as usize].add(acc, truth);
            }
        }
    }

    /// The fit of one comparison, if it had samples with motion.
    pub fn fit(&self, c: Comparison) -> Option<Fit> {
        // No pair for the accelerometer's magnitude ([`AccelMagnitude`]).
        self.pairs.get(c as usize)?.fit()
    }

    /// This check with the [`Lever`] fit too ([`Self::lever_fit`]; the 3-D check's, off
    /// in the planar one, which every log reader runs per row).
    pub fn with_lever(mut self) -> Self {
        self.lever = Some(Lever::default());
        self
    }

    /// The gyro against the encoder's rate with the sensor's height above the centre of
    /// rotation fitted out ([`Lever`]), for gravity `g` \[m/s^2\]; `None` without
    /// [`Self::with_lever`] or enough motion.
    pub fn lever_fit(&self, g: f64) -> Option<LeverFit> {
        self.lever.as_ref()?.fit(g)
    }

    /// The factor of comparison `c` when it correlates and is near 1, deg or 1/deg.
    fn verdict(&self, c: Comparison) -> Option<(Fit, f64)> {
        let f = self.fit(c)?;
        unit_factor(&f).map(|k| (f, k))
    }

    /// The columns found in degrees (or converted twice), each with its factor and fix.
    /// Empty for a log that is right, or too short or too still to tell.
    pub fn findings(&self) -> Vec<Finding> {
        // The accelerometer's unit, from its magnitude (no motion needed).
        let mut out: Vec<Finding> = self
            .accel
            .finding("ax, ay", self.accel_unit)
            .into_iter()
            .collect();
        if self.duration < MIN_DURATION {
            return out;
        }
        // A column that counts the other way: its pairs fit with the sign reversed (and then
        // say nothing of its unit until it is read the right way round).
        out.extend(self.sign_findings());
        let verdict = |c| self.verdict(c);
        // The encoder against the accelerometer (whose unit is fixed).
        let phi = verdict(Comparison::EncoderAccel);
        let phi_deg = matches!(phi, Some((_, k)) if k == DEG);
        if let Some((f, k)) = phi {
            if k != 1.0 {
                out.push(finding("phi", Comparison::EncoderAccel, f, k));
            }
        }
        // The gyro against the encoder's derivative, else the accelerometer's.
        let by_accel = verdict(Comparison::GyroAccelRate);
        match verdict(Comparison::GyroEncoderRate) {
            Some((f, k)) if k == DEG && !phi_deg => {
                out.push(finding("gyro", Comparison::GyroEncoderRate, f, k))
            }
            Some((f, k)) if k == 1.0 / DEG && phi.is_none() => {
                out.push(finding("phi", Comparison::GyroEncoderRate, f, k))
            }
            Some((_, k)) if k == 1.0 && !phi_deg => {}
            Some((f, k)) if k == 1.0 && phi_deg && by_accel.is_none() => {
                out.push(follows_deg_phi("gyro", Comparison::GyroEncoderRate, f))
            }
            _ => {
                if let Some((f, k)) = by_accel {
                    if k != 1.0 {
                        out.push(finding("gyro", Comparison::GyroAccelRate, f, k));
                    }
                }
            }
        }
        // The true angle against the accelerometer, else the encoder.
        match (
            verdict(Comparison::TruthAccel),
            verdict(Comparison::TruthEncoder),
        ) {
            (Some((f, k)), _) if k != 1.0 => {
                out.push(finding("theta", Comparison::TruthAccel, f, k))
            }
            (Some(_), _) => {}
            (None, Some((f, k))) if k == 1.0 && phi_deg => {
                out.push(follows_deg_phi("theta", Comparison::TruthEncoder, f))
            }
            (None, Some((f, k))) if k != 1.0 && phi.is_none_or(|(_, k)| k == 1.0) => {
                out.push(finding("theta", Comparison::TruthEncoder, f, k))
            }
            _ => {}
        }
        out
    }
}

impl UnitCheck {
    /// A pair that fits well with its sign reversed: `Some(true)`; well as it is:
    /// `Some(false)`; `None`: no verdict (too little motion, a poor fit, another factor).
    pub(crate) fn reversed(&self, c: Comparison) -> Option<bool> {
        reversed(&self.fit(c)?)
    }

    /// The columns whose signs disagree with the others' (MODEL.md section 1: theta, phi,
    /// gyro counter-clockwise positive, `(ax, ay) = (g sin theta, g cos theta)` at rest), the
    /// accelerometer's angle taken as the reference (gravity fixes its sign once ax's is
    /// right). Measured on the scooter ride: phi, gyro or ax negated gave 12.0, 8.0 (ekf) and
    /// 3.8 (Mahony) deg RMS with nothing said.
    fn sign_findings(&self) -> Vec<Finding> {
        let phi = self.reversed(Comparison::EncoderAccel);
        let truth = self.reversed(Comparison::TruthAccel);
        let mut out: Vec<Finding> = self.reversed_sensor().into_iter().collect();
        // The true angle against the accelerometer (whose sign the sensors agree with).
        if truth == Some(true) && phi != Some(true) {
            out.push(self.finding(
                "theta",
                Comparison::TruthAccel,
                format!(
                    "theta counts the other way from the accelerometer's angle atan2(ax, ay) \
                     ({}): every score against it is wrong; read it with --negate theta \
                     ({SIGN})",
                    self.how(Comparison::TruthAccel)
                ),
            ));
        }
        out
    }

    /// The sensor (phi, the gyro, ax, or two of them) whose sign disagrees with the others',
    /// when the comparisons tell.
    fn reversed_sensor(&self) -> Option<Finding> {
        let phi = self.reversed(Comparison::EncoderAccel);
        let gyro = self.reversed(Comparison::GyroAccelRate);
        let pair = self.reversed(Comparison::GyroEncoderRate);
        let truth = self.reversed(Comparison::TruthAccel);
        match (phi, gyro, pair) {
            // Both against the accelerometer, and with each other: the true angle, when the
            // log has it, tells which.
            (Some(true), Some(true), Some(false)) if truth == Some(true) => Some(self.finding(
                "ax",
                Comparison::TruthAccel,
                format!(
                    "the accelerometer's angle atan2(ax, ay) counts the other way from phi, \
                     the gyro and theta (theta against it: {}): is ax reversed? read it with \
                     --negate ax ({SIGN})",
                    self.how(Comparison::TruthAccel)
                ),
            )),
            (Some(true), Some(true), Some(false)) if truth == Some(false) => Some(self.finding(
                "phi, gyro",
                Comparison::EncoderAccel,
                format!(
                    "phi and gyro both count the other way from the accelerometer's angle \
                     atan2(ax, ay) and from theta ({}): are the encoder and the gyro both \
                     mounted the other way round? read them with --negate phi,gyro ({SIGN})",
                    self.how(Comparison::EncoderAccel)
                ),
            )),
            (Some(true), Some(true), Some(false)) => Some(self.finding(
                "phi, gyro",
                Comparison::EncoderAccel,
                format!(
                    "phi and gyro both count the other way from the accelerometer's angle \
                     atan2(ax, ay) ({}; the gyro against its derivative: {}): either ax is \
                     reversed (read it with --negate ax) or both are (--negate phi,gyro) \
                     ({SIGN})",
                    self.how(Comparison::EncoderAccel),
                    self.how(Comparison::GyroAccelRate)
                ),
            )),
            (Some(true), _, Some(true)) => Some(self.finding(
                "phi",
                Comparison::EncoderAccel,
                format!(
                    "phi counts the other way from the accelerometer's angle atan2(ax, ay) and \
                     from the gyro ({}): is the encoder mounted the other way round? read it \
                     with --negate phi ({SIGN})",
                    self.how(Comparison::EncoderAccel)
                ),
            )),
            (_, Some(true), Some(true)) => Some(self.finding(
                "gyro",
                Comparison::GyroAccelRate,
                format!(
                    "gyro counts the other way from the derivative of the accelerometer's \
                     angle and from the encoder's d(phi)/dt ({}): is the gyro mounted the \
                     other way round (clockwise positive)? read it with --negate gyro ({SIGN})",
                    self.how(Comparison::GyroAccelRate)
                ),
            )),
            // Without an accelerometer to tell which.
            (None, None, Some(true)) => Some(self.finding(
                "gyro",
                Comparison::GyroEncoderRate,
                format!(
                    "gyro and the encoder's derivative d(phi)/dt count opposite ways ({}): \
                     one of them is mounted the other way round; read it with --negate gyro \
                     or --negate phi ({SIGN})",
                    self.how(Comparison::GyroEncoderRate)
                ),
            )),
            _ => None,
        }
    }

    /// Comparison `c`'s fit, NaN when there is none.
    fn fit_or_nan(&self, c: Comparison) -> Fit {
        self.fit(c).unwrap_or(Fit {
            factor: f64::NAN,
            correlation: f64::NAN,
            samples: 0,
        })
    }

    /// Comparison `c`'s fit as a message gives it.
    fn how(&self, c: Comparison) -> String {
        let f = self.fit_or_nan(c);
        format!(
            "factor {:.2}, r = {:.2}, over {} rows below f_n / 4",
            f.factor, f.correlation, f.samples
        )
    }

    /// A finding on `column` from comparison `c`.
    fn finding(&self, column: &'static str, c: Comparison, message: String) -> Finding {
        Finding {
            column,
            comparison: c,
            fit: self.fit_or_nan(c),
            message,
        }
    }
}

/// The sign convention the sign findings cite.
const SIGN: &str = "MODEL.md section 1: theta, phi and gyro count counter-clockwise, and \
                    (ax, ay) = (g sin theta, g cos theta) at rest";

/// `col` (the gyro or the true angle) follows phi (or its rate) one to one while phi is
/// in degrees: it probably is too.
fn follows_deg_phi(col: &'static str, c: Comparison, f: Fit) -> Finding {
    Finding {
        column: col,
        comparison: c,
        fit: f,
        message: format!(
            "{col} follows {} (factor {:.2}, r = {:.2}) and phi is in degrees: is \
             {col} in {} too? read it with --deg {col}",
            if col == "gyro" { "d(phi)/dt" } else { "phi" },
            f.factor,
            f.correlation,
            if col == "gyro" { "deg/s" } else { "degrees" }
        ),
    }
}

fn finding(column: &'static str, comparison: Comparison, fit: Fit, k: f64) -> Finding {
    let against = match comparison {
        Comparison::GyroEncoderRate => "the encoder's derivative d(phi)/dt",
        Comparison::EncoderAccel | Comparison::TruthAccel => {
            "the accelerometer's angle atan2(ax, ay)"
        }
        Comparison::GyroAccelRate => "the derivative of the accelerometer's angle",
        Comparison::TruthEncoder => "phi",
        Comparison::AccelGravity => "gravity",
    };
    let how = format!(
        "least squares over {} rows below f_n / 4, r = {:.2}",
        fit.samples, fit.correlation
    );
    let unit = |c: &str| if c == "gyro" { "deg/s" } else { "degrees" };
    let message = if k > 1.0 {
        format!(
            "{column} is {:.1}x {against}: is {column} in {}? read it with --deg {column} \
             ({how})",
            fit.factor,
            unit(column)
        )
    } else if comparison == Comparison::GyroEncoderRate {
        // The gyro is 1/57.3 of phi': the encoder is the column in degrees.
        return Finding {
            column: "phi",
            comparison,
            fit,
            message: format!(
                "the encoder's derivative d(phi)/dt is {:.1}x the gyro: is phi in degrees? \
                 read it with --deg phi ({how})",
                1.0 / fit.factor
            ),
        };
    } else {
        format!(
            "{column} is 1/{:.1} of {against}: is {column} already in radians and read \
             with --deg? leave {column} out of --deg ({how})",
            1.0 / fit.factor
        )
    };
    Finding {
        column,
        comparison,
        fit,
        message,
    }
}

#[cfg(test)]
mod tests;
