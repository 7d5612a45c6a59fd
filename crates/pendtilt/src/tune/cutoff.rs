//! The differentiator cutoff of Algorithms 1-3 from the log's own spectrum.
//!
//! The inversion `theta = phi + asin(a phi' + b phi'')` undoes the pendulum's mechanical
//! low-pass: linearised, it passes phi's component at `w = 2 pi f` with gain
//! `G(f) = |1 - b w^2 + j a w|^2` (power). `A(f) = S_phi(f) G(f)` is the spectrum of the
//! tilt the inversion would give with no low-pass: the body's tilt at low frequency, the
//! floor vibration and the encoder's noise amplified by `b w^2` above it. Between the two
//! `A` has a valley `f_v` (the minimum of `A` smoothed over a third of an octave, searched
//! from half the natural frequency up to 40 % of the sample rate).
//!
//! The rule: the cutoff `f_c` minimises the predicted error power
//!
//! `E(f_c) = sum_{f < f_v} A(f) |1 - L(j w)|^2 + sum_{f >= f_v} A(f) |L(j w)|^2`,
//!
//! where `L` is the differentiator's 4th-order low-pass at `f_c`: the first sum is what
//! its delay and roll-off do to the tilt (about `(w tau)^2` at low frequency, the delay
//! side of the trade-off), the second the vibration and noise it lets through (the noise
//! side). `f_c` is searched over 0.5-20 times the natural frequency on a log grid.
use super::spectrum::{segment_for, welch, Psd};
use pendtilt_core::filters::diff::{Cutoff, DiffSettings, Response};
use pendtilt_core::PendulumParams;
use std::f64::consts::TAU;

/// The chosen cutoff and what the rule saw.
#[derive(Debug, Clone, PartialEq)]
pub struct CutoffChoice {
    /// The settings with the chosen cutoff (as a multiple of the natural frequency).
    pub settings: DiffSettings<f64>,
    /// The cutoff \[Hz\].
    pub hz: f64,
    /// The valley between tilt and vibration \[Hz\].
    pub valley_hz: f64,
    /// The predicted error at the chosen cutoff, RMS \[rad\].
    pub predicted_rms: f64,
    /// The predicted error at `reference` (the cutoff in use before), RMS \[rad\].
    pub reference_rms: f64,
}

/// Power gain of the low-pass `L` of `response` at `x = f / f_c`, and `|1 - L|^2`.
fn lowpass(response: Response, x: f64) -> (f64, f64) {
    let [c0, c1, c2, c3] = response.coefficients();
    // Denominator at s = j x: x^4 - c2 x^2 + c0 + j (c1 x - c3 x^3).
    let (dr, di) = (x.powi(4) - c2 * x * x + c0, c1 * x - c3 * x.powi(3));
    let d2 = dr * dr + di * di;
    let (lr, li) = (c0 * dr / d2, -c0 * di / d2);
    (lr * lr + li * li, (1.0 - lr).powi(2) + li * li)
}

/// The predicted error power of cutoff `fc` \[Hz\] (module documentation).
fn error_power(a: &[f64], psd: &Psd, valley: f64, fc: f64, response: Response) -> f64 {
    let mut e = 0.0;
    for (i, &ai) in a.iter().enumerate().skip(1) {
        let (pass, miss) = lowpass(response, psd.freq(i) / fc);
        e += ai * if psd.freq(i) < valley { miss } else { pass };
    }
    e * psd.df
}

