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
//! ([`crate::bank::check_settings_against_rate`], with [`MIN_DIFF_CUTOFF_TIMES_NATURAL`]).
use pendtilt_core::estimators::equations::accel_angle;
use pendtilt_core::filters::biquad::LowPass2;
use pendtilt_core::Sample;

use crate::sensors::Inputs;

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

/// Running least squares of `y = k x + c`: the unit checks' comparisons, planar here and
/// of the 3-D truth against its encoders (`cli::estimate3d`).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Pair {
    n: f64,
    sx: f64,
    sy: f64,
    sxx: f64,
    syy: f64,
    sxy: f64,
}

/// A fitted pair: the factor `k` and the correlation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit {
    /// The least-squares factor of `y` on `x`.
    pub factor: f64,
    /// The correlation coefficient of `x` and `y`.
    pub correlation: f64,
    /// Samples in the fit.
    pub samples: u64,
}

impl Pair {
    /// Adds a pair of readings (a non-finite one is left out).
    pub(crate) fn add(&mut self, x: f64, y: f64) {
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        self.n += 1.0;
        self.sx += x;
        self.sy += y;
        self.sxx += x * x;
        self.syy += y * y;
        self.sxy += x * y;
    }

    /// Pairs added.
    pub(crate) fn samples(&self) -> u64 {
        self.n as u64
    }

    /// The factor, the correlation and the RMS of `x` about its mean (its motion); `None`
    /// below 3 pairs or when either does not vary.
    fn slope(&self) -> Option<(f64, f64, f64)> {
        if self.n < 3.0 {
            return None;
        }
        let n = self.n;
        let vx = self.sxx / n - (self.sx / n).powi(2);
        let vy = self.syy / n - (self.sy / n).powi(2);
        let c = self.sxy / n - self.sx * self.sy / (n * n);
        (vx > 0.0 && vy > 0.0).then(|| (c / vx, c / (vx * vy).sqrt(), vx.sqrt()))
    }

    /// The fit, when `x` moved by at least [`MIN_MOTION`].
    pub(crate) fn fit(&self) -> Option<Fit> {
        let (factor, correlation, motion) = self.slope()?;
        // Too little motion in the reference: its factor would be noise (a 3 s still log
        // gave theta 1/82.7 of the accelerometer's angle at r > 0.8 without this floor).
        (motion >= MIN_MOTION).then_some(Fit {
            factor,
            correlation,
            samples: self.samples(),
        })
    }

    /// The factor of `y` on `x` from the regression of `x` on `y` (`var y / cov`), when
    /// `x`'s standard deviation is at least `floor`: the one to use when the noise is in
    /// `x` (the factor of `y` on `x` is then too small by `r^2`).
    pub(crate) fn fit_noisy_x_above(&self, floor: f64) -> Option<Fit> {
        let (slope, correlation, motion) = self.slope()?;
        // slope = cov / var x, r^2 = cov^2 / (var x var y): var y / cov = slope / r^2.
        (motion >= floor).then_some(Fit {
            factor: slope / (correlation * correlation),
            correlation,
            samples: self.samples(),
        })
    }
}

/// Running least squares of `y = a x + b x'' + c`: the encoder's rate `y` on the gyro `x`
/// and its second derivative `x''`, which takes out the swing that a sensor at a height
/// `h` above the centre the body rotates about adds to the pendulum. Its specific force
/// there leans by `-(h / g) theta''` besides the tilt, so `phi ~ theta - (h / g) theta''`
/// and `phi' ~ gyro - (h / g) gyro''`; on a ship's mast (ship3d, 5 m) the pendulum swings
/// 1.4x the pitch, and 1.8x its rate (the term grows with the frequency squared).
#[derive(Debug, Clone, Copy, Default)]
pub struct Lever {
    n: f64,
    // Sums of x, x'', y and of their products.
    s: [f64; 3],
    p: [[f64; 3]; 3],
}

