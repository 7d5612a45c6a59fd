//! Damaged cells, rows and files: said with where they are, flagged, never dropped.
use crate::common::estimate3d::{level_log, ok, simulate, HEAD};
use crate::common::{bin, pendtilt, s, stderr, write};

#[test]
fn a_corrupt_cell_names_file_line_and_column_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let log = write(
        dir.path(),
        "log.csv",
        &level_log(100, 1.0, Some((40, "0.04,0,0,abc,0,0,0,0,9.8"))),
    );
    let out = dir.path().join("est.csv");
    let o = pendtilt(&["estimate", s(&log), "-q", "-o", s(&out)]);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("log.csv:42: column 4 (`gyro_x`): not a number: `abc`"),
        "{e}"
    );
    assert!(!out.exists());
}

/// A missing cell and a time going back keep their rows, flagged; an angle in degrees
/// where radians are expected is read as missing with a warning naming its place.
#[test]
fn bad_rows_are_flagged_never_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = level_log(200, 1.0, Some((50, "0.05,0,,0,0,0,0,0,9.80665")));
    text = text.replace(
        "\n0.1,0,0,0,0,0,0,0,9.80665\n",
        "\n0.09,0,0,0,0,0,0,0,9.80665\n",
    );
    text = text.replace("\n0.15,0,0,", "\n0.15,45,0,");
    let log = write(dir.path(), "log.csv", &text);
    let out = dir.path().join("est.csv");
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "--flags",
        "--only",
        "ekf3d,pendulum3d",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("log.csv:152: column 2 (`phi_x`): 45 rad is beyond"),
        "{e}"
    );
    let out_text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = out_text.lines().collect();
    assert_eq!(lines.len(), 201);
    assert_eq!(
        lines[0],
        "t,pendulum3d_roll,pendulum3d_pitch,ekf3d_roll,ekf3d_pitch,pendulum3d_flags,ekf3d_flags"
    );
    for k in [51, 101, 151] {
        let cells: Vec<&str> = lines[k].split(',').collect();
        assert!(
            !cells[5].is_empty() && !cells[6].is_empty(),
            "row {k}: {}",
            lines[k]
        );
    }
    let calm: Vec<&str> = lines[120].split(',').collect();
    assert!(calm[5].is_empty() && calm[6].is_empty(), "{}", lines[120]);
    assert_eq!(calm[3].parse::<f64>().unwrap(), 0.0);
}

#[test]
fn a_3d_line_the_file_ends_in_has_its_cut_cell_missing() {
    // `0.1,0,0.03` cut from `0.1,0,0.0349,...`: phi_y reads as missing, the row flagged,
    // not as 0.03.
    let dir = tempfile::tempdir().unwrap();
    let mut text = level_log(100, 1.0, None);
    text.push_str("0.1,0,0.03");
    let log = write(dir.path(), "log.csv", &text);
    let out = dir.path().join("est.csv");
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "-q",
        "--only",
        "pendulum3d",
        "--flags",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(&out).unwrap();
    let last = csv.lines().last().unwrap();
    // t, pendulum3d_roll, pendulum3d_pitch (held at the level 0, not 0.03), the flags.
    assert_eq!(last, "0.1,0.0,0.0,sample_missing");
}

/// A 3-D log saved with a UTF-8 byte-order mark (Excel's "CSV UTF-8"), CRLF line ends and
/// a comment line reads as the plain log does, byte for byte (earlier: with the mark the
/// header's first name was read as `\u{feff}t`, the log taken for planar and refused by
/// `estimate` and `report` as "a 3-D log, and this command reads planar logs").
#[test]
fn a_3d_log_with_a_byte_order_mark_reads_as_without() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(dir.path(), "scooter3d", &["--duration", "1", "--seed", "2"]);
    let text = std::fs::read_to_string(&log).unwrap();
    let marked = format!("\u{feff}# logger 1.2\r\n{}", text.replace('\n', "\r\n"));
    let bom = write(dir.path(), "bom.csv", &marked);
    assert!(std::fs::read(&bom)
        .unwrap()
        .starts_with(b"\xEF\xBB\xBF# logger"));
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    ok(&["estimate", s(&log), "-q", "--flags", "-o", s(&a)]);
    ok(&["estimate", s(&bom), "-q", "--flags", "-o", s(&b)]);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let rep = dir.path().join("rep");
    ok(&["report", s(&bom), "-q", "--score-from", "0", "-o", s(&rep)]);
    assert!(rep.join("index.html").exists());
}

