//! Sensor gaps: short ones bridged, a gap longer than the restart gap restarts the
//! estimators that read the sensor as if they had started there.
use crate::common::plausibility::{
    assert_nothing_poisoned, assert_nothing_poisoned_but, cells, madgwick_resolution_deg, print,
    recovery, ride, run, text, Run, TOLERANCE_DEG,
};
use pendtilt::core::Flags;
use pendtilt::io::WarningKind;
use pendtilt::pipeline::PassError;
use pendtilt::sim::planar::{simulate, Scenario, SimRow};

/// The best a restart after a gap ending at row `k1` could do for estimator `name`, whose
/// two runs on the same readings close as `exp(-rate t)`: start at the truth plus the
/// fault-free run's mean offset over the next 10 s (an oracle). Returns how far that start
/// is from the fault-free run [deg] and when it is within 0.05 deg of it [s],
/// `ln(|d| / 0.05) / rate`.
fn oracle_restart(clean: &Run, rows: &[SimRow], name: &str, k1: usize, rate: f64) -> (f64, f64) {
    let j = clean.names.iter().position(|n| *n == name).unwrap();
    let err = |k: usize| clean.est[k][j].theta - rows[k].truth.theta;
    let offset = (k1..k1 + 10_000).map(err).sum::<f64>() / 10_000.0;
    let d = (err(k1) - offset).abs().to_degrees();
    (d, ((d / TOLERANCE_DEG).ln() / rate).max(0.0))
}

/// `tail` (a run started at row `k1`) placed at row `k1` of a run like `like`, whose rows
/// before it fill the rest.
fn shifted(tail: &Run, like: &Run, k1: usize) -> Run {
    let mut est = like.est[..k1].to_vec();
    est.extend_from_slice(&tail.est);
    Run {
        names: like.names.clone(),
        t: like.t.clone(),
        est,
        warnings: Vec::new(),
        result: Err(PassError::Settings(String::new())),
        implausible_count: 0,
    }
}

/// 100 missing gyro readings anywhere in a ride (27 gaps: seeds 1, 3, 6, from 2 s to 10 s):
/// the gyro peers bridge the gap with the angle fitted to the gyro's readings on either
/// side (`InputHold::bridged`, `core::estimators::gap_fit`) and are back within 0.05 deg
/// of the fault-free run within 2 s. Holding the mean alone left the integrated angle up
/// to 1 deg off, which Mahony forgets at kp = 0.45 /s: measured before the bridge, Mahony
/// back after up to 5.5 s, beyond 2 s in most gaps; with the line between the means on
/// either side, within 2 s in 22 of 27, at most 3.74 s; with the fit, 26 of
/// 27, at most 3.02 s (the complementary filter at most 0.96 s). Figures: `cargo test --release -p pendtilt --test plausibility --
/// --nocapture anywhere`.
#[test]
fn a_burst_of_100_missing_gyro_readings_anywhere_is_bridged() {
    let mut backs: Vec<(&str, f64)> = Vec::new();
    for seed in [1, 3, 6] {
        let (rows, rig) = ride("scooter", 14.0, seed);
        let base = cells(&rows);
        let clean = run(&text(&base), &rig);
        for k0 in (2000..=10_000).step_by(1000) {
            let mut c = base.clone();
            for row in c.iter_mut().skip(k0).take(100) {
                row[2].clear();
            }
            let bad = run(&text(&c), &rig);
            let rec = recovery(&clean, &bad, (k0 + 100) as f64 * 1e-3);
            for (name, back, _) in rec {
                if ["mahony", "complementary", "ekf"].contains(&name) {
                    backs.push((name, back));
                }
            }
        }
    }
    let times =
        |name: &str| -> Vec<f64> { backs.iter().filter(|b| b.0 == name).map(|b| b.1).collect() };
    for name in ["mahony", "complementary", "ekf"] {
        println!("{name}: back after {:.2?} s", times(name));
    }
    assert!(times("complementary").iter().all(|b| *b <= 2.0));
    // The EKF re-converges from the pendulum (measured 24 of 27 within 2 s, at most
    // 4.06 s; 24 of 27, at most 3.46 s, with theta' loosened by 3 vibration sigmas).
    let ekf = times("ekf");
    let within = ekf.iter().filter(|b| **b <= 2.0).count();
    assert!(within >= 23, "ekf within 2 s in {within} of 27: {ekf:?}");
    assert!(ekf.iter().all(|b| *b <= 5.0), "{ekf:?}");
    let mahony = times("mahony");
    let within = mahony.iter().filter(|b| **b <= 2.0).count();
    assert!(
        within >= 25,
        "mahony within 2 s in {within} of 27: {mahony:?}"
    );
    assert!(mahony.iter().all(|b| *b <= 3.5), "{mahony:?}");
}