/// A [`Lever`] fit: the factor of the gyro on the encoder's rate (`1 / a`), the multiple
/// correlation, and the height `h = -g b / a` \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeverFit {
    /// Factor, multiple correlation (as [`Fit::correlation`]) and samples.
    pub fit: Fit,
    /// The sensor's height above the centre the body rotates about \[m\].
    pub height: f64,
}

impl Lever {
    /// Adds the gyro `x`, its second derivative `x2` and the encoder's rate `y`.
    pub(crate) fn add(&mut self, x: f64, x2: f64, y: f64) {
        let v = [x, x2, y];
        if !v.iter().all(|u| u.is_finite()) {
            return;
        }
        self.n += 1.0;
        for i in 0..3 {
            self.s[i] += v[i];
            for j in 0..3 {
                self.p[i][j] += v[i] * v[j];
            }
        }
    }

    /// The fit, when the encoder's rate moved by at least [`MIN_MOTION`], with gravity `g`.
    pub(crate) fn fit(&self, g: f64) -> Option<LeverFit> {
        if self.n < 4.0 {
            return None;
        }
        let n = self.n;
        let c = |i: usize, j: usize| self.p[i][j] / n - self.s[i] * self.s[j] / (n * n);
        let (vxx, vx2, v22, vyy) = (c(0, 0), c(0, 1), c(1, 1), c(2, 2));
        let (cxy, c2y) = (c(0, 2), c(1, 2));
        let det = vxx * v22 - vx2 * vx2;
        if !(det > 0.0 && vyy > 0.0) || vyy.sqrt() < MIN_MOTION {
            return None;
        }
        let a = (v22 * cxy - vx2 * c2y) / det;
        let b = (vxx * c2y - vx2 * cxy) / det;
        let r2 = (a * cxy + b * c2y) / vyy;
        (a != 0.0 && r2.is_finite()).then(|| LeverFit {
            fit: Fit {
                factor: 1.0 / a,
                correlation: r2.clamp(0.0, 1.0).sqrt(),
                samples: n as u64,
            },
            height: -g * b / a,
        })
    }
}

/// Which of [`DEG`], `1 / DEG` and 1 a fitted factor is (within [`FACTOR_TOLERANCE`]),
/// when its correlation says anything ([`MIN_CORRELATION`]): a column in degrees, one
/// converted twice (or radians read with --deg), or a right one. The planar check's
/// comparisons and the 3-D log's (its gyro axes, its truth).
pub(crate) fn unit_factor(f: &Fit) -> Option<f64> {
    if f.correlation < MIN_CORRELATION {
        return None;
    }
    // A negative factor is a reversed sign, near no unit (a multiple correlation, the
    // lever fit's, is positive whatever the sign: gyro_x negated read as `-1.0x: is the
    // gyro in deg/s?`).
    let near = |target: f64| {
        f.factor > 0.0
            && f.factor / target < FACTOR_TOLERANCE
            && target / f.factor < FACTOR_TOLERANCE
    };
    [DEG, 1.0 / DEG, 1.0].into_iter().find(|&t| near(t))
}

/// Whether a fit is of a column that counts the other way: `Some(true)` when the negative
/// of its factor is a unit ([`unit_factor`], the correlation's size judged: a multiple
/// correlation has no sign), `Some(false)` when its factor is, `None` when neither.
pub(crate) fn reversed(f: &Fit) -> Option<bool> {
    let flipped = Fit {
        factor: -f.factor,
        correlation: f.correlation.abs(),
        ..*f
    };
    match (unit_factor(f), unit_factor(&flipped)) {
        (Some(_), _) => Some(false),
        (None, Some(_)) => Some(true),
        _ => None,
    }
}

/// A fourth-order low-pass: two second-order sections (the unit checks' and the 3-D
/// turn check's, `cli::estimate3d`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Smooth([LowPass2<f64>; 2]);

