//! Where the estimators' defaults come from: RMS error of alg1 and alg2 against the true
//! tilt on simulated scooter rides, swept over the differentiator's cutoff (as a multiple
//! of the pendulum's natural frequency), its response, which phi enters the equation, and
//! where theta'' comes from (Eq 22 window or the matched differentiator).
//!
//! `cargo run --release -p pendtilt --example tuning_sweep [SECONDS] [SEEDS]`
use pendtilt::sim::planar::{simulate, Scenario};
use pendtilt_core::estimators::alg1::{Alg1, Alg1Settings};
use pendtilt_core::estimators::alg2::{Alg2, Alg2Settings};
use pendtilt_core::estimators::front_end::FrontEndSettings;
use pendtilt_core::estimators::theta_dd::ThetaDdSource;
use pendtilt_core::estimators::PhiSource;
use pendtilt_core::filters::diff::{Cutoff, DiffSettings, Response};
use pendtilt_core::{PendulumParams, PlanarEstimator};

fn rms(est: &mut dyn PlanarEstimator<f64>, rows: &[pendtilt::sim::planar::SimRow]) -> f64 {
    let (mut acc, mut n) = (0.0, 0usize);
    for r in rows {
        let e = est.update(&r.sample());
        if r.t >= 1.0 {
            acc += (e.theta - r.truth.theta).powi(2);
            n += 1;
        }
    }
    (acc / n as f64).sqrt().to_degrees()
}

/// Mean over `rides` of the RMS error \[deg\] of the estimator `make` builds, one fresh per
/// ride.
fn mean_rms<E: PlanarEstimator<f64>>(
    rides: &[Vec<pendtilt::sim::planar::SimRow>],
    make: impl Fn() -> E,
) -> f64 {
    rides.iter().map(|r| rms(&mut make(), r)).sum::<f64>() / rides.len() as f64
}

/// One row of the table: alg1, alg2 with each theta'' source and alg2 with delay
/// compensation, all with the front end `fe`.
fn row(
    rides: &[Vec<pendtilt::sim::planar::SimRow>],
    params: PendulumParams<f64>,
    fe: FrontEndSettings<f64>,
) -> [f64; 6] {
    let mut cols = [0.0; 6];
    let s1 = Alg1Settings { front_end: fe };
    cols[0] = mean_rms(rides, || Alg1::new(s1));
    for (k, src) in [
        ThetaDdSource::Matched,
        ThetaDdSource::Window { span: 0.010 },
        ThetaDdSource::Window { span: 0.030 },
        ThetaDdSource::Window { span: 0.060 },
    ]
    .into_iter()
    .enumerate()
    {
        let s2 = Alg2Settings {
            front_end: FrontEndSettings {
                theta_dd: src,
                ..fe
            },
            ..Alg2Settings::from_params(params)
        };
        cols[1 + k] = mean_rms(rides, || Alg2::<f64>::new(s2));
    }
    let s2 = Alg2Settings {
        front_end: fe,
        delay_compensation: true,
        ..Alg2Settings::from_params(params)
    };
    cols[5] = mean_rms(rides, || Alg2::<f64>::new(s2));
    cols
}

/// The scooter ride from the command line: `[SECONDS] [SEEDS] [SCENARIO TOML]`; returns
/// it with its length and seed count.
fn scenario(args: &[String]) -> anyhow::Result<(Scenario, f64, u64)> {
    let secs: f64 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(60.0);
    let seeds: u64 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(2);
    let mut sc = Scenario::named("scooter")?;
    sc.duration = secs;
    if let Some(text) = args.get(3) {
        // Scenario TOML overrides, e.g. a file written by `pendtilt simulate --print-scenario`.
        sc = sc.merged(&std::fs::read_to_string(text)?, text)?.0;
        sc.duration = secs;
    }
    Ok((sc, secs, seeds))
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (sc, secs, seeds) = scenario(&args)?;
    let rides: Vec<_> = (1..=seeds)
        .map(|s| simulate(&sc, s))
        .collect::<Result<_, _>>()?;
    let params = sc.physical().normalised();
    println!(
        "scooter, {secs} s x {seeds} seeds; pendulum f_n = {:.2} Hz; RMS error [deg] (mean over seeds)",
        params.natural_frequency_hz()
    );
    println!(
        "{:<17} {:<9} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}",
        "response", "phi", "x f_n", "alg1", "alg2 M", "alg2 W10", "alg2 W30", "alg2 W60", "alg2+dc"
    );
    for response in [
        Response::Butterworth,
        Response::Bessel,
        Response::CriticallyDamped,
    ] {
        for phi in [PhiSource::Raw, PhiSource::Filtered] {
            for ratio in [0.8, 1.0, 1.3, 1.7, 2.2, 3.0, 5.0, 10.0] {
                let fe = FrontEndSettings {
                    differentiator: DiffSettings {
                        response,
                        cutoff: Cutoff::TimesNatural(ratio),
                    },
                    phi,
                    ..FrontEndSettings::from_params(params)
                };
                let cols = row(&rides, params, fe);
                println!(
                    "{:<17} {:<9} {:>6.1} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>8.4}",
                    format!("{response:?}"),
                    format!("{phi:?}"),
                    ratio,
                    cols[0],
                    cols[1],
                    cols[2],
                    cols[3],
                    cols[4],
                    cols[5]
                );
            }
        }
    }
    Ok(())
}