/// One missing accelerometer reading anywhere (27 positions, seeds 1, 3, 6): every
/// estimator is back within 0.05 deg of the fault-free run within 2 s. Madgwick holds the
/// last reading for one sample: it skipped the correction, and its normalised
/// step left it 2 beta dt (0.14 deg) from the fault-free run for 5.5 s on the cell.
#[test]
fn one_missing_accelerometer_reading_anywhere_leaves_no_estimator_off() {
    let mut worst: Vec<(&str, f64)> = Vec::new();
    for seed in [1, 3, 6] {
        let (rows, rig) = ride("scooter", 14.0, seed);
        let base = cells(&rows);
        let clean = run(&text(&base), &rig);
        for k in (2000..=10_000).step_by(1000) {
            let mut c = base.clone();
            c[k][3].clear();
            let bad = run(&text(&c), &rig);
            for (name, back, _) in recovery(&clean, &bad, (k + 1) as f64 * 1e-3) {
                match worst.iter_mut().find(|w| w.0 == name) {
                    Some(w) => w.1 = w.1.max(back),
                    None => worst.push((name, back)),
                }
            }
        }
    }
    println!("back after, the worst of 27: {worst:.3?}");
    for (name, back) in worst {
        assert!(back <= 2.0, "{name}: {back} s");
    }
}

/// A 450 ms gap in the gyro in the middle of a turn (the scooter ride, 12 s, seed 6, from
/// 8.2 s, where the body turns at 0.5 rad/s): the EKF and UKF coast on the gyro's 25 ms
/// mean and the pendulum. With theta' loosened by three vibration sigmas
/// (`MISSING_RATE_SIGMAS` before) the encoder's readings, swung by the pivot's
/// unknown translation, turned theta 5.7 deg off the truth; now 1.8 deg at most (the
/// fault-free run 0.10 over the same second).
#[test]
fn a_gyro_gap_in_a_turn_leaves_the_model_based_filters_on_the_pendulum() {
    let (rows, rig) = ride("scooter", 12.0, 6);
    let mut c = cells(&rows);
    for row in c.iter_mut().skip(8200).take(450) {
        row[2].clear();
    }
    let r = run(&text(&c), &rig);
    assert_eq!(r.result.as_ref().unwrap().restarts, 0);
    for name in ["ekf", "ukf"] {
        let j = r.names.iter().position(|n| *n == name).unwrap();
        let worst = (8200..9200)
            .map(|k| (r.est[k][j].theta - rows[k].truth.theta).abs().to_degrees())
            .fold(0.0, f64::max);
        println!("{name}: at most {worst:.2} deg from the truth over the gap and 0.55 s after");
        assert!(worst < 2.5, "{name}: {worst} deg");
    }
}

