//! Unit checks: time in ms or us, degrees read as radians (found from the physics, with
//! the factor), an accelerometer in g or mg, a column counting the other way, cutoffs
//! above Nyquist or below the floor; each detector also on correct logs that must not
//! trigger it.
use crate::common::plausibility::{cells, retimed, ride, run, run_with, text, Run};
use pendtilt::config::RigConfig;
use pendtilt::core::filters::diff::Cutoff;
use pendtilt::io::{AccelUnit, ReaderOptions, TimeUnit};
use pendtilt::sim::planar::{simulate, Scenario, SimRow};

#[test]
fn time_in_ms_or_us_is_an_error_with_the_fix_and_the_fix_works() {
    let (rows, rig) = ride("step", 2.0, 1);
    for (scale, unit, fix) in [
        (1e3, TimeUnit::Ms, "--time-unit ms (1000 Hz)"),
        (1e6, TimeUnit::Us, "--time-unit us (1000 Hz)"),
    ] {
        let log = retimed(&rows, scale);
        let r = run(&log, &rig);
        let err = r.result.unwrap_err().to_string();
        assert!(err.starts_with("ride.csv:17: column 1 (`t`): "), "{err}");
        assert!(err.contains(fix), "{err}");
        // No restart warnings before the error (each step would be a "gap").
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        let fixed = run_with(
            &log,
            &rig,
            ReaderOptions {
                limits: pendtilt::io::SensorLimits::of_rig(&rig),
                time_unit: Some(unit),
                ..ReaderOptions::default()
            },
        );
        let s = fixed.result.unwrap();
        assert_eq!((s.rows, s.restarts), (rows.len() as u64, 0));
    }
    // Correct logs at 1 kHz, 100 Hz and 20 Hz, and a short one, pass.
    for (rate, secs) in [(1000.0, 2.0), (100.0, 3.0), (20.0, 5.0), (1000.0, 0.005)] {
        let mut s = Scenario::named("step").unwrap();
        s.rate = rate;
        s.duration = secs;
        let rows = simulate(&s, 1).unwrap();
        let r = run(&text(&cells(&rows)), &s.rig().unwrap());
        assert!(
            r.result.is_ok(),
            "{rate} Hz: {:?}",
            r.result.err().map(|e| e.to_string())
        );
    }
}

fn degrees(rows: &[SimRow], cols: &[usize]) -> String {
    let mut c = cells(rows);
    for row in &mut c {
        for &i in cols {
            row[i] = format!("{}", row[i].parse::<f64>().unwrap().to_degrees());
        }
    }
    text(&c)
}

fn findings(r: &Run) -> Vec<(&'static str, f64, String)> {
    r.result
        .as_ref()
        .unwrap()
        .unit_findings
        .iter()
        .map(|f| (f.column, f.fit.factor, f.message.clone()))
        .collect()
}

/// The scenarios the degree detector must stay quiet on when the units are right.
fn scenarios() -> Vec<(&'static str, Vec<SimRow>, RigConfig)> {
    let mut v = Vec::new();
    for (name, secs) in [
        ("still", 6.0),
        ("step", 5.0),
        ("scooter", 12.0),
        ("sine", 10.0),
    ] {
        let (rows, rig) = ride(name, secs, 4);
        v.push((name, rows, rig));
    }
    // The case: a small motion, 2.3 deg and about 8 deg/s.
    let mut s = Scenario::named("sine").unwrap();
    s.motion.set_amplitude(0.04);
    s.duration = 12.0;
    v.push(("small sine", simulate(&s, 4).unwrap(), s.rig().unwrap()));
    v
}

