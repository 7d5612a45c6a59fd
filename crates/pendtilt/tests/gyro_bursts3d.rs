//! Gyro bursts on the 3-D model-based filters: 100 missing readings of one gyro axis
//! (an impossible 1e6 rad/s, read as missing) on the scooter3d ride, seeds 1, 3 and 5, each
//! axis, from 8, 12 and 16 s: 27 bursts. ekf3d and ukf3d bridge the missing axis by its
//! low-passed rate (the axes read stay as read), keep their gyro bias for `BIAS_HOLD` (2 s)
//! after, and at the first reading after a hold of 50 ms or more loosen roll and pitch
//! (to 0.5 deg after missing readings), uncorrelated with the rest, so the encoders carry
//! them back (`ModelBased::reacquire`). Measured (54 runs: 27 bursts, ekf3d and ukf3d):
//! back within 0.05 deg (inclination) of the fault-free run after 0.90-1.96 s, all 54
//! within 2 s, where they took 0.43-10.23 s, 12 of 54 within 2 s (all three axes bridged
//! for one missing, the bias held 0.5 s, no re-acquisition); loosened to the start's 2 deg,
//! 1.18-2.08 s, 43 of 54.
//!
//! The 3-D peers (VQF, madgwick3d, mahony3d, fusion3d) have their own sweep, bursts
//! anywhere from 2 s to 10 s (`the_3d_peers_after_a_burst_of_100_missing_gyro_readings_anywhere`).
//!
//! `cargo test --release -p pendtilt --test gyro_bursts3d -- --nocapture` prints each.
use std::path::{Path, PathBuf};

use pendtilt::core::spatial::attitude::inclination_error;

mod common;
use common::{pendtilt, s};

/// Per row: roll and pitch of `name` from an estimates CSV.
fn attitude(path: &Path, name: &str) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |c: &str| head.iter().position(|h| *h == c).unwrap();
    let (t, r, p) = (
        col("t"),
        col(&format!("{name}_roll")),
        col(&format!("{name}_pitch")),
    );
    lines
        .map(|l| {
            let c: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            (c[t], c[r], c[p])
        })
        .collect()
}

/// A scooter3d ride of `secs` seconds with seed `seed` in `dir`: its log, rig file and
/// scenario file.
fn ride(dir: &Path, seed: u64, secs: &str) -> (PathBuf, PathBuf, PathBuf) {
    let log = dir.join(format!("ride{seed}.csv"));
    let seed_text = seed.to_string();
    let args = [
        "simulate",
        "--scenario",
        "scooter3d",
        "--duration",
        secs,
        "--seed",
        &seed_text,
        "-q",
        "-o",
        s(&log),
    ];
    let o = pendtilt(&args);
    assert!(o.status.success());
    let rig = dir.join(format!("ride{seed}.rig.toml"));
    let scen = dir.join(format!("ride{seed}.scenario.toml"));
    (log, rig, scen)
}

