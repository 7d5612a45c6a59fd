//! `pendtilt tune` end to end: a log with no true angle in, a rig file out that
//! `pendtilt estimate` reads as it is and that beats the defaults against the simulator's
//! truth on a rig the project never saw; the inputs are never overwritten; the time limit
//! stops it early and it says so.
use std::path::{Path, PathBuf};

mod common;
use common::{pendtilt, s, stderr};
use pendtilt::config::RigConfig;
use pendtilt::sim::planar::simulate;
use pendtilt::tune::zoo;

/// A ride of the zoo written as a log without a true angle (t, phi, gyro, ax, ay), its rig
/// file, and the true tilt per row.
struct Fixture {
    dir: tempfile::TempDir,
    log: PathBuf,
    rig: PathBuf,
    truth: Vec<f64>,
}

impl Fixture {
    fn new(ride: u64, seconds: f64, with_theta: bool) -> Self {
        let r = zoo::ride(ride, seconds);
        let rows = simulate(&r.scenario, r.index).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("ride.csv");
        let mut text = String::from(if with_theta {
            "t,phi,gyro,ax,ay,theta\n"
        } else {
            "t,phi,gyro,ax,ay\n"
        });
        for row in &rows {
            text.push_str(&format!(
                "{:?},{:?},{:?},{:?},{:?}",
                row.t, row.phi, row.gyro, row.ax, row.ay
            ));
            if with_theta {
                text.push_str(&format!(",{:?}", row.truth.theta));
            }
            text.push('\n');
        }
        std::fs::write(&log, text).unwrap();
        let rig = dir.path().join("rig.toml");
        r.scenario.rig().unwrap().save(&rig).unwrap();
        Self {
            dir,
            log,
            rig,
            truth: rows.iter().map(|r| r.truth.theta).collect(),
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// `pendtilt tune LOG -p RIG -o out extra..`; panics unless it succeeds.
    fn tune(&self, out: &Path, extra: &[&str]) -> String {
        let mut a = vec!["tune", s(&self.log), "-p", s(&self.rig), "-o", s(out)];
        a.extend_from_slice(extra);
        let o = pendtilt(&a);
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    }

    /// RMS error \[deg\] against the truth after 2 s of `ekf, kf_alg2, alg1, alg2` as
    /// `pendtilt estimate` computes them with `rig`.
    fn estimate_rms(&self, rig: &Path) -> [f64; 4] {
        let out = self.path("est.csv");
        let o = pendtilt(&[
            "estimate",
            s(&self.log),
            "-p",
            s(rig),
            "-o",
            s(&out),
            "--only",
            "ekf,kf_alg2,alg1,alg2",
            "-q",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read_to_string(&out).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse().unwrap_or(f64::NAN))
                    .collect()
            })
            .collect();
        // One estimate per input row.
        assert_eq!(rows.len(), self.truth.len());
        ["ekf", "kf_alg2", "alg1", "alg2"].map(|name| {
            let c = header.iter().position(|h| *h == name).unwrap();
            let (mut sum, mut n) = (0.0, 0usize);
            for (row, th) in rows.iter().zip(&self.truth).skip(2000) {
                sum += (row[c] - th).powi(2);
                n += 1;
            }
            (sum / n as f64).sqrt().to_degrees()
        })
    }
}

#[test]
fn tune_writes_a_commented_rig_that_estimate_reads_and_that_beats_the_defaults() {
    // Zoo ride 3: f_n 2.10 Hz, damping 0.16, l12 32 mm, tactical sensors, a 34 Hz engine, a
    // chirp: none of the project's scenarios.
    let f = Fixture::new(3, 40.0, false);
    let tuned = f.path("tuned.toml");
    let stdout = f.tune(&tuned, &[]);
    // The likelihood before and after, and which target.
    assert!(
        stdout.contains("kf_alg2 innovation likelihood (mean -log L): before")
            && stdout.contains("no true angle used"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&tuned).unwrap();
    let rig = RigConfig::load(&tuned).unwrap();
    let start = RigConfig::load(&f.rig).unwrap();
    assert_eq!(
        rig.pendulum, start.pendulum,
        "the pendulum is the input rig's"
    );
    assert_ne!(rig.kalman, start.kalman);
    assert!(rig.ekf.gyro_density.is_some() && rig.ekf.process_jerk.is_some());
    // Every tuned value has a comment above it saying how it was found.
    for key in [
        "q_angle",
        "r_pendulum",
        "cutoff_times_natural",
        "gyro_density",
        "encoder_noise",
    ] {
        let i = text
            .lines()
            .position(|l| l.starts_with(&format!("{key} =")))
            .unwrap_or_else(|| panic!("{key} missing:\n{text}"));
        let above = text.lines().nth(i - 1).unwrap();
        assert!(above.starts_with('#'), "{key}: {above}");
    }
    assert!(text.contains(": tuned:"), "{text}");
    // Tuning the same log again gives the same file.
    let again = f.path("again.toml");
    f.tune(&again, &["-q"]);
    assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes());
    // Against the truth: the tuned rig beats the defaults for the inversions and the
    // Kalman filter on them (measured in the zoo: 1.36 -> 0.023 deg kf_alg2, 0.89 -> 0.27
    // alg1, 1.33 -> 0.69 alg2). The EKF is not asserted: its self-tuned sensor figures
    // made it worse on this ride (0.0092 -> 0.0106 deg; docs/fitting-and-tuning.md, "Self-tuning").
    let d = f.estimate_rms(&f.rig);
    let t = f.estimate_rms(&tuned);
    eprintln!("defaults {d:?}\ntuned    {t:?}");
    for (i, name) in ["kf_alg2", "alg1", "alg2"].iter().enumerate() {
        assert!(
            t[i + 1] < 0.8 * d[i + 1],
            "{name}: {} vs {}",
            t[i + 1],
            d[i + 1]
        );
    }
}

#[test]
fn tune_never_writes_onto_its_log_or_rig() {
    let f = Fixture::new(3, 12.0, false);
    let (log0, rig0) = (
        std::fs::read(&f.log).unwrap(),
        std::fs::read(&f.rig).unwrap(),
    );
    for (out, opt) in [(&f.log, "LOG"), (&f.rig, "--params")] {
        let o = pendtilt(&["tune", s(&f.log), "-p", s(&f.rig), "-o", s(out)]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains("is the same file as") && err.contains(opt),
            "{err}"
        );
    }
    assert_eq!(std::fs::read(&f.log).unwrap(), log0);
    assert_eq!(std::fs::read(&f.rig).unwrap(), rig0);
}

#[test]
fn the_truth_target_needs_and_names_a_theta_column() {
    let f = Fixture::new(5, 12.0, false);
    let out = f.path("t.toml");
    let o = pendtilt(&[
        "tune",
        s(&f.log),
        "-p",
        s(&f.rig),
        "-o",
        s(&out),
        "--target",
        "truth",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(s(&f.log)) && err.contains("theta column"),
        "{err}"
    );
    assert!(!out.exists());
    // With one, it says it used it.
    let f = Fixture::new(5, 12.0, true);
    let stdout = f.tune(&out, &["--target", "truth"]);
    assert!(stdout.contains("target: the true angle"), "{stdout}");
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("searched against the true angle"));
}

#[test]
fn a_bad_rig_is_named_with_its_line_and_column() {
    let f = Fixture::new(5, 12.0, false);
    let bad = f.path("bad.toml");
    std::fs::write(
        &bad,
        "[kalman]\nq_angle = 1e-3\n[ekf]\ngyro_density = -1.0\n",
    )
    .unwrap();
    let o = pendtilt(&["tune", s(&f.log), "-p", s(&bad), "-o", s(&f.path("o.toml"))]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!("{}:4:16: ekf.gyro_density", bad.display())),
        "{err}"
    );
}