#[test]
fn degrees_are_found_from_the_physics_with_the_factor_and_correct_logs_are_quiet() {
    for (name, rows, rig) in scenarios() {
        let clean = run(&text(&cells(&rows)), &rig);
        assert!(
            findings(&clean).is_empty(),
            "{name}: {:?}",
            findings(&clean)
        );
        if name == "still" {
            // Nothing moves: no fit, nothing to tell (and nothing claimed).
            let r = run(&degrees(&rows, &[2]), &rig);
            assert!(findings(&r).is_empty(), "{name}: {:?}", findings(&r));
            continue;
        }
        // The gyro in deg/s: 57.3x the encoder's derivative.
        let r = run(&degrees(&rows, &[2]), &rig);
        let f = findings(&r);
        assert_eq!(f.len(), 1, "{name}: {f:?}");
        assert_eq!(f[0].0, "gyro", "{name}: {f:?}");
        assert!(
            (f[0].1 / 57.3 - 1.0).abs() < 0.1,
            "{name}: factor {}",
            f[0].1
        );
        assert!(f[0].2.contains("the encoder's derivative") && f[0].2.contains("--deg gyro"));
        println!("{name}, gyro in deg/s: {}", f[0].2);
        // Every angle in degrees: each column named against the accelerometer.
        let r = run(&degrees(&rows, &[1, 2, 5]), &rig);
        let mut cols: Vec<_> = findings(&r).iter().map(|f| f.0).collect();
        cols.sort();
        assert_eq!(cols, ["gyro", "phi", "theta"], "{name}: {:?}", findings(&r));
        for f in findings(&r) {
            // Found directly (57.3 within the accelerometer's vibration bias), or by
            // following phi, itself found in degrees.
            assert!(
                (f.1 / 57.3 - 1.0).abs() < 0.3 || f.2.contains("and phi is in degrees"),
                "{name}: {f:?}"
            );
            assert!(f.2.contains(&format!("--deg {}", f.0)), "{name}: {f:?}");
            println!("{name}, all in degrees: {}", f.2);
        }
        // Only phi in degrees: phi' is 57.3x the gyro and phi 57.3x the accelerometer.
        let r = run(&degrees(&rows, &[1]), &rig);
        let f = findings(&r);
        assert_eq!(f.len(), 1, "{name}: {f:?}");
        assert_eq!(f[0].0, "phi", "{name}: {f:?}");
        // Read with --deg, the same logs are quiet again.
        let fixed = run_with(
            &degrees(&rows, &[1, 2, 5]),
            &rig,
            ReaderOptions {
                limits: pendtilt::io::SensorLimits::of_rig(&rig),
                degrees: "phi,gyro,theta".parse().unwrap(),
                ..ReaderOptions::default()
            },
        );
        assert!(
            findings(&fixed).is_empty(),
            "{name}: {:?}",
            findings(&fixed)
        );
    }
}

/// `rows` as a log text with the accelerometer divided by `per` \[m/s^2 per unit\].
fn accel_in(rows: &[SimRow], per: f64) -> String {
    let mut c = cells(rows);
    for (row, r) in c.iter_mut().zip(rows) {
        row[3] = format!("{}", r.ax / per);
        row[4] = format!("{}", r.ay / per);
    }
    text(&c)
}

/// An accelerometer in g or mg read as m/s^2 (item 3; found as a new user):
/// the planar estimators read only its direction, so g changed no estimate and said
/// nothing, but mg put every reading beyond the full scale (every accelerometer reader
/// without an estimate, 10 of 103 024 impossible readings listed, no fix). Now the median
/// magnitude against gravity names the unit and the fix, `--accel-unit`, with which the
/// estimates are the m/s^2 log's; read with `--accel-unit g` when in m/s^2 it says to leave
/// it out. Correct logs stay quiet (here and in the two degree tests above, which check
/// every finding).
#[test]
fn an_accelerometer_in_g_or_mg_is_named_from_gravity_and_the_fix_works() {
    let (rows, rig) = ride("scooter", 10.0, 2);
    let right = run(&text(&cells(&rows)), &rig);
    assert!(findings(&right).is_empty(), "{:?}", findings(&right));
    let with_unit = |log: &str, unit: AccelUnit| {
        run_with(
            log,
            &rig,
            ReaderOptions {
                accel_unit: Some(unit),
                ..ReaderOptions::for_rig(&rig)
            },
        )
    };
    for unit in [AccelUnit::G, AccelUnit::MilliG] {
        let log = accel_in(&rows, unit.metres_per_second_squared());
        let wrong = run(&log, &rig);
        let f = findings(&wrong);
        assert_eq!(f.len(), 1, "{unit}: {f:?}");
        assert_eq!(f[0].0, "ax, ay");
        assert!(
            f[0].2.contains(&format!(
                "is the accelerometer in {unit}? read it with --accel-unit {unit}"
            )),
            "{}",
            f[0].2
        );
        println!("{unit}: {}", f[0].2);
        let fixed = with_unit(&log, unit);
        assert!(
            findings(&fixed).is_empty(),
            "{unit}: {:?}",
            findings(&fixed)
        );
        assert_eq!(fixed.implausible_count, 0);
        for (k, (a, b)) in right.est.iter().zip(&fixed.est).enumerate() {
            for (j, (a, b)) in a.iter().zip(b).enumerate() {
                assert!(
                    (a.theta - b.theta).abs() <= 1e-9 || (a.theta.is_nan() && b.theta.is_nan()),
                    "{unit} {} row {k}: {} against {}",
                    right.names[j],
                    a.theta,
                    b.theta
                );
            }
        }
    }
    // m/s^2 read as g.
    let twice = with_unit(&text(&cells(&rows)), AccelUnit::G);
    let f = findings(&twice);
    assert!(
        f.len() == 1
            && f[0]
                .2
                .contains("is it already in m/s^2? leave out --accel-unit g"),
        "{f:?}"
    );
}