/// Chooses the cutoff for `phi` (NaN for missing) sampled at `rate`, a pendulum `params`
/// and the filter shape of `current` (whose cutoff is the reference the choice is
/// compared with).
pub fn choose(
    phi: &[f64],
    rate: f64,
    params: &PendulumParams<f64>,
    current: &DiffSettings<f64>,
) -> Result<CutoffChoice, String> {
    let psd = welch(phi, rate, segment_for(rate))
        .filter(|p| p.segments >= 8)
        .ok_or_else(|| "too short for the encoder's spectrum (5 s needed)".to_string())?;
    let f_n = params.natural_frequency_hz();
    let a: Vec<f64> = psd
        .density
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let w = TAU * psd.freq(i);
            let re = 1.0 - params.b * w * w;
            s * (re * re + (params.a * w).powi(2))
        })
        .collect();
    // The valley: the minimum of log A smoothed over a third of an octave.
    let third = 2f64.powf(1.0 / 6.0);
    let (lo, hi) = (0.5 * f_n, 0.4 * rate);
    let mut valley = (f64::INFINITY, f_n);
    for i in 1..a.len() {
        let f = psd.freq(i);
        if f < lo || f > hi {
            continue;
        }
        let (j0, j1) = (
            ((f / third / psd.df).floor() as usize).max(1),
            ((f * third / psd.df).ceil() as usize).min(a.len() - 1),
        );
        let n = (j1 + 1 - j0) as f64;
        let mean_log = a[j0..=j1].iter().map(|v| v.max(1e-300).ln()).sum::<f64>() / n;
        if mean_log < valley.0 {
            valley = (mean_log, f);
        }
    }
    if !valley.0.is_finite() {
        return Err("no spectrum between the pendulum and the sample rate".to_string());
    }
    let response = current.response;
    let mut best = (f64::INFINITY, 1.0);
    let steps = 60;
    for k in 0..=steps {
        let x = 0.5 * 40f64.powf(k as f64 / steps as f64);
        let fc = x * f_n;
        if fc > 0.4 * rate {
            break;
        }
        let e = error_power(&a, &psd, valley.1, fc, response);
        if e < best.0 {
            best = (e, x);
        }
    }
    let reference = error_power(&a, &psd, valley.1, current.cutoff_hz(params), response);
    Ok(CutoffChoice {
        settings: DiffSettings {
            response,
            cutoff: Cutoff::TimesNatural(best.1),
        },
        hz: best.1 * f_n,
        valley_hz: valley.1,
        predicted_rms: best.0.sqrt(),
        reference_rms: reference.sqrt(),
    })
}

/// Log-spaced points of the grid over 0.4-10 times f_n that [`by_gyro_reference`] starts
/// each search with (ratio 1.5 between points).
const GRID_POINTS: usize = 9;
/// Golden-section steps of [`by_gyro_reference`] between the best grid point's neighbours.
const GOLDEN_STEPS: usize = 6;
/// Cost evaluations [`by_gyro_reference`] makes: per algorithm the grid, then the
/// golden-section search (two inner points, one per step, both ends).
pub const EVALUATIONS: u64 = 2 * (GRID_POINTS + GOLDEN_STEPS + 4) as u64;

/// The cutoffs measured against the gyro's integral ([`super::reference`]), one per
/// algorithm: (multiple of f_n, RMS band error there \[rad\]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroCutoffs {
    /// Algorithm 1's (phi and phi'' alone).
    pub alg1: (f64, f64),
    /// Algorithm 2's (with the gyro): the shared `[differentiator]`, which Algorithm 3
    /// and the `kf_*` filters' measurement take too.
    pub alg2: (f64, f64),
}

/// The least of `cost` over multiples 0.4-10 of f_n: a log-spaced grid of [`GRID_POINTS`]
/// (the band error has several minima on a slow pendulum: zoo ride 12's alg1 at 0.4 and
/// 1.34 f_n, where a golden-section search alone may settle in the wrong one), then a
/// golden-section search between the best point's neighbours.
fn least(mut cost: impl FnMut(f64) -> f64) -> (f64, f64) {
    let (lo, hi) = (0.4f64, 10.0f64);
    let grid: Vec<f64> = (0..GRID_POINTS)
        .map(|k| lo * (hi / lo).powf(k as f64 / (GRID_POINTS - 1) as f64))
        .collect();
    let costs: Vec<f64> = grid.iter().map(|&x| cost(x)).collect();
    let i = (0..GRID_POINTS)
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .unwrap_or(0);
    let (a, b) = (
        grid[i.saturating_sub(1)],
        grid[(i + 1).min(GRID_POINTS - 1)],
    );
    let (x, c) = crate::peers::tune::golden_log(&mut cost, a, b, GOLDEN_STEPS);
    if c < costs[i] {
        (x, c)
    } else {
        (grid[i], costs[i])
    }
}