#[test]
fn a_time_limit_returns_the_best_so_far_and_says_it_stopped_early() {
    let f = Fixture::new(3, 20.0, false);
    let out = f.path("quick.toml");
    let stdout = f.tune(&out, &["--time-limit", "0"]);
    assert!(
        stdout.contains("STOPPED EARLY by --time-limit 0 s"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("# STOPPED EARLY"), "{text}");
    // What it writes is still a rig file estimate reads.
    RigConfig::load(&out).unwrap();
    // Without a limit it does not say so.
    let full = f.path("full.toml");
    assert!(!f.tune(&full, &[]).contains("STOPPED EARLY"));
}

/// RMS error \[deg\] after 2 s of `name` as `pendtilt estimate LOG -p RIG` computes it,
/// against the log's own `theta` (the simulator's truth).
fn truth_rms(log: &Path, rig: &Path, name: &str) -> f64 {
    let out = log.with_extension("est.csv");
    let o = pendtilt(&[
        "estimate",
        s(log),
        "-p",
        s(rig),
        "--only",
        &format!("alg2,{name}"),
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let column = |text: &str, col: &str| -> Vec<f64> {
        let mut lines = text.lines();
        let c = lines
            .next()
            .unwrap()
            .split(',')
            .position(|h| h == col)
            .unwrap();
        lines
            .map(|l| l.split(',').nth(c).unwrap().parse().unwrap())
            .collect()
    };
    let est = column(&std::fs::read_to_string(&out).unwrap(), name);
    let truth = column(&std::fs::read_to_string(log).unwrap(), "theta");
    assert_eq!(est.len(), truth.len());
    let e: Vec<f64> = est
        .iter()
        .zip(&truth)
        .skip(2000)
        .map(|(a, b)| (a - b).powi(2))
        .collect();
    (e.iter().sum::<f64>() / e.len() as f64).sqrt().to_degrees()
}

#[test]
fn a_still_log_never_tunes_a_noise_of_zero_and_its_rig_is_no_worse_than_the_defaults() {
    // A still pendulum under a 12-bit encoder reads one value throughout: tune took that
    // for an unquantised encoder without noise (encoder_bits = 0, encoder_noise = 0), an
    // encoder variance of 0 the EKF trusted without bound: on a scooter ride 0.131 ->
    // 0.222 deg RMS (20 s, seed 1, whole log).
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    for (scenario, log) in [("still", "still.csv"), ("scooter", "ride.csv")] {
        let o = pendtilt(&[
            "simulate",
            "--scenario",
            scenario,
            "--duration",
            "20",
            "-q",
            "-o",
            s(&p(log)),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let tuned = p("tuned.toml");
    let o = pendtilt(&["tune", s(&p("still.csv")), "-o", s(&tuned)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("warning: ")
            && e.contains(
                "sensors.encoder_noise = 0.000e0 rad, 12 bits: the log gave an encoder noise of 0"
            )
            && e.contains("phi never changed over 20000 samples")
            && e.contains("kept the start's value"),
        "{e}"
    );
    // Every noise the rig holds leaves the filter a measurement variance above 0.
    let rig = RigConfig::load(&tuned).unwrap();
    let ekf = rig.ekf.apply(pendtilt::core::ekf::ModelSettings::default());
    assert!(ekf.sensors.encoder_variance() > 0.0, "{:?}", ekf.sensors);
    assert!(ekf.sensors.gyro_density > 0.0 && ekf.sensors.accel_density > 0.0);
    // Against the truth, on the still log itself and on a ride: no estimator worse than
    // with the rig simulate wrote (the defaults) by more than 2 %. The tuned figures are
    // fixed (`adapt = false`), so they are held to the defaults' fixed figures: the
    // adaptive defaults beat them on the still log (0.0204 against 0.0257 deg), where the
    // forcing falls far below the defaults' scooter.
    for log in ["still.csv", "ride.csv"] {
        let log = p(log);
        let simulated = log.with_extension("rig.toml");
        let text = std::fs::read_to_string(&simulated).unwrap();
        let text = if text.contains("[ekf]") {
            text.replace("[ekf]", "[ekf]\nadapt = false")
        } else {
            format!("{text}\n[ekf]\nadapt = false\n")
        };
        let defaults = log.with_extension("fixed.toml");
        std::fs::write(&defaults, text).unwrap();
        for name in ["ekf", "ukf", "kf_alg2", "alg2"] {
            let (d, t) = (
                truth_rms(&log, &defaults, name),
                truth_rms(&log, &tuned, name),
            );
            eprintln!(
                "{} {name}: defaults {d:.4} deg, still-tuned {t:.4}",
                log.display()
            );
            assert!(t <= 1.02 * d, "{} {name}: {t} vs {d}", log.display());
        }
    }
}

/// A log whose gyro is in deg/s is said to be, as `estimate` says it, and the tuned file
/// records it (earlier: `tune` read it silently and wrote settings fitted to a gyro 57x
/// too large, most of its readings read as missing beyond the rig's full scale, of which
/// only the first ten were listed). With `--deg gyro` the warning goes; a correct log has
/// none.
#[test]
fn a_gyro_in_deg_per_s_is_said_and_recorded_in_the_tuned_file() {
    let f = Fixture::new(5, 12.0, false);
    let out = f.path("t.toml");
    let plain = f.tune(&out, &[]);
    assert!(!plain.contains("NOT TO BE TRUSTED"), "{plain}");
    assert!(plain.contains("the log: 12000 rows"), "{plain}");
    let text = std::fs::read_to_string(&f.log).unwrap();
    let mut deg = String::new();
    for (k, line) in text.lines().enumerate() {
        let mut cells: Vec<String> = line.split(',').map(String::from).collect();
        if k > 0 {
            cells[2] = format!("{:?}", cells[2].parse::<f64>().unwrap().to_degrees());
        }
        deg.push_str(&cells.join(","));
        deg.push('\n');
    }
    std::fs::write(&f.log, deg).unwrap();
    let o = pendtilt(&["tune", s(&f.log), "-p", s(&f.rig), "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("ride.csv: gyro is ")
            && e.contains(
                "x the encoder's derivative d(phi)/dt: is gyro in deg/s? read it with --deg gyro"
            ),
        "{e}"
    );
    let file = std::fs::read_to_string(&out).unwrap();
    assert!(
        file.contains("# NOT TO BE TRUSTED: tuned on a log whose units look wrong: gyro is "),
        "{file}"
    );
    let fixed = f.tune(&out, &["--deg", "gyro"]);
    assert!(!fixed.contains("NOT TO BE TRUSTED"), "{fixed}");
}
