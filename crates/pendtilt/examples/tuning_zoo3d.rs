//! The zoo of unseen 3-D rigs ([`pendtilt::tune::spatial::zoo`]): seeded scooter3d, ship3d
//! and ride3d logs on drawn pendulums and sensor grades; for each, ekf3d's RMS inclination
//! error (MODEL.md 7.9, from the scenario's `score_from`) at the rig's defaults,
//! self-tuned by the 3-D tune (no truth) and tuned against the truth (the reference); on
//! the scooter rides the best peer tuned against the truth. Then the median and worst of
//! self-tuned / reference over the rides the rules were chosen on (`--chosen`, default the
//! first 9) and the rest (held out).
//!
//! `cargo run --release -p pendtilt --example tuning_zoo3d [-- --rides N --seconds S --chosen K]`
//! (default 15 rides of 60 s, the first 9 chosen on).
use pendtilt::tune::spatial::zoo::{ride, score, Score3d};
use rayon::prelude::*;

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
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

fn summary(label: &str, s: &[&Score3d]) {
    let r: Vec<f64> = s.iter().map(|s| s.tuned / s.reference).collect();
    let d: Vec<f64> = s.iter().map(|s| s.defaults / s.reference).collect();
    let worst = r.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    println!(
        "{label} ({} rides): self-tuned / reference median {:.2}, worst {:.2} (targets 1.3, 2); \
         defaults / reference median {:.2}",
        s.len(),
        median(r),
        worst,
        median(d)
    );
}

fn main() -> anyhow::Result<()> {
    let rides: u64 = arg("--rides", 15)?;
    let seconds: f64 = arg("--seconds", 60.0)?;
    let chosen: u64 = arg("--chosen", 9)?;
    println!("{rides} rides of {seconds} s at 1 kHz; ekf3d RMS inclination error [deg]");
    println!("| ride | defaults | self-tuned | (adapt off) | reference | self/ref | best peer (truth-tuned) | tune [s] | rig |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let scores: Vec<Score3d> = (0..rides)
        .into_par_iter()
        .map(|k| {
            let r = ride(k, seconds);
            let peers = r.scenario.rig.mounting.speed_at == [0.0, 0.0, -0.25];
            score(&r, peers)
        })
        .collect();
    let d = |x: f64| x.to_degrees();
    for s in &scores {
        let peer = s
            .best_peer
            .map_or("-".to_string(), |(n, e)| format!("{n} {:.4}", d(e)));
        println!(
            "| {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.2} | {peer} | {:.1} | {} |",
            s.ride.index,
            d(s.defaults),
            d(s.tuned),
            d(s.tuned_fixed),
            d(s.reference),
            s.tuned / s.reference,
            s.tune_seconds,
            s.ride.description
        );
    }
    if std::env::args().any(|a| a == "--settings") {
        for s in &scores {
            let f = |x: &pendtilt::core::spatial::ekf::Settings<f64>| {
                format!(
                    "vib {:.4} jit {:.2e} gyro {:.2e}",
                    x.environment.vibration_density, x.encoder_jitter, x.sensors.gyro_density
                )
            };
            println!(
                "ride {}: tuned {} | reference {} | true gyro {:.2e}",
                s.ride.index,
                f(&s.tuned_settings),
                f(&s.reference_settings),
                s.ride.scenario.sensors.gyro_noise_density
            );
        }
    }
    let (a, b): (Vec<&Score3d>, Vec<&Score3d>) = scores.iter().partition(|s| s.ride.index < chosen);
    summary("chosen on", &a);
    summary("held out", &b);
    for s in scores.iter().filter(|s| s.best_peer.is_some()) {
        let (n, e) = s.best_peer.unwrap_or(("none", f64::INFINITY));
        let ok = s.tuned <= 0.05f64.to_radians() && s.tuned <= e / 5.0;
        println!(
            "scooter ride {} ({}): self-tuned {:.4} deg, best peer {n} {:.4} (1/{:.1}): {}",
            s.ride.index,
            if s.ride.index < chosen {
                "chosen on"
            } else {
                "held out"
            },
            d(s.tuned),
            d(e),
            e / s.tuned,
            if ok { "reached" } else { "NOT reached" }
        );
    }
    Ok(())
}
