//! The gyro's unit: deg/s found from the pendulum's frequency, from a vehicle's turns and
//! from the rig's full scale, and not blamed on the speed.
use crate::common::estimate3d::{inv3d_stderr, level_log, simulate};
use crate::common::{pendtilt, s, stderr, write};
use std::path::Path;

/// `[gyro] full_scale = 500` (meant deg/s) in a 3-D rig is doubted with the fix, as in a
/// planar one; 8.73 is not.
#[test]
fn a_3d_rigs_gyro_full_scale_in_deg_per_s_is_doubted_with_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let log = write(dir.path(), "log.csv", &level_log(20, 1.0, None));
    let out = dir.path().join("est.csv");
    let rig = write(
        dir.path(),
        "r.toml",
        "[pendulum3d]\n[gyro]\nfull_scale = 500\n",
    );
    let o = pendtilt(&["estimate", s(&log), "--params", s(&rig), "-o", s(&out)]);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("r.toml: gyro.full_scale: 500 rad/s is above 69.8 rad/s")
            && e.contains("write gyro.full_scale = 8.72665"),
        "{e}"
    );
    let rig = write(
        dir.path(),
        "r.toml",
        "[pendulum3d]\n[gyro]\nfull_scale = 8.73\n",
    );
    let o = pendtilt(&["estimate", s(&log), "--params", s(&rig), "-o", s(&out)]);
    assert!(!stderr(&o).contains("gyro.full_scale"), "{}", stderr(&o));
}

/// The factor printed after `prefix` in `e` (`57.2x ...`), and the text from it on.
fn factor_after<'a>(e: &'a str, prefix: &str) -> (f64, &'a str) {
    let at = e
        .find(prefix)
        .unwrap_or_else(|| panic!("`{prefix}` not found: {e}"));
    let rest = &e[at + prefix.len()..];
    (rest.split('x').next().unwrap().parse().unwrap(), rest)
}

/// The 3-D log at `log` with its gyro columns in deg/s.
fn gyro_in_degrees(log: &Path) -> String {
    let text = std::fs::read_to_string(log).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let gyro: Vec<usize> = header
        .split(',')
        .enumerate()
        .filter(|(_, h)| h.starts_with("gyro_"))
        .map(|(i, _)| i)
        .collect();
    let mut deg = format!("{header}\n");
    for l in lines {
        let cells: Vec<String> = l
            .split(',')
            .enumerate()
            .map(|(i, c)| {
                if gyro.contains(&i) {
                    c.parse::<f64>().unwrap().to_degrees().to_string()
                } else {
                    c.to_string()
                }
            })
            .collect();
        deg.push_str(&cells.join(","));
        deg.push('\n');
    }
    deg
}

/// Both gyro axes of `gdeg.csv` named as in deg/s against their encoder, each factor within
/// `tolerance` of 57.3: per axis, its name and the message from the factor on.
fn gyro_named_in_deg_per_s(e: &str, tolerance: f64) -> Vec<(&'static str, &str)> {
    [("gyro_x", "phi_x"), ("gyro_y", "phi_y")]
        .into_iter()
        .map(|(gyro, phi)| {
            let (factor, rest) = factor_after(e, &format!("gdeg.csv: {gyro} is "));
            assert!(
                rest.contains(&format!(
                    "x the encoder's derivative d({phi})/dt: is the gyro in deg/s?"
                )),
                "{e}"
            );
            assert!(
                (factor / 57.2958 - 1.0).abs() < tolerance,
                "{gyro}: {factor}"
            );
            (gyro, rest)
        })
        .collect()
}

/// The gyro's unit is judged below the rig's own pendulum's frequencies, axis by axis.
/// With the default planar rig's band (f_n 2.19 Hz), a 0.49 Hz pendulum's
/// swing entered the comparison: scooter3d's gyro in deg/s read as 52.2x and 56.0x the
/// encoders' derivatives, ship3d's as 43.2x on roll and was not found on pitch (found
/// now with the sensor's height fitted out, next test).
#[test]
fn a_3d_gyro_unit_is_judged_below_the_rigs_own_pendulum_frequency() {
    let dir = tempfile::tempdir().unwrap();
    // 20 times the inertia, the same damping ratio: f_n 2.19 Hz / sqrt(20) = 0.49 Hz.
    let long = write(
        dir.path(),
        "long.toml",
        "[rig.pendulum3d]\ninertia_xx = 0.0026\ninertia_yy = 0.0026\ndamping_x = 0.00478\n\
         damping_y = 0.00478\n",
    );
    let log = simulate(
        dir.path(),
        "scooter3d",
        &["--config", s(&long), "--duration", "60", "--seed", "1"],
    );
    let rig = dir.path().join("scooter3d.rig.toml");
    let deg = write(dir.path(), "gdeg.csv", &gyro_in_degrees(&log));
    let run = |log: &Path| inv3d_stderr(log, &rig);
    gyro_named_in_deg_per_s(&run(&deg), 0.02);
    let e = run(&log);
    assert!(!e.contains("deg/s"), "{e}");
}

