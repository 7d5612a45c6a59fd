//! The zoo of unseen rigs: seeded simulated rides with random rigs, sensors,
//! vibration and motions ([`pendtilt::tune::zoo`]); for each, the RMS error of ekf,
//! kf_alg2, alg1 and alg2 at the defaults, self-tuned (no true angle) and tuned by a
//! brute-force grid against the true angle (the oracle); then the median and worst ratios
//! per estimator against the targets.
//!
//! Then the planar ekf's defaults against its self-tuned result: the median and worst of
//! defaults / self-tuned over the rides the rules were chosen on (1-14) and the held-out
//! ones (15-20), with the adaptation (the defaults) and without it (`[ekf] adapt = false`,
//! the defaults as they were before it; docs/adaptation.md).
//!
//! Last, the scooter target: the self-tuned ekf on the 60 s scooter ride (seed 5) against
//! the peers with their gains searched against the true angle.
//!
//! `cargo run --release -p pendtilt --example tuning_zoo [-- --rides N --seconds S]`
//! (default 20 rides of 40 s).
use pendtilt::peers::tune::{search_peer_gains, Log};
use pendtilt::sim::planar::Scenario;
use pendtilt::tune::zoo::ride;
use pendtilt::tune::zoo::score::{bank_rms, RideLog};
use pendtilt::tune::zoo::score::{score, RideScore, ESTIMATORS};
use pendtilt::tune::{rig_file, tune, Options, Start};

/// `--name VALUE` from the command line, parsed, or `default`.
fn arg<T: std::str::FromStr>(name: &str, default: T) -> anyhow::Result<T> {
    let args: Vec<String> = std::env::args().collect();
    match args.iter().position(|a| a == name) {
        Some(i) => args
            .get(i + 1)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| anyhow::anyhow!("{name} needs a number")),
        None => Ok(default),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn worst(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

fn print_ride(s: &RideScore) {
    let d = |x: f64| x.to_degrees();
    let cells: Vec<String> = (0..4)
        .map(|i| {
            format!(
                "{:.4} {:.4} {:.4}",
                d(s.defaults[i]),
                d(s.tuned[i]),
                d(s.oracle[i])
            )
        })
        .collect();
    println!(
        "| {} | {} | {:.4} | {:.1} | {} |",
        s.ride.index,
        cells.join(" | "),
        d(s.defaults_fixed[0]),
        s.tune_seconds,
        s.ride.description
    );
}

/// Scores `rides` rides of `seconds` s, printing each ride's row as it is scored.
fn score_rides(rides: u64, seconds: f64) -> Vec<RideScore> {
    println!(
        "{rides} rides of {seconds} s at 1 kHz; RMS error [deg]: defaults / self-tuned / oracle"
    );
    println!(
        "| ride | {} | ekf def, adapt off | tune [s] | rig |",
        ESTIMATORS
            .iter()
            .map(|e| format!("{e} def / tuned / oracle"))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut scores = Vec::new();
    for k in 1..=rides {
        let s = score(&ride(k, seconds));
        print_ride(&s);
        scores.push(s);
    }
    scores
}

/// Per estimator: self-tuned against the oracle and against the defaults, and the rides
/// where tuning made it worse.
fn print_ratios(scores: &[RideScore]) {
    println!();
    println!("| estimator | tuned/oracle median | worst | tuned/defaults median | worst | rides where tuned > 1.05 x defaults |");
    println!("|---|---|---|---|---|---|");
    for (i, name) in ESTIMATORS.iter().enumerate() {
        let to: Vec<f64> = scores.iter().map(|s| s.tuned[i] / s.oracle[i]).collect();
        let td: Vec<f64> = scores.iter().map(|s| s.tuned[i] / s.defaults[i]).collect();
        let bad: Vec<String> = scores
            .iter()
            .zip(&td)
            .filter(|(_, r)| **r > 1.05)
            .map(|(s, r)| format!("{} ({r:.2})", s.ride.index))
            .collect();
        println!(
            "| {name} | {:.2} | {:.2} | {:.2} | {:.2} | {} |",
            median(to.clone()),
            worst(&to),
            median(td.clone()),
            worst(&td),
            if bad.is_empty() {
                "none".to_string()
            } else {
                bad.join(", ")
            }
        );
    }
}

/// The ekf's defaults against its self-tuned result, with the adaptation and without, on
/// the rides its rules were chosen on, the held-out ones and all.
fn print_ekf_defaults(scores: &[RideScore]) {
    println!(
        "\n| ekf defaults / self-tuned | rides | median | worst | adapt off: median | worst |"
    );
    println!("|---|---|---|---|---|---|");
    for (label, range) in [
        ("chosen on", 1..=14),
        ("held out", 15..=20),
        ("all", 1..=u64::MAX),
    ] {
        let part: Vec<&RideScore> = scores
            .iter()
            .filter(|s| range.contains(&s.ride.index))
            .collect();
        if part.is_empty() {
            continue;
        }
        let on: Vec<f64> = part.iter().map(|s| s.defaults[0] / s.tuned[0]).collect();
        let off: Vec<f64> = part
            .iter()
            .map(|s| s.defaults_fixed[0] / s.tuned[0])
            .collect();
        println!(
            "| {label} | {} | {:.2} | {:.2} | {:.2} | {:.2} |",
            part.len(),
            median(on.clone()),
            worst(&on),
            median(off.clone()),
            worst(&off)
        );
    }
}

fn main() -> anyhow::Result<()> {
    let rides: u64 = arg("--rides", 20)?;
    let seconds: f64 = arg("--seconds", 40.0)?;
    let scores = score_rides(rides, seconds);
    print_ratios(&scores);
    print_ekf_defaults(&scores);
    let t: Vec<f64> = scores.iter().map(|s| s.tune_seconds).collect();
    if !t.is_empty() {
        println!(
            "\nself-tuning wall time per ride: median {:.2} s, worst {:.2} s",
            median(t.clone()),
            worst(&t)
        );
    }
    scooter_against_peers()
}

/// The self-tuned ekf on the 60 s scooter ride (seed 5) against the best-tuned peers.
fn scooter_against_peers() -> anyhow::Result<()> {
    let sc = Scenario::named("scooter")?;
    let log = RideLog::simulate(&sc, 5);
    let rig = sc.rig()?;
    let t = tune(&log.samples, &Start::from_rig(&rig), &Options::default());
    let ekf = bank_rms(&rig_file::tuned_rig(&rig, &t), &log)[0];
    let p = search_peer_gains(
        &Log {
            samples: &log.samples,
            truth: &log.truth,
            skip: log.skip,
        },
        20,
    );
    let best = p.madgwick_beta.1.min(p.mahony.1).min(p.complementary_tau.1);
    println!(
        "\nscooter 60 s seed 5 [deg]: self-tuned ekf {:.4}; peers tuned against the truth: \
         madgwick {:.4}, mahony {:.4}, complementary {:.4}; ekf / best peer = 1/{:.1}",
        ekf.to_degrees(),
        p.madgwick_beta.1.to_degrees(),
        p.mahony.1.to_degrees(),
        p.complementary_tau.1.to_degrees(),
        best / ekf
    );
    Ok(())
}