/// `estimate input` with the ride's rig and scenario, only the estimators `only`, into
/// `out`.
fn estimate_only(rig: &Path, scen: &Path, only: &str, input: &Path, out: &Path) {
    let o = pendtilt(&[
        "estimate",
        s(input),
        "-p",
        s(rig),
        "--scenario",
        s(scen),
        "--only",
        only,
        "-o",
        s(out),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn ekf3d_and_ukf3d_are_back_within_2_s_after_100_missing_readings_of_one_gyro_axis() {
    let dir = tempfile::tempdir().unwrap();
    let mut backs = Vec::new();
    for seed in [1u64, 3, 5] {
        let (log, rig, scen) = ride(dir.path(), seed, "30");
        let estimate =
            |input: &Path, out: &Path| estimate_only(&rig, &scen, "ekf3d,ukf3d", input, out);
        let clean_out = dir.path().join("clean.csv");
        estimate(&log, &clean_out);
        let text = std::fs::read_to_string(&log).unwrap();
        let mut lines: Vec<Vec<String>> = text
            .lines()
            .map(|l| l.split(',').map(String::from).collect())
            .collect();
        for axis in ["gyro_x", "gyro_y", "gyro_z"] {
            let j = lines[0].iter().position(|h| h == axis).unwrap();
            for k0 in [8000usize, 12000, 16000] {
                let kept: Vec<String> = (k0..k0 + 100).map(|k| lines[k + 1][j].clone()).collect();
                for k in k0..k0 + 100 {
                    lines[k + 1][j] = "1e6".into();
                }
                let bad = dir.path().join("bad.csv");
                let body: Vec<String> = lines.iter().map(|l| l.join(",")).collect();
                std::fs::write(&bad, body.join("\n") + "\n").unwrap();
                for (k, v) in (k0..k0 + 100).zip(kept) {
                    lines[k + 1][j] = v;
                }
                let bad_out = dir.path().join("bad_est.csv");
                estimate(&bad, &bad_out);
                let t_end = (k0 + 100) as f64 * 1e-3;
                for name in ["ekf3d", "ukf3d"] {
                    let (c, b) = (attitude(&clean_out, name), attitude(&bad_out, name));
                    assert_eq!(c.len(), b.len(), "a row was lost");
                    let mut last_out = None;
                    for (x, y) in c.iter().zip(&b) {
                        if x.0 < t_end {
                            continue;
                        }
                        let d = inclination_error(x.1, x.2, y.1, y.2).to_degrees();
                        if d.is_nan() || d > 0.05 {
                            last_out = Some(x.0);
                        }
                    }
                    let back = last_out.map_or(0.0, |t| t - t_end + 1e-3);
                    println!("seed {seed} {axis} from {k0} ms: {name} back after {back:.2} s");
                    backs.push(back);
                }
            }
        }
    }
    let within = backs.iter().filter(|b| **b <= 2.0).count();
    let worst = backs.iter().cloned().fold(0.0, f64::max);
    println!(
        "within 2 s: {within} of {}; worst {worst:.2} s",
        backs.len()
    );
    assert!(worst <= 2.0, "{backs:?}");
    assert_eq!(within, backs.len());
}

/// The 3-D peers, each a gyro + accelerometer filter that holds a missing gyro axis at its
/// 25 ms mean (`Imu6`).
const PEERS: [&str; 4] = ["vqf", "madgwick3d", "mahony3d", "fusion3d"];

/// Time \[s\] after `t_end` from which `bad` stays within 0.05 deg (inclination) of
/// `clean` to the log's end (infinite: not within at the end), and the largest difference
/// \[deg\] from 2 s after `t_end` on.
fn back_after(clean: &[(f64, f64, f64)], bad: &[(f64, f64, f64)], t_end: f64) -> (f64, f64) {
    assert_eq!(clean.len(), bad.len(), "a row was lost");
    let mut last_out = None;
    let mut after_2s = 0.0f64;
    for (i, (x, y)) in clean.iter().zip(bad).enumerate() {
        if x.0 < t_end {
            continue;
        }
        let d = inclination_error(x.1, x.2, y.1, y.2).to_degrees();
        let d = if d.is_finite() { d } else { f64::INFINITY };
        if d > 0.05 {
            last_out = Some(i);
        }
        if x.0 >= t_end + 2.0 {
            after_2s = after_2s.max(d);
        }
    }
    let back = match last_out {
        None => 0.0,
        Some(i) if i + 1 == clean.len() => f64::INFINITY,
        Some(i) => clean[i + 1].0 - t_end,
    };
    (back, after_2s)
}

/// One burst's outcome for one peer: (case, peer, time back \[s\], largest difference
/// from 2 s after the burst on \[deg\]).
type PeerBack = (&'static str, &'static str, f64, f64);

/// The log's `lines` with `value` in the columns `cols` of the 100 rows from row `k0`,
/// written to `path`.
fn write_burst(lines: &[Vec<String>], cols: &[usize], value: &str, k0: usize, path: &Path) {
    let mut bad_lines = lines.to_vec();
    for row in bad_lines.iter_mut().skip(k0 + 1).take(100) {
        for &j in cols {
            row[j] = value.to_string();
        }
    }
    let body: Vec<String> = bad_lines.iter().map(|l| l.join(",")).collect();
    std::fs::write(path, body.join("\n") + "\n").unwrap();
}

/// The peers' sweep on the 14 s ride of `seed`: gyro_x at 1e6, then all three gyro cells
/// empty, 100 rows from each second of 2-10 s; each burst's outcome per peer, printed.
fn peer_backs(dir: &Path, seed: u64) -> Vec<PeerBack> {
    let mut backs = Vec::new();
    let (log, rig, scen) = ride(dir, seed, "14");
    let only = PEERS.join(",");
    let estimate = |input: &Path, out: &Path| estimate_only(&rig, &scen, &only, input, out);
    let clean_out = dir.join("clean.csv");
    estimate(&log, &clean_out);
    let clean: Vec<_> = PEERS.iter().map(|p| attitude(&clean_out, p)).collect();
    let text = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    let col = |c: &str| lines[0].iter().position(|h| h == c).unwrap();
    let cases: [(&str, Vec<usize>, &str); 2] = [
        ("gyro_x", vec![col("gyro_x")], "1e6"),
        (
            "gyro_xyz",
            vec![col("gyro_x"), col("gyro_y"), col("gyro_z")],
            "",
        ),
    ];
    for (case, cols, value) in &cases {
        for k0 in (2000usize..=10_000).step_by(1000) {
            let bad = dir.join("bad.csv");
            write_burst(&lines, cols, value, k0, &bad);
            let bad_out = dir.join("bad_est.csv");
            estimate(&bad, &bad_out);
            let t_end = (k0 + 100) as f64 * 1e-3;
            for (name, c) in PEERS.iter().zip(&clean) {
                let (back, after) = back_after(c, &attitude(&bad_out, name), t_end);
                println!(
                    "seed {seed} {case} from {k0} ms: {name} back after {back:.2} s \
                     ({after:.3} deg from 2 s on)"
                );
                backs.push((*case, *name, back, after));
            }
        }
    }
    backs
}

/// Peer `name`'s outcomes over the sweep of `case`, printed and held to its measured
/// figures with a margin.
fn assert_peer_comes_back(case: &str, name: &str, backs: &[PeerBack]) {
    let mut b: Vec<f64> = backs
        .iter()
        .filter(|x| x.0 == case && x.1 == name)
        .map(|x| x.2)
        .collect();
    let worst_after = backs
        .iter()
        .filter(|x| x.0 == case && x.1 == name)
        .map(|x| x.3)
        .fold(0.0, f64::max);
    b.sort_by(f64::total_cmp);
    let within = b.iter().filter(|x| **x <= 2.0).count();
    let rms_after = (backs
        .iter()
        .filter(|x| x.0 == case && x.1 == name)
        .map(|x| x.3 * x.3)
        .sum::<f64>()
        / b.len() as f64)
        .sqrt();
    let worst = b[b.len() - 1];
    println!(
        "{case} {name}: within 2 s in {within} of {}, median {:.2} s, worst {worst:.2} s; \
         from 2 s on {rms_after:.3} deg RMS, at most {worst_after:.3}",
        b.len(),
        b[b.len() / 2],
    );
    let what = format!("{case} {name}: {b:?}");
    let all_three = case == "gyro_xyz";
    match name {
        // Forgets any angle error within ms (measured at most 0.38 s).
        "madgwick3d" => assert!(worst <= 0.6, "{what}"),
        // Measured at most 0.42 s; 0.42 s and 0.47 s (the bridge's window).
        "mahony3d" | "vqf" => assert!(worst <= 1.0, "{what}"),
        // Measured 23; 17 of 27 within 2 s, 0.037; 0.051 deg RMS from 2 s on, at
        // most 0.095; 0.095 (0.064; 0.070 and 0.123; 0.114 with the line).
        _ => {
            assert!(within >= if all_three { 15 } else { 21 }, "{what}");
            assert!(rms_after <= 0.065 && worst_after <= 0.13, "{what}");
        }
    }
}

/// 100 missing gyro readings anywhere in a ride, for the 3-D peers: gyro_x 1e6 (impossible,
/// read as missing) and, separately, all three gyro cells empty, on the scooter3d ride
/// (14 s), seeds 1, 2 and 3, from 2 s to 10 s every second (27 bursts each). Per peer: the
/// time after the burst back within 0.05 deg (inclination) of the fault-free run, and the
/// largest difference from 2 s after it on.
///
/// Each peer holds a missing axis at its 25 ms mean and, once `BRIDGE_WINDOW` (0.42 s) of
/// readings have come after the gap, takes the core's bridge over it
/// (`Imu6::with_gap_bridge`: the angle through the gap fitted to the readings on either
/// side, `core::estimators::gap_fit`), less what its gain forgot since (Mahony kp, VQF
/// 1 / tau_acc, fusion3d its gain; Madgwick none). Measured (gyro_x; all three axes)
/// within 2 s: with the hold alone, Mahony 17; 9, VQF 12; 5, fusion3d 12; 3; with the line
/// between the 25 ms means on either side, Mahony 27; 27, VQF 22; 18, fusion3d
/// 10; 6; with the fit, Mahony and VQF 27; 27 (at most 0.42 s; 0.47 s: the window), fusion3d
/// 23; 17, 0.037; 0.051 deg RMS from 2 s on (0.064; 0.070 with the line), at most 0.095;
/// 0.095. Madgwick 27; 27 throughout (at most 0.29 s; 0.38 s). fusion3d's acceleration
/// rejection leaves it a gain of about 0.085 /s on this ride (docs/reliability.md section
/// 8), and a kick of its angle as small as the fit's residual can grow: see
/// `fusion3d_keeps_a_kick_of_its_angle`. The assertions hold these figures with a margin.
///
/// `cargo test --release -p pendtilt --test gyro_bursts3d -- --nocapture anywhere` prints
/// each.
#[test]
fn the_3d_peers_after_a_burst_of_100_missing_gyro_readings_anywhere() {
    let dir = tempfile::tempdir().unwrap();
    // (case, peer) -> (back [s], deg from 2 s on) per burst.
    let mut backs: Vec<PeerBack> = Vec::new();
    for seed in [1u64, 2, 3] {
        backs.extend(peer_backs(dir.path(), seed));
    }
    for case in ["gyro_x", "gyro_xyz"] {
        for name in PEERS {
            assert_peer_comes_back(case, name, &backs);
        }
    }
}

/// Why fusion3d misses 2 s after some bursts that Mahony and VQF meet: on this ride its
/// acceleration rejection leaves it a gain of about 0.085 /s, and which readings it rejects
/// follows its own estimate, so an angle error does not simply decay: a kick of one gyro_x
/// reading worth `kick` degrees of roll (the scooter3d ride, seeds 1-3, at 2-10 s) is
/// carried and can grow. Measured: a 0.01 deg kick is back within 0.05 deg at once in all
/// 27 (at most 0.017 deg from 2 s on); a 0.03 deg kick (the gap fit's largest residual on
/// these rides is 0.037 deg) never comes back within 0.05 deg in 2 of 27, and takes 4.9 s
/// in a third. No bridge that leaves 0.03 deg can hold fusion3d to 2 s everywhere.
#[test]
fn fusion3d_keeps_a_kick_of_its_angle() {
    let dir = tempfile::tempdir().unwrap();
    let mut missed = [0usize; 2];
    let mut worst_small = 0.0f64;
    for seed in [1u64, 2, 3] {
        let (log, rig, scen) = ride(dir.path(), seed, "14");
        let clean_out = dir.path().join("clean.csv");
        estimate_only(&rig, &scen, "fusion3d", &log, &clean_out);
        let clean = attitude(&clean_out, "fusion3d");
        let text = std::fs::read_to_string(&log).unwrap();
        let lines: Vec<Vec<String>> = text
            .lines()
            .map(|l| l.split(',').map(String::from).collect())
            .collect();
        let gx = lines[0].iter().position(|h| h == "gyro_x").unwrap();
        for (i, kick) in [0.01f64, 0.03].into_iter().enumerate() {
            for k0 in (2000usize..=10_000).step_by(1000) {
                let mut bad = lines.clone();
                let g: f64 = bad[k0 + 1][gx].parse().unwrap();
                // One 1 ms reading turned by `kick` degrees more.
                bad[k0 + 1][gx] = (g + kick.to_radians() / 1e-3).to_string();
                let path = dir.path().join("kicked.csv");
                let body: Vec<String> = bad.iter().map(|l| l.join(",")).collect();
                std::fs::write(&path, body.join("\n") + "\n").unwrap();
                let out = dir.path().join("kicked_est.csv");
                estimate_only(&rig, &scen, "fusion3d", &path, &out);
                let (back, after) =
                    back_after(&clean, &attitude(&out, "fusion3d"), k0 as f64 * 1e-3);
                println!("seed {seed} kick {kick} deg at {k0} ms: back after {back:.2} s ({after:.3} deg from 2 s on)");
                if back > 2.0 {
                    missed[i] += 1;
                }
                if i == 0 {
                    worst_small = worst_small.max(after);
                }
            }
        }
    }
    println!("kicks of 0.01 / 0.03 deg beyond 2 s: {missed:?} of 27 each");
    // A kick well under the bound is carried, not lost, and stays under it.
    assert_eq!(missed[0], 0, "{missed:?}");
    assert!(worst_small > 0.005 && worst_small < 0.04, "{worst_small}");
    // Three times larger, still under the bound, it is not forgotten in 2 s everywhere.
    assert!(missed[1] >= 1, "{missed:?}");
}