#[test]
fn a_10_s_gap_of_every_sensor_restarts_every_estimator_as_if_started_there() {
    let (rows, rig) = ride("scooter", 30.0, 3);
    let base = cells(&rows);
    let clean = run(&text(&base), &rig);
    let (k0, k1) = (5000, 15000);
    let mut c = base.clone();
    for row in c.iter_mut().take(k1).skip(k0) {
        for cell in row.iter_mut().take(5).skip(1) {
            cell.clear();
        }
    }
    let bad = run(&text(&c), &rig);
    assert_eq!(bad.est.len(), rows.len());
    no_estimate_beyond_the_restart_gap(&bad, k0, k1);
    // After the gap every estimator gives exactly what it gives when started there, but
    // the EKF and the UKF, which resume: they keep their gyro bias (a gap cannot change it
    // beyond its random walk) and start the rest afresh.
    let tail = run(&text(&base[k1..]), &rig);
    as_if_started_there(&bad, &tail, k1);
    let rec = recovery(&clean, &bad, k1 as f64 * 1e-3);
    print("10 s gap of every sensor", &rec);
    let fresh = recovery(&clean, &shifted(&tail, &bad, k1), k1 as f64 * 1e-3);
    print("the same rows started afresh", &fresh);
    assert_nothing_poisoned("10 s gap", &clean, &bad, &rows, k1 as f64 * 1e-3 + 2.0);
    for (r, f) in rec.iter().zip(&fresh) {
        back_within_bounds(*r, f.1);
    }

    // The same gap as missing rows (the time jumps by 10 s).
    let mut c = base[..k0].to_vec();
    c.extend_from_slice(&base[k1..]);
    let jumped = run(&text(&c), &rig);
    assert_eq!(jumped.result.as_ref().unwrap().restarts, 1);
    for (k, row) in bad.est[k1..].iter().enumerate() {
        for (j, e) in row.iter().enumerate() {
            let d = (e.theta - jumped.est[k0 + k][j].theta).abs();
            // The resuming filters grow the bias variance by its walk over the gap either
            // way (predicted through the empty rows, or added for the jump).
            let tol = if resumes(bad.names[j]) { 1e-6 } else { 1e-12 };
            assert!(d <= tol, "{} at row {}: {d}", bad.names[j], k1 + k);
        }
    }
}

/// The EKF, the UKF, the complementary filter and Mahony resume after a gap (they keep
/// their gyro bias or steady offset); the others start afresh.
fn resumes(name: &str) -> bool {
    matches!(name, "ekf" | "ukf" | "complementary" | "mahony")
}

/// The gap of rows `k0..k1` restarted the estimators once, said so on the row after it,
/// and beyond the restart gap no estimator gave an estimate.
fn no_estimate_beyond_the_restart_gap(bad: &Run, k0: usize, k1: usize) {
    assert!(bad.result.is_ok());
    let restarts: Vec<_> = bad
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Restarted)
        .collect();
    assert_eq!(restarts.len(), 1, "{:?}", bad.warnings);
    assert_eq!(restarts[0].line, k1 as u64 + 2);
    assert!(
        restarts[0].message.contains("after a gap of 10.0"),
        "{}",
        restarts[0]
    );
    assert_eq!(bad.result.as_ref().unwrap().restarts, 1);
    // Beyond the restart gap (0.5 s) no estimator gives an estimate: each reads a sensor
    // that is gone (they gave the gyro's last mean integrated, the EKF 170 deg off by the
    // gap's end, and the summary counted it: 58 deg RMS).
    for (k, row) in bad.est.iter().enumerate().take(k1).skip(k0 + 502) {
        for (j, e) in row.iter().enumerate() {
            assert!(
                e.theta.is_nan() && e.flags.contains(Flags::SAMPLE_MISSING),
                "{} at row {k}: {e:?}",
                bad.names[j]
            );
        }
    }
}

/// After the gap ending at row `k1`, every estimator that does not resume gives exactly
/// what it gives on the rows after it alone (`tail`).
fn as_if_started_there(bad: &Run, tail: &Run, k1: usize) {
    for (k, row) in tail.est.iter().enumerate() {
        for (j, e) in row.iter().enumerate() {
            if resumes(tail.names[j]) {
                continue;
            }
            let b = bad.est[k1 + k][j];
            // Equal to rounding: a restarted differentiator may keep its filter design
            // for the same step (1 ulp).
            assert!(
                (e.theta - b.theta).abs() <= 1e-12 && e.flags == b.flags,
                "{} at row {}: {:?} against {:?}",
                tail.names[j],
                k1 + k,
                b,
                e
            );
        }
    }
}