/// On a ship the IMU rides high above the centre the hull rolls and pitches about (ship3d:
/// 5 m), and the specific force there leans by `-(h / g) theta''` besides the tilt: the
/// pendulum swings 1.4x the pitch and 1.8x its rate. The gyro's unit is judged with that
/// height fitted out (`units::Lever`): a gyro in deg/s is named on both axes
/// with its factor and the height found. Without it pitch read 34x and was not named
/// (beyond 1.5x of 57.3), roll 45x. The correct log says nothing.
#[test]
fn a_3d_gyro_unit_is_judged_with_the_sensors_height_above_the_rotation_fitted_out() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path(), "ship3d", &["--duration", "60", "--seed", "2"]);
    let rig = dir.path().join("ship3d.rig.toml");
    let deg = write(dir.path(), "gdeg.csv", &gyro_in_degrees(&log));
    let e = inv3d_stderr(&deg, &rig);
    // 56.5x and 57.8x measured.
    for (gyro, rest) in gyro_named_in_deg_per_s(&e, 0.03) {
        let at = rest.find("swing of a sensor ").expect(&e) + "swing of a sensor ".len();
        let height: f64 = rest[at..].split(' ').next().unwrap().parse().unwrap();
        // The IMU is 5 m above O (MODEL.md 7, ship3d): 4.7 and 5.1 m found.
        assert!((height - 5.0).abs() < 0.5, "{gyro}: {height} m");
    }
    let e = inv3d_stderr(&log, &rig);
    assert!(!e.contains("deg/s"), "{e}");
}

/// A 3-D log's gyro in deg/s is named from the physics (d(phi_x)/dt ~ gyro_x, d(phi_y)/dt ~
/// gyro_y below the pendulum's frequency), and the slip warning it used to set off alone,
/// which blamed the speed's unit, is left out (earlier: scooter3d with the gyro in deg/s
/// gave inv3d 47 deg RMS and only `wheel slip flagged on 97 % of the rows ...; is it in
/// m/s?`). Correct logs say nothing.
#[test]
fn a_3d_gyro_in_deg_per_s_is_named_not_blamed_on_the_speed() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path(), "scooter3d", &["--duration", "8", "--seed", "3"]);
    let deg = write(dir.path(), "gdeg.csv", &gyro_in_degrees(&log));
    let out = dir.path().join("est.csv");
    let run = |log: &Path, extra: &[&str]| {
        let mut args = vec!["estimate", s(log), "--only", "inv3d", "-o", s(&out)];
        args.extend_from_slice(extra);
        let o = pendtilt(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stderr(&o)
    };
    let e = run(&deg, &[]);
    assert!(
        e.contains("gdeg.csv: gyro_x is ")
            && e.contains("x the encoder's derivative d(phi_x)/dt: is the gyro in deg/s?"),
        "{e}"
    );
    assert!(!e.contains("is it in m/s?"), "{e}");
    let e = run(&log, &[]);
    assert!(!e.contains("deg/s") && !e.contains("slip"), "{e}");
    // Read with --deg the encoder is scaled with the gyro: no finding on a correct log.
    let e = run(&log, &["--deg"]);
    assert!(!e.contains("deg/s"), "{e}");
}

/// A vehicle log's gyro in deg/s is found from its turns, where the encoders cannot tell
/// (a car's turns swing its pendulum outward): the yaw rate against the lateral
/// acceleration over the speed (earlier: ride3d's gyro in deg/s was said only by the
/// slip warning, which blamed the speed's unit first). Correct logs say nothing.
#[test]
fn a_vehicle_gyro_in_deg_per_s_is_found_from_its_turns() {
    let dir = tempfile::tempdir().unwrap();
    for seed in ["1", "2"] {
        let log = simulate(dir.path(), "ride3d", &["--duration", "60", "--seed", seed]);
        let rig = dir.path().join("ride3d.rig.toml");
        let deg = write(dir.path(), "zdeg.csv", &gyro_in_degrees(&log));
        let run = |log: &Path| inv3d_stderr(log, &rig);
        let e = run(&deg);
        let (factor, rest) = factor_after(&e, "zdeg.csv: gyro_z is ");
        assert!(rest.starts_with(&format!(
            "{factor:.1}x the yaw rate the turns imply (the lateral acceleration over the speed, a_y / v): is the gyro in deg/s?"
        )));
        // 54.4 and 47.6 measured against 57.3: the roll's share of gravity in a_y.
        assert!(factor > 45.0 && factor < 65.0, "seed {seed}: {factor}");
        assert!(!e.contains("is it in m/s?"), "{e}");
        let e = run(&log);
        assert!(!e.contains("deg/s"), "seed {seed}: {e}");
    }
}
