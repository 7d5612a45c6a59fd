//! The paper's Fig. 3: the Kalman posterior variance against the measurement variance R.
//!
//! Eq (12), with sigma_X and R variances (MODEL.md section 4): after one update the
//! variance of the fused estimate is sigma_X R / (sigma_X + R), below both inputs. The
//! Monte-Carlo check draws a prediction and a measurement with those variances around a
//! known value, fuses them with the Kalman gain K = sigma_X / (sigma_X + R) (Eqs 6, 8 with
//! H = 1), and measures the variance of the posterior error.
use std::path::Path;

use plotters::style::RGBColor;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::Serialize;

use super::figures::{plot_curves, Curve, FigureFiles, FigureSpec, LegendPosition};
use super::palette::Palette;
use super::ReportError;

/// Eq (12): posterior variance of a one-dimensional Kalman update, from the prediction
/// variance `sigma_x` and the measurement variance `r` (both >= 0, not both 0).
pub fn posterior_variance(sigma_x: f64, r: f64) -> Result<f64, ReportError> {
    check_variances(sigma_x, r)?;
    Ok(sigma_x * r / (sigma_x + r))
}

fn check_variances(sigma_x: f64, r: f64) -> Result<(), ReportError> {
    if !(sigma_x.is_finite() && r.is_finite() && sigma_x >= 0.0 && r >= 0.0) {
        return Err(ReportError::Invalid(format!(
            "variances must be finite and >= 0 (sigma_X = {sigma_x}, R = {r})"
        )));
    }
    if sigma_x + r == 0.0 {
        return Err(ReportError::Invalid(
            "sigma_X and R are both 0: the gain is undefined".into(),
        ));
    }
    Ok(())
}

/// A Monte-Carlo estimate of the posterior variance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MonteCarloVariance {
    /// Mean squared posterior error (the true value is known, so no mean is removed).
    pub variance: f64,
    /// Its standard error for Gaussian errors: variance * sqrt(2 / n).
    pub std_error: f64,
    /// Number of draws.
    pub draws: usize,
}