/// One estimator's recovery after the gap (`est`, `back` \[s\], `worst` \[deg\]) within
/// its measured bound, and against `back_fresh`, its recovery started afresh there.
fn back_within_bounds((est, back, worst): (&str, f64, f64), back_fresh: f64) {
    // Bounds measured (docs/reliability.md 7b). The complementary filter and Mahony
    // restart as a running mean of the accelerometer angle (after the prefilter has
    // settled) and keep their steady offset, the gyro bias times their time constant:
    // the complementary filter is back after 1.98 s (2.36 s started afresh); Mahony
    // (kp = 0.45 /s) after 7.24 s (10.95 s afresh, from one reading): what its clean
    // run remembers of the accelerometer over the last seconds fades at kp, 0.41 of
    // it in 2 s, and no restart can know it (the twins of
    // `no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap`). Madgwick: its
    // resolution.
    match est {
        "madgwick" => assert!(worst <= madgwick_resolution_deg(), "{est}: {worst} deg"),
        "mahony" => assert!(
            back <= 9.0 && worst <= 0.8,
            "{est}: back after {back} s, {worst} deg off 2 s after the gap"
        ),
        _ => assert!(back <= 2.0, "{est} back after {back} s"),
    }
    match est {
        // Keeping the bias: back within 1.01 s; started afresh the bias re-converges
        // over 5.6 s.
        "ekf" | "ukf" => assert!(
            back <= 1.1 && back_fresh > 5.0,
            "{est}: {back} s, afresh {back_fresh} s"
        ),
        // Keeping the steady offset.
        "complementary" | "mahony" => assert!(
            back < 0.9 * back_fresh,
            "{est}: {back} s, afresh {back_fresh} s"
        ),
        _ => assert!(!resumes(est)),
    }
}

#[test]
fn a_gap_shorter_than_the_restart_gap_is_bridged_not_restarted() {
    let (rows, rig) = ride("scooter", 4.0, 6);
    let mut c = cells(&rows);
    for row in c.iter_mut().skip(1000).take(400) {
        row[2].clear();
    }
    let r = run(&text(&c), &rig);
    assert_eq!(r.result.as_ref().unwrap().restarts, 0);
    for row in c.iter_mut().skip(1000).take(600) {
        row[2].clear();
    }
    let r = run(&text(&c), &rig);
    assert_eq!(r.result.as_ref().unwrap().restarts, 1);
    let w = r
        .warnings
        .iter()
        .find(|w| w.kind == WarningKind::Restarted)
        .unwrap();
    assert!(
        w.message.starts_with("gyro back after a gap of 0.60"),
        "{w}"
    );
    // Only the estimators reading the gyro restarted: accel and pendulum did not.
    let n_gyro = pendtilt::bank::planar::REGISTRY
        .iter()
        .filter(|e| r.names.contains(&e.name) && e.needs().has(pendtilt::sensors::Sensor::Gyro))
        .count();
    // alg1 shares its front end with alg2, so it restarts with it.
    assert!(
        w.message.contains(&format!("{} estimators", n_gyro + 1)),
        "{w}"
    );
}

