//! The accelerometer's Kalman filters on the zoo of unseen rigs: for each
//! seeded ride of [`pendtilt::tune::zoo`], the RMS error after 2 s of `kf_accel`,
//! `kf_fused` and `kf_alg2` as `estimate` builds them from the rig file, at the defaults and
//! self-tuned (no true angle); then per filter the median and worst of tuned / defaults,
//! and kf_fused against kf_alg2 (the accelerometer beside Algorithm 2 should not cost).
//!
//! `cargo run --release -p pendtilt --example tuning_zoo_accel [-- --rides N --seconds S]`
//! (default 20 rides of 40 s, the zoo's).
use pendtilt::bank::planar::{Bank, BankSettings, Inputs};
use pendtilt::config::RigConfig;
use pendtilt::tune::zoo::ride;
use pendtilt::tune::zoo::score::RideLog;
use pendtilt::tune::{rig_file, tune, Options, Start};

/// The filters scored, and what they read.
const NAMES: [&str; 3] = ["kf_accel", "kf_fused", "kf_alg2"];
const NEEDED: [&str; 5] = ["accel", "alg2", "kf_accel", "kf_fused", "kf_alg2"];

/// `--name VALUE` from the command line, or `default`.
fn arg<T: std::str::FromStr>(name: &str, default: T) -> T {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// RMS error \[deg\] after the log's skip of each of [`NAMES`] with `rig`.
fn rms(rig: &RigConfig, log: &RideLog) -> anyhow::Result<[f64; 3]> {
    let only: Vec<String> = NEEDED.iter().map(|s| s.to_string()).collect();
    let mut bank = Bank::new(
        &BankSettings::from_rig(rig.clone()),
        Inputs::ALL,
        Some(&only),
    )
    .map_err(anyhow::Error::msg)?;
    let cols = NAMES.map(|n| bank.names().iter().position(|b| *b == n));
    let mut sums = [(0.0, 0usize); 3];
    let mut out = Vec::new();
    for (k, (s, t)) in log.samples.iter().zip(&log.truth).enumerate() {
        bank.update(s, &mut out);
        if k < log.skip {
            continue;
        }
        for (acc, c) in sums.iter_mut().zip(cols) {
            let e = c.map_or(f64::NAN, |i| out[i].theta - t);
            if e.is_finite() {
                acc.0 += e * e;
                acc.1 += 1;
            }
        }
    }
    Ok(sums.map(|(s, n)| (s / n as f64).sqrt().to_degrees()))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

fn main() -> anyhow::Result<()> {
    let rides: u64 = arg("--rides", 20);
    let seconds: f64 = arg("--seconds", 40.0);
    println!("{rides} rides of {seconds} s; RMS error after 2 s [deg]: defaults -> self-tuned");
    let (mut accel, mut fused, mut beside) = (Vec::new(), Vec::new(), Vec::new());
    for i in 1..=rides {
        let r = ride(i, seconds);
        let log = RideLog::simulate(&r.scenario, r.index);
        let rig = r.scenario.rig()?;
        let t = tune(&log.samples, &Start::from_rig(&rig), &Options::default());
        let (d, u) = (rms(&rig, &log)?, rms(&rig_file::tuned_rig(&rig, &t), &log)?);
        println!(
            "{i:2} kf_accel {:.4} -> {:.4} | kf_fused {:.4} -> {:.4} | kf_alg2 {:.4} -> {:.4} | {}",
            d[0], u[0], d[1], u[1], d[2], u[2], r.description
        );
        accel.push(u[0] / d[0]);
        fused.push(u[1] / d[1]);
        beside.push(u[1] / u[2]);
    }
    let worst = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    for (what, v) in [
        ("kf_accel tuned / defaults", &accel),
        ("kf_fused tuned / defaults", &fused),
        ("kf_fused / kf_alg2, both tuned", &beside),
    ] {
        println!(
            "{what}: median {:.2}, worst {:.2}",
            median(v.clone()),
            worst(v)
        );
    }
    Ok(())
}