impl Smooth {
    pub(crate) fn new(hz: f64) -> Self {
        Self([LowPass2::new(hz); 2])
    }
    fn reset(&mut self) {
        self.0[0].reset();
        self.0[1].reset();
    }
    pub(crate) fn update(&mut self, u: f64, dt: f64) -> f64 {
        let v = self.0[0].update(u, dt);
        self.0[1].update(v, dt)
    }
}

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
    /// [`crate::io::STANDARD_GRAVITY`]), for the accelerometer `columns` read with `given`
    /// (`--accel-unit`, `None`: m/s^2): the unit that explains it, or the question. `None`
    /// for a log that is right or has fewer than [`MIN_ACCEL_READINGS`] readings.
    pub fn finding(
        &self,
        columns: &'static str,
        given: Option<crate::io::AccelUnit>,
    ) -> Option<Finding> {
        use crate::io::{AccelUnit, STANDARD_GRAVITY};
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
            crate::io::plausibility::fmt_sig(median),
            crate::io::plausibility::fmt_sig(ratio),
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
    accel_unit: Option<crate::io::AccelUnit>,
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
    pub fn with_accel_unit(mut self, unit: Option<crate::io::AccelUnit>) -> Self {
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
        if self.inputs.accel {
            self.accel.add(s.ax.hypot(s.ay));
        }
        let th = theta.unwrap_or(f64::NAN);
        // Readings beyond the sensors' bounds still count here (a gyro in deg/s is beyond
        // a rad/s full scale), unless absurd in any unit.
        let ok = |v: f64| v.abs() < ABSURD;
        let usable = s.dt.is_finite()
            && (!self.inputs.phi || ok(s.phi))
            && (!self.inputs.gyro || ok(s.gyro))
            && (!self.inputs.accel || (ok(s.ax) && ok(s.ay)));
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
        if self.inputs.accel {
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
        let (p, g, a) = (self.inputs.phi, self.inputs.gyro, self.inputs.accel);
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
        let gyro = self.reversed(Comparison::GyroAccelRate);
        let pair = self.reversed(Comparison::GyroEncoderRate);
        let truth = self.reversed(Comparison::TruthAccel);
        let fit = |c| {
            self.fit(c).unwrap_or(Fit {
                factor: f64::NAN,
                correlation: f64::NAN,
                samples: 0,
            })
        };
        let how = |c: Comparison| {
            let f = fit(c);
            format!(
                "factor {:.2}, r = {:.2}, over {} rows below f_n / 4",
                f.factor, f.correlation, f.samples
            )
        };
        let sign = "MODEL.md section 1: theta, phi and gyro count counter-clockwise, and \
                    (ax, ay) = (g sin theta, g cos theta) at rest";
        let finding = |column: &'static str, c: Comparison, message: String| Finding {
            column,
            comparison: c,
            fit: fit(c),
            message,
        };
        let mut out = Vec::new();
        match (phi, gyro, pair) {
            // Both against the accelerometer, and with each other: the true angle, when the
            // log has it, tells which.
            (Some(true), Some(true), Some(false)) if truth == Some(true) => out.push(finding(
                "ax",
                Comparison::TruthAccel,
                format!(
                    "the accelerometer's angle atan2(ax, ay) counts the other way from phi, \
                     the gyro and theta (theta against it: {}): is ax reversed? read it with \
                     --negate ax ({sign})",
                    how(Comparison::TruthAccel)
                ),
            )),
            (Some(true), Some(true), Some(false)) if truth == Some(false) => out.push(finding(
                "phi, gyro",
                Comparison::EncoderAccel,
                format!(
                    "phi and gyro both count the other way from the accelerometer's angle \
                     atan2(ax, ay) and from theta ({}): are the encoder and the gyro both \
                     mounted the other way round? read them with --negate phi,gyro ({sign})",
                    how(Comparison::EncoderAccel)
                ),
            )),
            (Some(true), Some(true), Some(false)) => out.push(finding(
                "phi, gyro",
                Comparison::EncoderAccel,
                format!(
                    "phi and gyro both count the other way from the accelerometer's angle \
                     atan2(ax, ay) ({}; the gyro against its derivative: {}): either ax is \
                     reversed (read it with --negate ax) or both are (--negate phi,gyro) \
                     ({sign})",
                    how(Comparison::EncoderAccel),
                    how(Comparison::GyroAccelRate)
                ),
            )),
            (Some(true), _, Some(true)) => out.push(finding(
                "phi",
                Comparison::EncoderAccel,
                format!(
                    "phi counts the other way from the accelerometer's angle atan2(ax, ay) and \
                     from the gyro ({}): is the encoder mounted the other way round? read it \
                     with --negate phi ({sign})",
                    how(Comparison::EncoderAccel)
                ),
            )),
            (_, Some(true), Some(true)) => out.push(finding(
                "gyro",
                Comparison::GyroAccelRate,
                format!(
                    "gyro counts the other way from the derivative of the accelerometer's \
                     angle and from the encoder's d(phi)/dt ({}): is the gyro mounted the \
                     other way round (clockwise positive)? read it with --negate gyro ({sign})",
                    how(Comparison::GyroAccelRate)
                ),
            )),
            // Without an accelerometer to tell which.
            (None, None, Some(true)) => out.push(finding(
                "gyro",
                Comparison::GyroEncoderRate,
                format!(
                    "gyro and the encoder's derivative d(phi)/dt count opposite ways ({}): \
                     one of them is mounted the other way round; read it with --negate gyro \
                     or --negate phi ({sign})",
                    how(Comparison::GyroEncoderRate)
                ),
            )),
            _ => {}
        }
        // The true angle against the accelerometer (whose sign the sensors agree with).
        if truth == Some(true) && phi != Some(true) {
            out.push(finding(
                "theta",
                Comparison::TruthAccel,
                format!(
                    "theta counts the other way from the accelerometer's angle atan2(ax, ay) \
                     ({}): every score against it is wrong; read it with --negate theta \
                     ({sign})",
                    how(Comparison::TruthAccel)
                ),
            ));
        }
        out
    }
}

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
mod tests {
    use super::*;
    use crate::io::{AccelUnit, STANDARD_GRAVITY};