/// A sensor that counts the other way from MODEL.md section 1's signs (found as a new
/// user): phi, gyro or ax negated on the scooter ride gave 12.0 deg RMS (alg2), 8.0
/// (ekf) and 3.8 (Mahony) with nothing said. Now the pairs that fit with the sign reversed
/// name the column, the accelerometer's angle the reference and the true angle, when the
/// log has it, telling ax from phi and gyro both; `--negate` fixes it, to the bit.
#[test]
fn a_column_counting_the_other_way_is_named_and_negate_fixes_it() {
    let (rows, rig) = ride("scooter", 10.0, 2);
    let base = cells(&rows);
    let right = run(&text(&base), &rig);
    let without_theta = |c: &[[String; 6]]| {
        let mut t = String::from("t,phi,gyro,ax,ay\n");
        for r in c {
            t.push_str(&r[..5].join(","));
            t.push('\n');
        }
        t
    };
    for (cols, with_theta, named) in [
        (&[1][..], true, "phi"),
        (&[2], true, "gyro"),
        (&[3], true, "ax"),
        (&[5], true, "theta"),
        (&[1, 2], true, "phi, gyro"),
        (&[1], false, "phi"),
        (&[2], false, "gyro"),
        // Without the true angle, ax reversed and phi and gyro both reversed look alike.
        (&[3], false, "phi, gyro"),
    ] {
        let mut c = base.clone();
        for row in c.iter_mut() {
            for &i in cols {
                row[i] = format!("{}", -row[i].parse::<f64>().unwrap());
            }
        }
        let log = if with_theta {
            text(&c)
        } else {
            without_theta(&c)
        };
        let case = format!("{cols:?} negated, theta {with_theta}");
        let wrong = run(&log, &rig);
        let f = findings(&wrong);
        assert_eq!(f.len(), 1, "{case}: {f:?}");
        assert_eq!(f[0].0, named, "{case}: {f:?}");
        println!("{case}: {}", f[0].2);
        let list: Vec<&str> = cols
            .iter()
            .map(|&i| ["t", "phi", "gyro", "ax", "ay", "theta"][i])
            .collect();
        let list = list.join(",");
        assert!(
            f[0].2.contains(&format!("--negate {list}")),
            "{case}: {}",
            f[0].2
        );
        let fixed = run_with(
            &log,
            &rig,
            ReaderOptions {
                negate: list.parse().unwrap(),
                ..ReaderOptions::for_rig(&rig)
            },
        );
        assert!(
            findings(&fixed).is_empty(),
            "{case}: {:?}",
            findings(&fixed)
        );
        for (k, (a, b)) in right.est.iter().zip(&fixed.est).enumerate() {
            for (j, (a, b)) in a.iter().zip(b).enumerate() {
                assert!(
                    a.theta.to_bits() == b.theta.to_bits(),
                    "{case}: {} row {k}: {} against {}",
                    right.names[j],
                    a.theta,
                    b.theta
                );
            }
        }
    }
}