/// The restarts of the 10 s gap over six rides (seeds 1-6, 30 s) and three gap positions
/// each (5-15 s, 8-18 s, 6-16.5 s): nothing poisoned for every estimator but Mahony in
/// all 18; the
/// complementary filter back within 0.05 deg of the fault-free run within 2 s in at least
/// 14 of them and within 3 s in all (measured: 14, worst 2.82 s; 3 of 18 and 3.05 s
/// before it kept its offset); Mahony within 9 s in all (1.4-8.0 s; 7.1-12.9 s from one
/// reading) and, against the truth from 2 s after the gap, within 0.25 deg of its
/// fault-free run's error in all (measured: at most 0.16 deg worse; up to 1.67 deg worse
/// when it restarted from one reading); and a restart knowing the truth (an oracle) would
/// still be beyond 2 s in at least half of them (measured 11 of 18, up to 4.9 s): the
/// fault-free run's own error at the gap's end, 0.04-0.45 deg, fades only at kp. Figures:
/// `cargo test --release -p pendtilt --test plausibility -- --nocapture over_six`.
#[test]
fn restarts_over_six_rides_and_three_gap_positions() {
    let comp_tau = pendtilt::peers::PeerSettings::default()
        .complementary
        .time_constant;
    let mut cases = Vec::new();
    for seed in 1..=6u64 {
        let (rows, rig) = ride("scooter", 30.0, seed);
        let base = cells(&rows);
        let clean = run(&text(&base), &rig);
        for (k0, k1) in [(5000usize, 15000usize), (8000, 18000), (6000, 16500)] {
            let bad = run(&gapped(&base, k0, k1), &rig);
            let case = format!("seed {seed}, gap rows {k0}-{k1}");
            cases.push(gap_case(&case, &rows, &clean, &bad, k1, comp_tau));
        }
    }
    let comp: Vec<f64> = cases.iter().map(|c| c.comp).collect();
    let mahony_back: Vec<f64> = cases.iter().map(|c| c.mahony_back).collect();
    let mahony_truth: Vec<f64> = cases.iter().map(|c| c.mahony_truth).collect();
    let mahony_oracle: Vec<f64> = cases.iter().map(|c| c.mahony_oracle).collect();
    let comp_oracle: Vec<f64> = cases.iter().map(|c| c.comp_oracle).collect();
    let within_2 = comp.iter().filter(|b| **b <= 2.0).count();
    assert!(
        within_2 >= 14,
        "complementary within 2 s in {within_2} of 18: {comp:?}"
    );
    assert!(comp.iter().all(|b| *b <= 3.0), "{comp:?}");
    assert!(mahony_back.iter().all(|b| *b <= 9.0), "{mahony_back:?}");
    assert!(mahony_truth.iter().all(|d| *d <= 0.25), "{mahony_truth:?}");
    let comp_beyond: Vec<_> = (0..18).filter(|&i| comp[i] > 2.0).collect();
    println!(
        "complementary: beyond 2 s in {comp_beyond:?}, an oracle restart there {:.2?}; \
         every oracle {comp_oracle:.2?}",
        comp_beyond
            .iter()
            .map(|&i| comp_oracle[i])
            .collect::<Vec<_>>()
    );
    // An oracle restart (knowing the truth and the next 10 s) is back within 1.6 s in all
    // 18. What a restart cannot know is the fault-free run's own error at the gap's end (its
    // accelerometer's error over the gap's last tau): a twin of the ride that brakes in the
    // gap gives the same faulty log and another fault-free run, so no restart meets 2 s on
    // both (`no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap`). Tried
    // earlier, estimating it from the readings after the gap by their uniform
    // mean, or by their mean mirrored with weights exp(-t / T), T = 0.5-4 tau: 4 of 18
    // beyond 2 s in each (at most 2.35-2.79 s).
    assert!(comp_oracle.iter().all(|t| *t <= 2.0), "{comp_oracle:?}");
    let beyond = mahony_oracle.iter().filter(|t| **t > 2.0).count();
    println!("mahony: an oracle restart is beyond 2 s in {beyond} of 18: {mahony_oracle:.2?}");
    // Why 2 s is out of reach for Mahony at kp = 0.45 /s: even a restart knowing the truth
    // misses it in most cases (measured 11 of 18, up to 4.9 s).
    assert!(beyond >= 9, "{mahony_oracle:?}");
}

/// What one gap left: the complementary filter's and Mahony's recovery \[s\], Mahony's
/// RMS from the truth over the fault-free run's \[deg\], and an oracle restart's recovery
/// for Mahony and the complementary filter \[s\].
struct GapCase {
    comp: f64,
    mahony_back: f64,
    mahony_truth: f64,
    mahony_oracle: f64,
    comp_oracle: f64,
}