    /// A vibrating body's specific force: gravity tilted by `tilt` plus a vibration of
    /// `vib` m/s^2 (a deterministic spread of tones), in `unit`.
    fn accel_log(n: usize, vib: f64, unit: AccelUnit) -> AccelMagnitude {
        let mut m = AccelMagnitude::default();
        for k in 0..n {
            let t = k as f64 * 1e-3;
            let tilt = 0.3 * (0.7 * t).sin();
            let v = vib * ((2.0 * std::f64::consts::PI * 37.0 * t).sin() + (91.0 * t).cos());
            let (ax, ay) = (
                STANDARD_GRAVITY * tilt.sin() + v,
                STANDARD_GRAVITY * tilt.cos() - 0.5 * v,
            );
            m.add(ax.hypot(ay) / unit.metres_per_second_squared());
        }
        m
    }

    /// The median magnitude to 1 %; a log in g or mg named with the unit that explains it
    /// and the fix; a log in m/s^2 quiet, also with strong vibration; m/s^2 read with
    /// `--accel-unit g` told to leave it out; one absurd reading moves nothing; too few
    /// readings, no verdict.
    #[test]
    fn the_accelerometer_in_g_or_mg_is_found_from_gravity() {
        let right = accel_log(5000, 3.0, AccelUnit::MetresPerSecondSquared);
        let med = right.median().unwrap();
        assert!((med / STANDARD_GRAVITY - 1.0).abs() < 0.1, "{med}");
        assert!(right.finding("ax, ay", None).is_none());
        // A hard ride: 8 m/s^2 of vibration on 9.8 of gravity.
        assert!(accel_log(5000, 8.0, AccelUnit::MetresPerSecondSquared)
            .finding("ax, ay", None)
            .is_none());
        for (unit, ratio) in [(AccelUnit::G, 0.102), (AccelUnit::MilliG, 102.0)] {
            let f = accel_log(5000, 3.0, unit).finding("ax, ay", None).unwrap();
            assert_eq!(f.comparison, Comparison::AccelGravity);
            assert!(
                (f.fit.factor / ratio - 1.0).abs() < 0.1,
                "{unit}: {}",
                f.fit.factor
            );
            assert!(
                f.message
                    .starts_with("ax, ay: the specific force's median magnitude is")
                    && f.message.contains(&format!(
                        "is the accelerometer in {unit}? read it with --accel-unit {unit}"
                    )),
                "{}",
                f.message
            );
            // Read with the right unit (the reader scales to m/s^2 before the check): quiet.
            assert!(accel_log(5000, 3.0, AccelUnit::MetresPerSecondSquared)
                .finding("ax, ay", Some(unit))
                .is_none());
        }
        // m/s^2 read as g: 9.8x too large.
        let mut twice = AccelMagnitude::default();
        for k in 0..500 {
            twice.add(STANDARD_GRAVITY * STANDARD_GRAVITY * (1.0 + 1e-3 * k as f64));
        }
        let f = twice.finding("ax, ay, az", Some(AccelUnit::G)).unwrap();
        assert!(
            f.message.contains("(read with --accel-unit g)")
                && f.message
                    .contains("is it already in m/s^2? leave out --accel-unit g"),
            "{}",
            f.message
        );
        // Neither g nor mg explains ft/s^2 (3.28x): the question.
        let mut feet = AccelMagnitude::default();
        for _ in 0..500 {
            feet.add(STANDARD_GRAVITY / 0.3048);
        }
        let f = feet.finding("ax, ay", None).unwrap();
        assert!(
            f.message.contains("is the accelerometer in m/s^2"),
            "{}",
            f.message
        );
        // One absurd reading in a right log, zeros and NaN: no finding, the median kept.
        let mut one = accel_log(5000, 3.0, AccelUnit::MetresPerSecondSquared);
        one.add(1e300);
        one.add(1e5);
        one.add(0.0);
        one.add(f64::NAN);
        assert!(one.finding("ax, ay", None).is_none());
        assert_eq!(one.median(), right.median());
        // Too few readings to tell.
        assert!(accel_log(99, 3.0, AccelUnit::G)
            .finding("ax, ay", None)
            .is_none());
        assert!(accel_log(100, 3.0, AccelUnit::G)
            .finding("ax, ay", None)
            .is_some());
    }