/// Short logs (4 s): the gyro in deg/s and `--deg` given on a log in radians are found
/// (now the filters start on the mean of the first 50 ms and are read from one
/// period of their cutoff on, 1.8 s, where they waited 3.7 s after starting on one reading,
/// and none of these was said), and the correct logs stay quiet, a still one included (a
/// reference moving less than 0.5 deg gives no fit).
#[test]
fn degree_mistakes_on_a_4_s_log_are_found_and_correct_short_logs_are_quiet() {
    for name in ["step", "sine", "sigmoid", "scooter", "chirp", "still"] {
        for seed in [1, 2] {
            let (rows, rig) = ride(name, 4.0, seed);
            let case = format!("{name} seed {seed}");
            let clean = run(&text(&cells(&rows)), &rig);
            assert!(
                findings(&clean).is_empty(),
                "{case}: {:?}",
                findings(&clean)
            );
            if name == "still" {
                continue;
            }
            let r = run(&degrees(&rows, &[2]), &rig);
            let f = findings(&r);
            assert!(
                f.iter()
                    .any(|f| f.0 == "gyro" && f.2.contains("--deg gyro")),
                "{case}: {f:?}"
            );
            // In radians, read with --deg: 1/57.3 of the accelerometer's angle.
            let twice = run_with(
                &text(&cells(&rows)),
                &rig,
                ReaderOptions {
                    limits: pendtilt::io::SensorLimits::of_rig(&rig),
                    degrees: "phi,gyro,theta".parse().unwrap(),
                    ..ReaderOptions::default()
                },
            );
            let f = findings(&twice);
            assert!(
                f.iter()
                    .any(|f| f.0 == "phi" && f.2.contains("already in radians")),
                "{case}: {f:?}"
            );
        }
    }
}

#[test]
fn cutoffs_above_nyquist_or_below_the_floor_are_refused_with_the_valid_range() {
    let (rows, rig) = ride("step", 2.0, 1);
    let log = text(&cells(&rows));
    let refuse = |edit: &dyn Fn(&mut RigConfig), says: &[&str]| {
        let mut r = rig.clone();
        edit(&mut r);
        let e = run(&log, &r).result.unwrap_err().to_string();
        for s in says {
            assert!(e.contains(s), "{e}");
        }
    };
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::Hz(1000.0),
        &[
            "ride.csv: [differentiator] cutoff_hz = 1000 Hz is at or above the Nyquist frequency 500 Hz",
            "valid range: 1.09",
            "up to below 500 Hz",
        ],
    );
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::Hz(500.0),
        &["Nyquist frequency 500 Hz"],
    );
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::Hz(0.2),
        &["cutoff_hz = 0.2 Hz is below 0.5 f_n", "f_n = 2.186 Hz"],
    );
    refuse(
        &|r| r.differentiator.cutoff = Cutoff::TimesNatural(300.0),
        &["cutoff_times_natural = 300", "Nyquist"],
    );
    refuse(
        &|r| r.accel.prefilter_hz = Some(600.0),
        &["[accel] prefilter_hz = 600 Hz is at or above the Nyquist frequency 500 Hz"],
    );
    // Accepted: anything inside the range.
    for hz in [1.2, 2.8, 40.0, 400.0] {
        let mut r = rig.clone();
        r.differentiator.cutoff = Cutoff::Hz(hz);
        assert!(run(&log, &r).result.is_ok(), "{hz} Hz refused");
    }
    // At 100 Hz, 60 Hz is above Nyquist; 40 Hz is not.
    let mut s = Scenario::named("step").unwrap();
    s.rate = 100.0;
    s.duration = 2.0;
    let slow = text(&cells(&simulate(&s, 1).unwrap()));
    let mut r = rig.clone();
    r.differentiator.cutoff = Cutoff::Hz(60.0);
    assert!(run(&slow, &r)
        .result
        .unwrap_err()
        .to_string()
        .contains("Nyquist frequency 50 Hz"));
    r.differentiator.cutoff = Cutoff::Hz(40.0);
    assert!(run(&slow, &r).result.is_ok());
}
