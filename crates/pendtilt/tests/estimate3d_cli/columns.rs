//! The header: names with units in them, a name twice or unknown, `--map`, and a sensor
//! axis counting the other way.
use crate::common::estimate3d::{inv3d_stderr, level_log, simulate};
use crate::common::{pendtilt, s, stderr, write};
use std::path::Path;

/// A 3-D header with units in its names (`gyro_x[deg/s]`, `phi_y_deg`, `roll_deg`):
/// each named with the `sed` that renames it and `--deg` for degrees (was: the generic
/// missing-column error, and `roll_deg` silently unscored). The planar rule, reused.
#[test]
fn a_3d_header_with_units_in_its_names_is_named_with_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let clean = level_log(20, 1.0, None);
    let named = clean
        .replacen("gyro_x", "gyro_x[deg/s]", 1)
        .replacen("phi_y", "phi_y_deg", 1);
    let log = write(dir.path(), "u.csv", &named);
    let out = dir.path().join("est.csv");
    let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&out)]);
    let e = stderr(&o);
    assert!(!o.status.success());
    let fix = format!(
        "`phi_y_deg` is `phi_y`, `gyro_x[deg/s]` is `gyro_x` with their units in the name, \
         and a 3-D log's columns are read by their MODEL.md 7.6 names alone (no --map): \
         rename them: `sed -i '1s/phi_y_deg/phi_y/;1s/gyro_x\\[deg\\/s\\]/gyro_x/' {}`; \
         then read it with --deg",
        s(&log)
    );
    assert!(e.contains("u.csv:1: ") && e.contains(&fix), "{e}");
    // The library's 3-D reader gives the same fix.
    let e = pendtilt::io::read_log3d(&log).unwrap_err().to_string();
    assert!(
        e.contains("no `phi_y`, `gyro_x` column") && e.contains(&fix),
        "{e}"
    );
    // The sed given restores the header.
    let sed = std::process::Command::new("sed")
        .args([
            "-i",
            "1s/phi_y_deg/phi_y/;1s/gyro_x\\[deg\\/s\\]/gyro_x/",
            s(&log),
        ])
        .status()
        .unwrap();
    assert!(sed.success());
    assert_eq!(std::fs::read_to_string(&log).unwrap(), clean);
    // A truth in radians under its unit: read, warned as not scored, no --deg asked for.
    let with_truth = clean
        .replacen("az\n", "az,roll_rad,pitch\n", 1)
        .replace(",9.80665\n", ",9.80665,0,0\n");
    let log = write(dir.path(), "r.csv", &with_truth);
    let o = pendtilt(&["estimate", s(&log), "-o", s(&out)]);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("r.csv:1: `roll_rad` is `roll` with its unit in the name")
            && e.contains("`sed -i '1s/roll_rad/roll/'")
            && e.contains("until then no inclination error is scored")
            && !e.contains("--deg"),
        "{e}"
    );
    // Behind a logger's comment line the header is on line 2, and so is the sed (it said
    // `1s/`, which renamed nothing).
    let commented = format!("# logger 1.2\n{with_truth}");
    let log = write(dir.path(), "k.csv", &commented);
    let o = pendtilt(&["estimate", s(&log), "-o", s(&out)]);
    let e = stderr(&o);
    assert!(
        e.contains("k.csv:2: `roll_rad` is `roll`") && e.contains("`sed -i '2s/roll_rad/roll/'"),
        "{e}"
    );
    let sed = std::process::Command::new("sed")
        .args(["-i", "2s/roll_rad/roll/", s(&log)])
        .status()
        .unwrap();
    assert!(sed.success());
    let o = pendtilt(&["estimate", s(&log), "-o", s(&out)]);
    assert!(!stderr(&o).contains("in the name"), "{}", stderr(&o));
    // Plain names: no such words.
    let log = write(dir.path(), "c.csv", &clean);
    let o = pendtilt(&["estimate", s(&log), "-o", s(&out)]);
    assert!(!stderr(&o).contains("in the name"), "{}", stderr(&o));
}

