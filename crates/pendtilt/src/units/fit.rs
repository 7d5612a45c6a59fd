//! The running fits the checks compare columns with: `y = k x + c` ([`Pair`]), the
//! lever arm's `y = a x + b x'' + c` ([`Lever`]), and a fourth-order low-pass ([`Smooth`]).
use super::*;

/// Running least squares of `y = k x + c`: the unit checks' comparisons, planar here and
/// of the 3-D truth against its encoders (`pipeline::spatial`).
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
/// turn check's, `pipeline::spatial`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Smooth([LowPass2<f64>; 2]);

impl Smooth {
    pub(crate) fn new(hz: f64) -> Self {
        Self([LowPass2::new(hz); 2])
    }
    pub(super) fn reset(&mut self) {
        self.0[0].reset();
        self.0[1].reset();
    }
    pub(crate) fn update(&mut self, u: f64, dt: f64) -> f64 {
        let v = self.0[0].update(u, dt);
        self.0[1].update(v, dt)
    }
}