/// The cutoffs measured against the gyro's integral ([`super::reference`]): for Algorithm
/// 1 and Algorithm 2 apart, the multiple of the natural frequency in 0.4-10 with the least
/// band error (a grid, then a golden-section search; [`EVALUATIONS`] runs in all). Used whenever the log has a gyro;
/// the spectral rule of [`choose`] is the fallback.
///
/// Each cost evaluation ticks `budget`; past its deadline the cost is infinite (the
/// caller then keeps the other rule's cutoff).
///
/// Why: on the simulated scooter ride (60 s, seed 5) the spectral rule alone chose
/// 5.4 Hz where the default 2.8 Hz was better (alg1 0.99 deg against 0.56 deg): what it
/// calls tilt below its valley holds the floor's low-frequency translation too, which the
/// pendulum cannot tell from tilt. The gyro can. Apart, because one cutoff for both
/// (the least sum of their squared band errors) suited neither on slow pendulums: zoo
/// ride 12 (f_n 0.5 Hz) took 0.4 f_n, where alg1's error was 4.57 deg (1.34 f_n: 3.13)
/// and alg2's 4.56 (10 f_n: 1.49); each band error followed its true error within 15 %
/// over the whole range there.
pub fn by_gyro_reference(
    samples: &[pendtilt_core::Sample<f64>],
    alg1: &pendtilt_core::estimators::alg1::Alg1Settings<f64>,
    alg2: &pendtilt_core::estimators::alg2::Alg2Settings<f64>,
    bias: f64,
    skip: usize,
    budget: &mut super::search::Budget,
) -> GyroCutoffs {
    use pendtilt_core::estimators::alg1::Alg1;
    use pendtilt_core::estimators::alg2::Alg2;
    use pendtilt_core::estimators::front_end::FrontEndSettings;
    use pendtilt_core::PlanarEstimator;
    let reference = super::reference::integral(samples, bias);
    let mut run = |e: &mut dyn PlanarEstimator<f64>| -> f64 {
        if !budget.tick() {
            return f64::INFINITY;
        }
        let est: Vec<f64> = samples.iter().map(|s| e.update(s).theta).collect();
        super::reference::band_error(&est, &reference, samples, skip)
    };
    let at = |fe: &FrontEndSettings<f64>, x: f64| FrontEndSettings {
        differentiator: DiffSettings {
            response: alg2.front_end.differentiator.response,
            cutoff: Cutoff::TimesNatural(x),
        },
        ..*fe
    };
    let one = least(|x| {
        run(&mut Alg1::<f64>::new(
            pendtilt_core::estimators::alg1::Alg1Settings {
                front_end: at(&alg1.front_end, x),
            },
        ))
    });
    let two = least(|x| {
        run(&mut Alg2::<f64>::new(
            pendtilt_core::estimators::alg2::Alg2Settings {
                front_end: at(&alg2.front_end, x),
                ..*alg2
            },
        ))
    });
    GyroCutoffs {
        alg1: one,
        alg2: two,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lowpass_is_minus_three_db_at_the_cutoff_and_unity_at_dc() {
        for r in [
            Response::Butterworth,
            Response::Bessel,
            Response::CriticallyDamped,
        ] {
            let (p, _) = lowpass(r, 1.0);
            assert!((p - 0.5).abs() < 1e-6, "{r:?}: {p}");
            let (p0, m0) = lowpass(r, 1e-6);
            assert!((p0 - 1.0).abs() < 1e-9 && m0 < 1e-9);
            // |1 - L|^2 ~ (w tau)^2 at low frequency, tau the DC delay.
            let x = 1e-3;
            let (_, m) = lowpass(r, x);
            let tau = r.dc_delay(1.0);
            assert!((m / (x * tau).powi(2) - 1.0).abs() < 1e-2, "{r:?}");
        }
    }
}