/// The gap ending at row `k1` of ride `rows`: nothing poisoned (but Mahony, held to its
/// own bound), and the recoveries of the complementary filter and Mahony, theirs and an
/// oracle restart's.
fn gap_case(
    case: &str,
    rows: &[SimRow],
    clean: &Run,
    bad: &Run,
    k1: usize,
    comp_tau: f64,
) -> GapCase {
    let from = k1 as f64 * 1e-3 + 2.0;
    // Mahony is held to its own bound below: on the rides where its own error is
    // smallest (0.127 deg RMS, seed 1, the gap at 5 s) what its slow memory of the
    // accelerometer leaves over the following 10 s is larger (0.189 deg RMS).
    assert_nothing_poisoned_but(case, clean, bad, rows, from, &["mahony"]);
    let rec = recovery(clean, bad, k1 as f64 * 1e-3);
    let back = |name: &str| rec.iter().find(|r| r.0 == name).unwrap().1;
    let j = clean.names.iter().position(|n| *n == "mahony").unwrap();
    let truth_rms = |r: &Run| {
        let e: Vec<f64> = ((from * 1000.0).round() as usize..rows.len())
            .map(|k| (r.est[k][j].theta - rows[k].truth.theta).powi(2))
            .collect();
        (e.iter().sum::<f64>() / e.len() as f64).sqrt().to_degrees()
    };
    let (b, c) = (truth_rms(bad), truth_rms(clean));
    // The best a restart could do: start at the truth plus the fault-free run's
    // mean offset over the next 10 s (an oracle). Two Mahony runs on the same
    // readings differ by their difference at the start times exp(-kp t), so the
    // oracle is back within 0.05 deg after ln(|d| / 0.05) / kp.
    let kp = pendtilt::peers::ahrs_planar::MAHONY_GAINS[0];
    let (d, oracle) = oracle_restart(clean, rows, "mahony", k1, kp);
    println!(
        "  mahony: an oracle restart {d:.3} deg from the fault-free run, back after \
         {oracle:.2} s"
    );
    let mahony_oracle = oracle;
    let (d, oracle) = oracle_restart(clean, rows, "complementary", k1, 1.0 / comp_tau);
    println!(
        "  complementary: an oracle restart {d:.3} deg from the fault-free run, back \
         after {oracle:.2} s"
    );
    let comp_oracle = oracle;
    println!(
        "{case}: complementary back after {:.3} s, mahony {:.3} s, mahony against \
         the truth {b:.3} deg RMS (fault-free {c:.3})",
        back("complementary"),
        back("mahony")
    );
    GapCase {
        comp: back("complementary"),
        mahony_back: back("mahony"),
        mahony_truth: b - c,
        mahony_oracle,
        comp_oracle,
    }
}

/// The gap's text of a log: every sensor cell of rows `k0..k1` empty.
fn gapped(c: &[[String; 6]], k0: usize, k1: usize) -> String {
    let mut c = c.to_vec();
    for row in c.iter_mut().take(k1).skip(k0) {
        for cell in row.iter_mut().take(5).skip(1) {
            cell.clear();
        }
    }
    text(&c)
}

