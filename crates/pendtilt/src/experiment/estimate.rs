//! Runs the estimator bank (and the extra variants of the experiment) over a ride.
use pendtilt_core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt_core::{Estimate, PlanarEstimator};

use crate::bank::planar::{Bank, BankSettings, Inputs};

use super::progress::{Progress, CHUNK};
use super::rides::Ride;

/// Name of the delay-compensated Algorithm 2 (not in the paper; the bank's registry has it
/// too, and then the bank's runs instead of [`alg2_delay_compensated`]).
pub const ALG2_DELAY_COMPENSATED: &str = "alg2_dc";

/// An estimator that is not in the bank's registry, run beside it.
pub struct Extra {
    /// Output name.
    pub name: String,
    /// The estimator.
    pub estimator: Box<dyn PlanarEstimator<f64> + Send>,
}

/// Algorithm 2 with [`Alg2Settings::delay_compensation`] on, named [`ALG2_DELAY_COMPENSATED`].
pub fn alg2_delay_compensated(settings: &BankSettings) -> Extra {
    Extra {
        name: ALG2_DELAY_COMPENSATED.to_string(),
        estimator: Box::new(Alg2::<f64>::new(Alg2Settings {
            delay_compensation: true,
            ..settings.rig.alg2_settings()
        })),
    }
}

/// Named output series, in column order.
pub type Series = Vec<(String, Vec<f64>)>;

/// Runs every bank estimator whose inputs `inputs` provides, then the extras (those whose
/// name the bank does not already have), over the ride's samples; returns one series per
/// output, each as long as the ride.
pub fn run_estimators(
    ride: &Ride,
    settings: &BankSettings,
    inputs: Inputs,
    mut extras: Vec<Extra>,
    progress: &dyn Progress,
) -> Result<Series, String> {
    let mut bank = Bank::new(settings, inputs, None)?;
    // An extra that the registry has gained since is run once, by the bank.
    extras.retain(|x| !bank.names().iter().any(|n| *n == x.name));
    let n = ride.len();
    let mut out: Vec<Vec<f64>> = vec![Vec::with_capacity(n); bank.names().len() + extras.len()];
    let mut est: Vec<Estimate<f64>> = Vec::with_capacity(bank.names().len());
    progress.stage(
        &format!("estimating on {} ({} estimators)", ride.label, out.len()),
        n as u64,
    );
    for (k, s) in ride.samples.iter().enumerate() {
        let clipped = ride.clipped.get(k).copied().unwrap_or_default();
        bank.update_clipped(s, clipped, &mut est);
        for (col, e) in out.iter_mut().zip(&est) {
            col.push(e.theta);
        }
        for (col, x) in out[est.len()..].iter_mut().zip(extras.iter_mut()) {
            col.push(x.estimator.update(s).theta);
        }
        if (k as u64 + 1) % CHUNK == 0 {
            progress.advance(CHUNK);
        }
    }
    progress.advance(n as u64 % CHUNK);
    let names = bank
        .names()
        .iter()
        .map(|s| s.to_string())
        .chain(extras.iter().map(|x| x.name.clone()));
    Ok(names.zip(out).collect())
}