/// A 3-D header with a column named twice and one missing names both, and an extra column
/// is said to be ignored, as the planar reader says it (earlier: `gyro_x` twice was
/// reported only as "no `gyro_y`", and a column `extra` was dropped without a word).
#[test]
fn a_3d_column_named_twice_or_unknown_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path(), "scooter3d", &["--duration", "0.5"]);
    let text = std::fs::read_to_string(&log).unwrap();
    let (head, rows) = text.split_once('\n').unwrap();
    let dup = write(
        dir.path(),
        "dup.csv",
        &format!("{}\n{rows}", head.replacen("gyro_y", "gyro_x", 1)),
    );
    let extra: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                format!("{l},extra\n")
            } else {
                format!("{l},1\n")
            }
        })
        .collect();
    let extra = write(dir.path(), "extra.csv", &extra);
    let out = dir.path().join("est.csv");
    let o = pendtilt(&["estimate", s(&dup), "-o", s(&out)]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains(
            "but no `gyro_y`, and `gyro_x` is fields 4 and 5: is one of them the missing one?"
        ),
        "{}",
        stderr(&o)
    );
    let o = pendtilt(&["estimate", s(&extra), "--only", "inv3d", "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: ")
            && stderr(&o).contains(
                "extra.csv:1: ignored, not a column of a 3-D log (MODEL.md 7.6): `extra`"
            ),
        "{}",
        stderr(&o)
    );
    let o = pendtilt(&["estimate", s(&log), "--only", "inv3d", "-o", s(&out)]);
    assert!(!stderr(&o).contains("ignored"), "{}", stderr(&o));
}

/// The 3-D log at `log` with the columns `names` negated, and without its true `roll` and
/// `pitch` unless `truth`.
fn negated(log: &Path, names: &[&str], truth: bool) -> String {
    let text = std::fs::read_to_string(log).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep = |h: &str| truth || (h != "roll" && h != "pitch");
    let row = |cells: Vec<String>| -> String {
        let kept: Vec<String> = (header.iter().zip(cells))
            .filter(|(h, _)| keep(h))
            .map(|(_, c)| c)
            .collect();
        kept.join(",") + "\n"
    };
    let mut out = row(header.iter().map(|h| h.to_string()).collect());
    for l in lines {
        let cells = l.split(',').zip(&header).map(|(c, h)| {
            if names.contains(h) {
                format!("{}", -c.parse::<f64>().unwrap())
            } else {
                c.to_string()
            }
        });
        out.push_str(&row(cells.collect()));
    }
    out
}