/// Why no restart can bring the accelerometer peers back within 0.05 deg of their
/// fault-free run 2 s after the 10 s gap (seed 3, 5-15 s), and why the
/// complementary filter's 1.98 s there is its ride's luck. Two twins of the ride differ
/// from it only inside the gap, where the gap took every reading away: one brakes gently
/// over the gap's last 2 s (a horizontal deceleration `1 m/s^2 sin^2`, 0.1 g at its peak,
/// read by the accelerometer as the specific force it makes in the tilted body axes), one
/// rides a smooth road over the gap's last 5 s (the accelerometer as the same ride without
/// vibration gives it). The faulty logs of the three are one log, so any restart gives one
/// output on all three; but their fault-free runs, which remember what the accelerometer
/// read at their own rate, stand up to `D` apart from 2 s after the gap on, and a restart
/// within 0.05 deg of two of them there needs `D <= 0.1 deg`. Measured D (braking /
/// smooth road): Mahony 0.79 / 0.46 deg, the complementary filter 0.17 / 0.01, Madgwick
/// 0.25 / 0.26 (its resolution: the few millidegrees its runs differ by at the gap's end
/// become up to 4 beta dt, 0.27 deg). The same restart is back after 7.24 s on the ride
/// and 1.35 s on the smooth-road twin (Mahony), 1.98 s and 3.11 s on the braking one (the
/// complementary filter): which one meets 2 s is decided by readings no restart sees.
/// The estimators that read the pendulum are compared too, though a braking pendulum
/// would swing: their D is at most 0.03 deg (kf_accel), and they meet 2 s on every twin.
/// Figures: `cargo test --release -p pendtilt --test plausibility -- --nocapture twin`.
#[test]
fn no_restart_meets_2_s_on_both_a_ride_and_its_twins_in_the_gap() {
    let (k0, k1) = (5000, 15000);
    let mut scenario = Scenario::named("scooter").unwrap();
    scenario.duration = 30.0;
    let rows = simulate(&scenario, 3).unwrap();
    let rig = scenario.rig().unwrap();
    scenario.vibration = Default::default();
    let smooth = simulate(&scenario, 3).unwrap();
    let base = cells(&rows);
    let mut braking = base.clone();
    let (a, b) = (k1 - 2000, k1);
    for (k, row) in braking.iter_mut().enumerate().take(b).skip(a) {
        let s = ((k - a) as f64 / (b - a) as f64 * std::f64::consts::PI).sin();
        let brake = s * s;
        let th = rows[k].truth.theta;
        // A horizontal deceleration, in the body axes of MODEL.md section 1 (x along
        // the tilted horizontal, y along the tilted vertical).
        row[3] = format!("{}", rows[k].ax + brake * th.cos());
        row[4] = format!("{}", rows[k].ay - brake * th.sin());
    }
    let mut smooth_road = base.clone();
    for (k, row) in smooth_road.iter_mut().enumerate().take(k1).skip(k1 - 5000) {
        row[3] = format!("{}", smooth[k].ax);
        row[4] = format!("{}", smooth[k].ay);
    }
    let g = gapped(&base, k0, k1);
    for t in [&braking, &smooth_road] {
        assert_eq!(g, gapped(t, k0, k1), "the faulty logs differ");
    }
    let clean = run(&text(&base), &rig);
    let twins = [run(&text(&braking), &rig), run(&text(&smooth_road), &rig)];
    let bad = run(&g, &rig);
    let (at, t_end) = (k1 + 2000, k1 as f64 * 1e-3);
    let rec = recovery(&clean, &bad, t_end);
    for (j, name) in clean.names.iter().enumerate() {
        let mut apart = Vec::new();
        for (tw, what) in twins.iter().zip(["brakes", "rides a smooth road"]) {
            // From 2 s after the gap on, the largest difference.
            let d = (at..rows.len())
                .map(|k| (clean.est[k][j].theta - tw.est[k][j].theta).abs())
                .fold(0.0, f64::max)
                .to_degrees();
            let b_twin = recovery(tw, &bad, t_end)[j].1;
            println!(
                "  {name:<14} the ride and its twin that {what}: fault-free runs {d:.3} deg \
                 apart from 2 s after the gap on; the restart back after {:.2} s on the ride, \
                 {b_twin:.2} s on the twin",
                rec[j].1
            );
            apart.push((d, b_twin));
        }
        let (d, b_twin) = apart
            .iter()
            .copied()
            .fold((0.0, 0.0), |a, x| if x.0 > a.0 { x } else { a });
        if ["mahony", "complementary", "madgwick"].contains(name) {
            assert!(d > 2.0 * TOLERANCE_DEG, "{name}: {d} deg");
            // The restart meets 2 s on at most one of the two.
            assert!(
                rec[j].1 > 2.0 || b_twin > 2.0,
                "{name}: {} s, {b_twin} s",
                rec[j].1
            );
        } else {
            // The estimators that meet 2 s: on every twin too.
            assert!(
                d < 2.0 * TOLERANCE_DEG && b_twin <= 2.0,
                "{name}: {d} deg, {b_twin} s"
            );
        }
    }
}