/// Two 3-D logs joined without a second header: an error on the row that runs on from
/// the earlier time, naming the line, and the commands it gives split the log into two
/// that `estimate` reads (earlier: exit 0, no word, the second half's rows held and
/// flagged `bad_time_step`, inv3d 5.4 deg RMS on scooter3d where it has 0.72).
#[test]
fn two_3d_logs_joined_are_refused_with_the_commands_that_split_them() {
    let dir = tempfile::tempdir().unwrap();
    let one = level_log(800, 1.0, None);
    let joined = format!("{one}{}", &one[HEAD.len() + 1..]);
    write(dir.path(), "joined.csv", &joined);
    let out = dir.path().join("est.csv");
    let o = bin()
        .current_dir(dir.path())
        .args(["estimate", "joined.csv", "-q", "-o", "est.csv"])
        .output()
        .unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(!out.exists());
    assert!(
        e.contains(
            "joined.csv:803: column 1 (`t`): the time went back on line 802 (0.799 then 0 s)"
        ),
        "{e}"
    );
    let cmd = e.split('`').rev().nth(1).unwrap();
    assert!(
        cmd.starts_with("head -n 801 joined.csv > first.csv"),
        "{cmd}"
    );
    let sh = std::process::Command::new("sh")
        .current_dir(dir.path())
        .args(["-c", cmd])
        .status()
        .unwrap();
    assert!(sh.success());
    for half in ["first.csv", "second.csv"] {
        assert_eq!(
            std::fs::read_to_string(dir.path().join(half)).unwrap(),
            one,
            "{half}"
        );
    }
}

/// A missing cell and a repeated time stamp in a 3-D log are said with their line, as the
/// planar reader says them; a burst lists the first three and counts the rest, apart from
/// the other warnings (earlier: the rows were flagged, and nothing was said).
#[test]
fn missing_cells_and_repeated_times_in_a_3d_log_are_said() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = level_log(2000, 1.0, Some((300, "0.3,0,0,nan,0,0,0,0,9.80665")));
    text = text.replace("\n0.5,0,0,", "\n0.499,0,0,");
    for k in 1000..1200 {
        text = text.replace(
            &format!("\n{},0,0,0,0,0,0,0,9.80665\n", k as f64 * 1e-3),
            &format!("\n{},0,0,0,0,0,,0,9.80665\n", k as f64 * 1e-3),
        );
    }
    let log = write(dir.path(), "log.csv", &text);
    let out = dir.path().join("est.csv");
    let o = pendtilt(&[
        "estimate",
        s(&log),
        "--only",
        "pendulum3d,ekf3d",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("log.csv:302: `gyro_x` empty, nan, infinite or absent: read as missing"),
        "{e}"
    );
    assert!(
        e.contains(
            "log.csv:502: column 1 (`t`): time repeated (0.499 then 0.499 s): the row is kept"
        ),
        "{e}"
    );
    assert!(e.contains("log.csv:1002: `ax` empty"), "{e}");
    assert!(e.contains("log.csv:1003: `ax` empty"), "{e}");
    assert!(!e.contains("log.csv:1004: `ax` empty"), "{e}");
    assert!(
        e.contains("log.csv: 201 rows with a missing sensor cell (flagged sample_missing), the first 3 listed"),
        "{e}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), 2001);
}