/// A 3-D sensor axis that counts the other way (found as a new user): on
/// scooter3d (30 s, seed 2) gyro_x negated gave ekf3d 11.3 deg RMS and the warning
/// `gyro_x is -1.0x the encoder's derivative ...: is the gyro in deg/s?` (a negative factor
/// passed as 57.3); phi_x negated, 13.3 deg with the same wrong warning; ay negated, VQF 8.0
/// deg and nothing said; ax negated, only the wheel-slip warning. Now each is named, from
/// the signs of the encoder, the gyro and the accelerometer's tilt about that axis, with
/// the column to negate; the correct log says nothing (and the six scenarios, above).
#[test]
fn a_3d_sensor_axis_counting_the_other_way_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(
        dir.path(),
        "scooter3d",
        &["--duration", "30", "--seed", "2"],
    );
    let rig = dir.path().join("scooter3d.rig.toml");
    let e = inv3d_stderr(&log, &rig);
    assert!(!e.contains("the other way"), "{e}");
    for (column, says) in [
        ("gyro_x", "gyro_x counts the other way from the encoder's d(phi_x)/dt and from the rate of the accelerometer's roll atan2(ay, az): is the gyro's axis reversed? negate gyro_x in the log"),
        ("gyro_y", "gyro_y counts the other way from the encoder's d(phi_y)/dt"),
        ("phi_x", "phi_x counts the other way from the accelerometer's roll atan2(ay, az) and from gyro_x: is the encoder's axis reversed? negate phi_x in the log"),
        ("phi_y", "phi_y counts the other way from the accelerometer's pitch"),
        ("ay", "the accelerometer's roll atan2(ay, az) counts the other way from phi_x and gyro_x: is ay reversed? negate ay in the log"),
        ("ax", "the accelerometer's pitch atan2(-ax, |(ay, az)|) counts the other way from phi_y and gyro_y: is ax reversed? negate ax in the log"),
    ] {
        let wrong = write(dir.path(), "neg.csv", &negated(&log, &[column], true));
        let e = inv3d_stderr(&wrong, &rig);
        assert!(e.contains(&format!("neg.csv: {says}")), "{column}: {e}");
        assert!(!e.contains("deg/s?") && !e.contains("is it in m/s?"), "{column}: {e}");
    }
    // Two columns reversed look like the third reversed alone: the true angle tells them
    // apart, and without it the message gives both.
    for (columns, truth, says) in [
        (&["gyro_x", "ay"][..], true, "gyro_x and the accelerometer's roll atan2(ay, az) both count the other way from phi_x and from the true roll: is the IMU turned half round? negate gyro_x and ay in the log"),
        (&["gyro_y", "gyro_x", "ax", "ay"][..], true, "gyro_y and the accelerometer's pitch atan2(-ax, |(ay, az)|) both count the other way from phi_y and from the true pitch"),
        (&["phi_x", "gyro_x"][..], true, "phi_x and gyro_x both count the other way from the accelerometer's roll atan2(ay, az) and from the true roll: are the encoder and the gyro both reversed? negate phi_x and gyro_x in the log"),
        (&["phi_x"][..], true, "negate phi_x in the log (MODEL.md"),
        (&["phi_x"][..], false, "negate phi_x in the log; or, if the IMU is turned half round, negate gyro_x and ay"),
        (&["ay"][..], false, "negate ay in the log; or, if the encoder and the gyro both are, negate phi_x and gyro_x"),
    ] {
        let wrong = write(dir.path(), "neg.csv", &negated(&log, columns, truth));
        let e = inv3d_stderr(&wrong, &rig);
        assert!(e.contains(says), "{columns:?}, truth {truth}: {e}");
    }
}

/// `--map` names a 3-D log's columns: a log under other names gives the estimates of the
/// same log under MODEL.md 7.6's names; mapped onto a name the header lacks, it is an
/// error naming it; and with `t` alone mapped it is refused, never read as planar.
#[test]
fn map_reads_a_3d_log_under_other_names() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = level_log(300, 1.0, None);
    let log = write(d, "log.csv", &text);
    let (head, body) = text.split_once('\n').unwrap();
    let renamed_head = head
        .replace("t,", "time,")
        .replace("phi_x", "enc_x")
        .replace("phi_y", "enc_y")
        .replace("gyro_x", "gx")
        .replace("gyro_y", "gy")
        .replace("gyro_z", "gz");
    assert!(renamed_head.starts_with("time,enc_x,"), "{renamed_head}");
    let other = write(d, "other.csv", &format!("{renamed_head}\n{body}"));
    let (a, b) = (d.join("a.csv"), d.join("b.csv"));
    let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&a)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let map = "t=time,phi_x=enc_x,phi_y=enc_y,gyro_x=gx,gyro_y=gy,gyro_z=gz";
    let o = pendtilt(&["estimate", s(&other), "--map", map, "-q", "-o", s(&b)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // A source the header lacks.
    let o = pendtilt(&[
        "estimate",
        s(&other),
        "--map",
        "t=time,phi_x=enc_x,phi_y=encoder_y,gyro_x=gx,gyro_y=gy,gyro_z=gz",
        "-o",
        s(&b),
    ]);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("--map phi_y=encoder_y: no column `encoder_y` in the header"),
        "{e}"
    );
    // `t` alone: not read as planar (only `accel` would run, on the wrong axes).
    let o = pendtilt(&["estimate", s(&other), "--map", "t=time", "-o", s(&b)]);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("a 3-D log under other names?") && e.contains("--map"),
        "{e}"
    );
    // A 3-D column mapped on a planar log.
    let planar = write(d, "p.csv", "t,phi,gyro\n0,0.1,0\n0.001,0.1,0\n");
    let o = pendtilt(&["estimate", s(&planar), "--map", "gyro_z=gyro", "-o", s(&b)]);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("p.csv:1: not a 3-D log: no `phi_x`, `phi_y`"),
        "{e}"
    );
}