    /// A sensor 5 m above the centre its body pitches about (two sines, 5 deg at 0.14 Hz
    /// and 1 deg at 0.31 Hz, as ship3d's pitch): the pendulum reads `theta - (h / g)
    /// theta''`. The plain pair takes the gyro for 0.57 of the encoder's rate; the lever
    /// fit gives 1 (57.3 with the gyro in deg/s) and the height.
    #[test]
    fn the_lever_fit_takes_out_the_height_above_the_centre_of_rotation() {
        let (h, g, dt) = (5.0, 9.80665, 1e-3);
        let parts = [(5f64.to_radians(), 0.14), (1f64.to_radians(), 0.31)];
        for scale in [1.0, DEG] {
            let mut check = UnitCheck::with_natural_frequency(
                2.19,
                Inputs {
                    phi: true,
                    gyro: true,
                    accel: false,
                },
            )
            .with_lever();
            for k in 0..60_000 {
                let t = k as f64 * dt;
                let (mut th, mut rate, mut acc) = (0.0, 0.0, 0.0);
                for (a, f) in parts {
                    let w = std::f64::consts::TAU * f;
                    th += a * (w * t).sin();
                    rate += a * w * (w * t).cos();
                    acc -= a * w * w * (w * t).sin();
                }
                let s = Sample {
                    dt: if k == 0 { 0.0 } else { dt },
                    phi: th - h / g * acc,
                    gyro: scale * rate,
                    ax: f64::NAN,
                    ay: f64::NAN,
                };
                check.add(&s, None);
            }
            let plain = check.fit(Comparison::GyroEncoderRate).unwrap();
            assert!(plain.factor / scale < 0.7, "{plain:?}");
            let l = check.lever_fit(g).unwrap();
            assert!((l.fit.factor / scale - 1.0).abs() < 0.01, "{l:?}");
            assert!(l.fit.correlation > 0.999, "{l:?}");
            assert!((l.height - h).abs() < 0.1, "{l:?}");
        }
    }
}