/// Monte-Carlo posterior variance for `sigma_x` and `r` (variances), `draws` draws from a
/// ChaCha8 generator seeded with `seed` (the same seed gives the same number).
pub fn monte_carlo_posterior_variance(
    sigma_x: f64,
    r: f64,
    draws: usize,
    seed: u64,
) -> Result<MonteCarloVariance, ReportError> {
    check_variances(sigma_x, r)?;
    if draws < 2 {
        return Err(ReportError::Invalid(format!(
            "Monte-Carlo needs at least 2 draws, got {draws}"
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let pred = Normal::new(0.0, sigma_x.sqrt()).map_err(|e| ReportError::Invalid(e.to_string()))?;
    let meas = Normal::new(0.0, r.sqrt()).map_err(|e| ReportError::Invalid(e.to_string()))?;
    let truth = 0.0;
    let gain = sigma_x / (sigma_x + r);
    let mut sum_sq = 0.0;
    for _ in 0..draws {
        let x_pred = truth + pred.sample(&mut rng);
        let z = truth + meas.sample(&mut rng);
        let x_post = x_pred + gain * (z - x_pred);
        sum_sq += (x_post - truth).powi(2);
    }
    let variance = sum_sq / draws as f64;
    Ok(MonteCarloVariance {
        variance,
        std_error: variance * (2.0 / draws as f64).sqrt(),
        draws,
    })
}

/// Settings of Fig. 3.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fig3Config {
    /// Prediction variance sigma_X \[deg^2\], held constant as in the paper's figure.
    pub sigma_x: f64,
    /// Largest measurement variance R \[deg^2\] on the abscissa.
    pub r_max: f64,
    /// Points of the analytic curve.
    pub curve_points: usize,
    /// Values of R checked by Monte-Carlo.
    pub mc_points: usize,
    /// Draws per Monte-Carlo point.
    pub draws: usize,
    /// Seed of the first Monte-Carlo point (the k-th uses seed + k).
    pub seed: u64,
}

impl Default for Fig3Config {
    fn default() -> Self {
        Self {
            sigma_x: 1.0,
            r_max: 5.0,
            curve_points: 200,
            mc_points: 11,
            draws: 20_000,
            seed: 3,
        }
    }
}

/// One Monte-Carlo point of Fig. 3.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Fig3Point {
    /// Measurement variance R.
    pub r: f64,
    /// Eq (12).
    pub analytic: f64,
    /// The Monte-Carlo estimate.
    pub monte_carlo: MonteCarloVariance,
}

/// The data of Fig. 3: the analytic curve and the Monte-Carlo points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fig3Data {
    /// Settings used.
    pub config: Fig3Config,
    /// Abscissae R of the analytic curve.
    pub r: Vec<f64>,
    /// Eq (12) at each R.
    pub analytic: Vec<f64>,
    /// The Monte-Carlo checks.
    pub points: Vec<Fig3Point>,
}

impl Fig3Data {
    /// Largest |Monte-Carlo - analytic| in units of the Monte-Carlo standard error.
    pub fn worst_z(&self) -> f64 {
        self.points
            .iter()
            .map(|p| (p.monte_carlo.variance - p.analytic).abs() / p.monte_carlo.std_error)
            .fold(0.0, f64::max)
    }
}

/// Computes Fig. 3: Eq (12) on `curve_points` values of R in \[0, r_max\], and the
/// Monte-Carlo check on `mc_points` values of R in (0, r_max].
pub fn fig3_data(cfg: &Fig3Config) -> Result<Fig3Data, ReportError> {
    if !(cfg.sigma_x.is_finite() && cfg.sigma_x > 0.0 && cfg.r_max.is_finite() && cfg.r_max > 0.0) {
        return Err(ReportError::Invalid(
            "Fig 3 needs sigma_X > 0 and r_max > 0".into(),
        ));
    }
    if cfg.curve_points < 2 || cfg.mc_points < 1 {
        return Err(ReportError::Invalid(
            "Fig 3 needs at least 2 curve points and 1 Monte-Carlo point".into(),
        ));
    }
    let r: Vec<f64> = (0..cfg.curve_points)
        .map(|k| cfg.r_max * k as f64 / (cfg.curve_points - 1) as f64)
        .collect();
    let analytic = r
        .iter()
        .map(|&rv| posterior_variance(cfg.sigma_x, rv))
        .collect::<Result<Vec<_>, _>>()?;
    let points = (1..=cfg.mc_points)
        .map(|k| {
            let rv = cfg.r_max * k as f64 / cfg.mc_points as f64;
            Ok(Fig3Point {
                r: rv,
                analytic: posterior_variance(cfg.sigma_x, rv)?,
                monte_carlo: monte_carlo_posterior_variance(
                    cfg.sigma_x,
                    rv,
                    cfg.draws,
                    cfg.seed.wrapping_add(k as u64),
                )?,
            })
        })
        .collect::<Result<Vec<_>, ReportError>>()?;
    Ok(Fig3Data {
        config: cfg.clone(),
        r,
        analytic,
        points,
    })
}

/// Draws Fig. 3 into `dir/stem.{png,svg}`: Eq (12), the Monte-Carlo points with +-2
/// standard-error bars, and the two inputs' variances for reference (the posterior lies
/// below both).
pub fn plot_fig3(
    dir: &Path,
    stem: &str,
    data: &Fig3Data,
    palette: &Palette,
) -> Result<FigureFiles, ReportError> {
    let sx = data.config.sigma_x;
    let meas_only = data.r.clone();
    let pred_only = vec![sx; data.r.len()];
    let mc_r: Vec<f64> = data.points.iter().map(|p| p.r).collect();
    let mc_v: Vec<f64> = data.points.iter().map(|p| p.monte_carlo.variance).collect();
    let mc_e: Vec<f64> = data
        .points
        .iter()
        .map(|p| 2.0 * p.monte_carlo.std_error)
        .collect();
    let mut spec = FigureSpec::new(
        &format!("Fig 3: Kalman posterior variance vs measurement variance (σX = {sx} deg²)"),
        "measurement variance R [deg²]",
        "variance [deg²]",
    );
    spec.legend = LegendPosition::UpperLeft;
    let y_top = sx.max(1e-12) * 1.6;
    spec.y_range = Some((0.0, y_top));
    let mut mc = Curve::points("Monte-Carlo (±2 s.e.)", &mc_r, &mc_v);
    mc.y_err = Some(&mc_e);
    let mut analytic = Curve::line("Eq 12: σX·R/(σX+R)", &data.r, &data.analytic);
    analytic.width = 3;
    let mut meas = Curve::line("measurement alone: R", &data.r, &meas_only);
    meas.width = 2;
    let mut pred = Curve::line("prediction alone: σX", &data.r, &pred_only);
    pred.width = 2;
    // Colours for this figure's own curves, unless the caller's palette sets them.
    let mut pal = palette.clone();
    for (name, colour) in [
        (meas.name, RGBColor(150, 150, 150)),
        (pred.name, RGBColor(31, 119, 180)),
        (analytic.name, RGBColor(0, 0, 0)),
        (mc.name, RGBColor(214, 39, 40)),
    ] {
        if !palette.has(name) {
            pal.set(name, colour);
        }
    }
    plot_curves(dir, stem, &spec, &[meas, pred, analytic, mc], &pal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq12_by_hand() {
        assert_eq!(posterior_variance(1.0, 1.0).unwrap(), 0.5);
        assert!((posterior_variance(2.0, 3.0).unwrap() - 1.2).abs() < 1e-15);
        assert_eq!(posterior_variance(1.0, 0.0).unwrap(), 0.0);
        assert!(posterior_variance(0.0, 0.0).is_err());
        assert!(posterior_variance(-1.0, 1.0).is_err());
        assert!(posterior_variance(f64::NAN, 1.0).is_err());
    }

    #[test]
    fn monte_carlo_matches_eq12_within_its_sampling_error() {
        for (sx, r, seed) in [(1.0, 0.5, 1), (1.0, 3.0, 2), (0.2, 0.05, 3), (4.0, 4.0, 4)] {
            let mc = monte_carlo_posterior_variance(sx, r, 50_000, seed).unwrap();
            let a = posterior_variance(sx, r).unwrap();
            // 4 standard errors: a false alarm about once in 16 000 runs, but seeded
            assert!(
                (mc.variance - a).abs() < 4.0 * mc.std_error,
                "sx {sx} r {r}: mc {} analytic {a} se {}",
                mc.variance,
                mc.std_error
            );
            // and the standard error is small enough to have tested something
            assert!(mc.std_error < 0.01 * a);
        }
    }

    #[test]
    fn a_wrong_gain_would_be_caught() {
        // the test above has power: the variance with K = 0.5 instead of the optimum at
        // sx = 1, r = 3 is 0.25 + 0.75 = 1.0 vs Eq 12's 0.75, far outside 4 s.e.
        let mc = monte_carlo_posterior_variance(1.0, 3.0, 50_000, 2).unwrap();
        assert!((mc.variance - 1.0).abs() > 10.0 * mc.std_error);
    }

    #[test]
    fn seeded_and_reproducible() {
        let a = monte_carlo_posterior_variance(1.0, 2.0, 1000, 9).unwrap();
        let b = monte_carlo_posterior_variance(1.0, 2.0, 1000, 9).unwrap();
        assert_eq!(a, b);
        let d = fig3_data(&Fig3Config::default()).unwrap();
        assert_eq!(d.points.len(), 11);
        assert!(d.worst_z() < 4.0, "worst z {}", d.worst_z());
        // below both inputs everywhere
        for (r, v) in d.r.iter().zip(&d.analytic) {
            assert!(*v <= r.min(d.config.sigma_x) + 1e-15);
        }
    }
}
