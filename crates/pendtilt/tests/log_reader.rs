//! The sensor-log reader on good and bad files: each case gives an
//! error naming file, line and column, or a kept (flagged / NaN) sample with a warning;
//! never a panic, never a dropped row. The cases and outcomes are tabled in
//! docs/bad-input.md.
use std::f64::consts::PI;

use pendtilt::io::{
    Column, LogError, LogErrorKind, LogReader, LogRecord, LogWarning, ReaderOptions, TimeUnit,
    WarningKind,
};

fn open(text: &str, options: ReaderOptions) -> Result<LogReader<&[u8]>, LogError> {
    LogReader::new(text.as_bytes(), "log.csv", options)
}

/// Reads everything: the records, the warnings, and the error that stopped the read.
fn read_all(
    text: &str,
    options: ReaderOptions,
) -> (Vec<LogRecord>, Vec<LogWarning>, Option<LogError>) {
    let mut reader = match open(text, options) {
        Ok(r) => r,
        Err(e) => return (Vec::new(), Vec::new(), Some(e)),
    };
    let mut records = Vec::new();
    let mut warnings: Vec<LogWarning> = reader.drain_warnings().collect();
    let mut error = None;
    loop {
        match reader.next_record() {
            Ok(Some(r)) => records.push(r),
            Ok(None) => break,
            Err(e) => {
                error = Some(e);
                break;
            }
        }
        warnings.extend(reader.drain_warnings());
    }
    warnings.extend(reader.drain_warnings());
    (records, warnings, error)
}

fn ok(text: &str) -> (Vec<LogRecord>, Vec<LogWarning>) {
    let (records, warnings, error) = read_all(text, ReaderOptions::default());
    if let Some(e) = error {
        panic!("unexpected error: {e}");
    }
    (records, warnings)
}

fn fails(text: &str, options: ReaderOptions) -> LogError {
    let (_, _, error) = read_all(text, options);
    error.expect("expected an error")
}

const GOOD: &str = "t,phi,gyro,ax,ay,theta\n\
0.000,0.01,0.1,0.5,9.8,0.011\n\
0.001,0.02,0.2,0.6,9.7,0.021\n\
0.002,0.03,0.3,0.7,9.6,0.031\n";

#[test]
fn good_log_reads_every_column() {
    let (records, warnings) = ok(GOOD);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(records.len(), 3);
    let r = &records[1];
    assert_eq!(r.line, 3);
    assert_eq!(
        (r.t, r.sample.phi, r.sample.gyro, r.sample.ax, r.sample.ay),
        (0.001, 0.02, 0.2, 0.6, 9.7)
    );
    assert_eq!(r.theta, Some(0.021));
    assert!(r.issues.is_clean());
    let reader = open(GOOD, ReaderOptions::default()).unwrap();
    assert!(reader.columns().missing().is_empty());
    assert!(reader.columns().ignored.is_empty());
}

#[test]
fn empty_file_is_an_error() {
    for text in ["", "\n\n", "# only a comment\n"] {
        let e = fails(text, ReaderOptions::default());
        assert!(matches!(*e.kind, LogErrorKind::Empty), "{e}");
        assert_eq!(e.to_string(), "log.csv: the file is empty: no header row");
    }
}

#[test]
fn header_only_is_an_error() {
    let e = fails("t,phi\n", ReaderOptions::default());
    assert!(matches!(*e.kind, LogErrorKind::NoData), "{e}");
    assert_eq!(e.line, Some(1));
    assert_eq!(e.to_string(), "log.csv:1: header only, no data rows");
}

#[test]
fn missing_time_column_is_an_error_with_a_hint() {
    let e = fails("time,phi\n0,1\n", ReaderOptions::default());
    assert!(matches!(*e.kind, LogErrorKind::MissingTime { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.starts_with("log.csv:1: no `t` column"), "{msg}");
    assert!(
        msg.contains("time, phi") && msg.contains("--map t="),
        "{msg}"
    );

    let e = fails("0,0.1,0.2\n0.001,0.1,0.2\n", ReaderOptions::default());
    assert!(e.to_string().contains("looks like data"), "{e}");

    let e = fails("T,phi\n0,1\n", ReaderOptions::default());
    assert!(e.to_string().contains("did you mean `T`"), "{e}");

    let e = fails("t;phi;gyro\n0;1;2\n", ReaderOptions::default());
    assert!(e.to_string().contains("separated by `;`"), "{e}");
    // The fix, not only the question (earlier: the CLI has no delimiter option).
    assert!(
        e.to_string().contains(
            "the log must be comma-separated: convert it with `tr ';' ',' < log.csv > \
             log_commas.csv` (numbers with a decimal comma, `0,5`: `sed 's/,/./g'` first)"
        ),
        "{e}"
    );
    let e = fails("t\tphi\n0\t1\n", ReaderOptions::default());
    assert!(e.to_string().contains("separated by tabs"), "{e}");
    assert!(e.to_string().contains("`tr '\\t' ','"), "{e}");
    let semicolon = ReaderOptions {
        delimiter: b';',
        ..ReaderOptions::default()
    };
    let (records, _, error) = read_all("t;phi;gyro\n0;1;2\n", semicolon);
    assert!(error.is_none());
    assert_eq!(records[0].sample.gyro, 2.0);
}

#[test]
fn a_time_column_under_another_name_is_named_in_the_hint() {
    // A new user's `time` got `--map t=NAME`, the fix left to guess.
    let hint = |header: &str| {
        let e = fails(
            &format!("{header},phi,gyro\n0,1,2\n"),
            ReaderOptions::default(),
        );
        assert!(matches!(*e.kind, LogErrorKind::MissingTime { .. }), "{e}");
        e.to_string()
    };
    for (header, fix) in [
        ("time", "did you mean `time`? (--map t=time)"),
        ("timestamp", "did you mean `timestamp`? (--map t=timestamp)"),
        ("Time", "did you mean `Time`? (--map t=Time)"),
        ("Time [s]", "did you mean `Time [s]`? (--map 't=Time [s]')"),
        ("t_s", "(--map t=t_s)"),
        ("seconds", "(--map t=seconds)"),
        // A smaller unit in the name: its --time-unit too.
        ("time_ms", "(--map t=time_ms --time-unit ms)"),
        (
            "Timestamp (us)",
            "(--map 't=Timestamp (us)' --time-unit us)",
        ),
    ] {
        let msg = hint(header);
        assert!(msg.contains(fix), "{header}: {msg}");
    }
    // Names that are not time: the general hint, never a guess.
    for header in ["temp", "t_env", "theta_ref"] {
        let msg = hint(header);
        assert!(
            msg.contains("name the time column with --map t=NAME"),
            "{header}: {msg}"
        );
    }
    // With --time-unit already given, it is not asked for again.
    let ms = ReaderOptions {
        time_unit: Some(TimeUnit::Ms),
        ..ReaderOptions::default()
    };
    let e = fails("time_ms,phi\n0,1\n", ms);
    assert!(e.to_string().contains("(--map t=time_ms)"), "{e}");
}

#[test]
fn missing_optional_columns_are_reported_not_errors() {
    let text = "t,phi,temp\n0,0.1,20\n";
    let reader = open(text, ReaderOptions::default()).unwrap();
    let cols = reader.columns();
    assert!(cols.has(Column::Phi) && !cols.has(Column::Gyro));
    assert_eq!(
        cols.missing(),
        vec![Column::Gyro, Column::Ax, Column::Ay, Column::Theta]
    );
    assert_eq!(cols.ignored, vec!["temp".to_string()]);
    assert_eq!(
        cols.to_string(),
        "columns: t, phi; missing: gyro, ax, ay, theta; ignored: temp"
    );
    let (records, _) = ok(text);
    assert!(records[0].sample.gyro.is_nan() && records[0].theta.is_none());
}

#[test]
fn case_mismatch_is_suggested_never_guessed() {
    let reader = open("t,Phi\n0,1\n", ReaderOptions::default()).unwrap();
    assert!(!reader.columns().has(Column::Phi));
    let s = reader.columns().to_string();
    assert!(s.contains("--map phi=Phi"), "{s}");
}

#[test]
fn duplicate_used_column_is_an_error_naming_both_fields() {
    let e = fails("t,phi,gyro,phi\n0,1,2,3\n", ReaderOptions::default());
    assert!(
        matches!(*e.kind, LogErrorKind::DuplicateColumn { first: 2, .. }),
        "{e}"
    );
    assert_eq!(e.line, Some(1));
    assert_eq!(e.column.as_ref().unwrap().position, 4);
    let msg = e.to_string();
    assert!(
        msg.starts_with("log.csv:1: column 4 (`phi`): duplicate column"),
        "{msg}"
    );
    assert!(msg.contains("field 2"), "{msg}");
}

#[test]
fn duplicate_ignored_column_is_a_warning() {
    let (records, warnings) = ok("t,temp,temp\n0,1,2\n");
    assert_eq!(records.len(), 1);
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].kind, WarningKind::DuplicateIgnoredColumn);
    assert!(
        warnings[0]
            .to_string()
            .starts_with("log.csv:1: column `temp`"),
        "{}",
        warnings[0]
    );
}

#[test]
fn non_numeric_cell_is_an_error_naming_line_column_and_text() {
    let text = "t,phi,gyro\n0,0.1,0.2\n0.001,abc,0.2\n0.002,0.1,0.2\n";
    let (records, _, error) = read_all(text, ReaderOptions::default());
    assert_eq!(records.len(), 1, "rows before the bad one are delivered");
    let e = error.unwrap();
    assert!(matches!(*e.kind, LogErrorKind::NotANumber { ref text, .. } if text == "abc"));
    assert_eq!(e.line, Some(3));
    assert_eq!(
        e.to_string(),
        "log.csv:3: column 2 (`phi`): not a number: `abc`"
    );
}

#[test]
fn nan_inf_and_empty_cells_are_missing_samples_with_warnings() {
    let text =
        "t,phi,gyro,theta\n0,nan,0.1,0\n0.001,0.2,inf,0\n0.002,0.3,,-Infinity\n0.003,0.4,0.4,0\n";
    let (records, warnings) = ok(text);
    assert_eq!(records.len(), 4, "no row dropped");
    assert!(records[0].sample.phi.is_nan() && records[0].issues.missing_values);
    assert!(records[1].sample.gyro.is_nan() && records[1].sample.phi == 0.2);
    assert!(records[2].sample.gyro.is_nan());
    assert!(records[2].theta.unwrap().is_nan());
    assert!(records[3].issues.is_clean());
    let kinds: Vec<WarningKind> = warnings.iter().map(|w| w.kind).collect();
    assert_eq!(
        kinds,
        vec![
            WarningKind::NonFinite,
            WarningKind::NonFinite,
            WarningKind::EmptyCell,
            WarningKind::NonFinite
        ]
    );
    assert_eq!(warnings[0].line, 2);
    assert_eq!(warnings[0].column, Some(Column::Phi));
    assert!(warnings[2]
        .to_string()
        .starts_with("log.csv:4: column `gyro`: empty cell"));
    let mut reader = open(text, ReaderOptions::default()).unwrap();
    while reader.next_record().unwrap().is_some() {}
    assert_eq!(reader.summary().missing(Column::Gyro), 2);
    assert_eq!(reader.summary().missing(Column::Phi), 1);
    assert_eq!(reader.summary().count(WarningKind::NonFinite), 3);
}

#[test]
fn a_number_beyond_f64_is_quoted_as_written_not_as_inf() {
    // Was: column `phi`: `inf`: read as missing (the log held 1e400).
    let text = "t,phi,gyro\n0,1e400,0.1\n0.001,0.2,-1e400\n0.002,0.3,inf\n0.003,nan,-Infinity\n";
    let (records, warnings) = ok(text);
    assert_eq!(records.len(), 4, "no row dropped");
    let w: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w[0].starts_with(
            "log.csv:2: column `phi`: `1e400` is beyond the largest number, 1.8e308 (inf): read \
             as missing"
        ),
        "{w:?}"
    );
    assert!(
        w[1].contains("`-1e400` is beyond the largest number"),
        "{w:?}"
    );
    assert!(
        w[2].contains("column `gyro`: `inf`: read as missing"),
        "{w:?}"
    );
    // As written, not as Rust prints them (earlier: `nan` was quoted `NaN`).
    assert!(
        w[3].contains("column `phi`: `nan`: read as missing"),
        "{w:?}"
    );
    assert!(
        w[4].contains("column `gyro`: `-Infinity`: read as missing"),
        "{w:?}"
    );
}

#[test]
fn time_repeated_or_backwards_is_kept_and_flagged() {
    let text = "t,phi\n0,0\n0.001,0\n0.001,0\n0.0005,0\n0.002,0\n";
    let (records, warnings) = ok(text);
    assert_eq!(records.len(), 5, "no row dropped");
    let bad: Vec<bool> = records.iter().map(|r| r.issues.bad_time).collect();
    assert_eq!(bad, vec![false, false, true, true, false]);
    assert_eq!(
        records[2].t, 0.001,
        "time passed through for the estimators to flag"
    );
    let time: Vec<&LogWarning> = warnings
        .iter()
        .filter(|w| w.kind == WarningKind::TimeNotIncreasing)
        .collect();
    assert_eq!(time.len(), 2);
    assert_eq!(time[0].line, 4);
    assert!(time[0].message.contains("repeated"), "{}", time[0]);
    assert_eq!(time[1].line, 5);
    assert!(time[1].message.contains("goes back"), "{}", time[1]);
    assert!(
        time[1].to_string().starts_with("log.csv:5: column `t`:"),
        "{}",
        time[1]
    );
}

#[test]
fn missing_time_cell_is_kept_and_flagged() {
    let (records, warnings) = ok("t,phi\n0,0\n,0.1\nnan,0.2\n0.003,0\n");
    assert_eq!(records.len(), 4);
    assert!(records[1].t.is_nan() && records[1].issues.bad_time);
    assert!(records[2].t.is_nan() && records[2].issues.bad_time);
    assert!(warnings
        .iter()
        .any(|w| w.kind == WarningKind::TimeMissing && w.line == 3));
}

fn regular(n: usize, dt: f64) -> String {
    let mut s = String::from("t,phi\n");
    for k in 0..n {
        s.push_str(&format!("{},0\n", k as f64 * dt));
    }
    s
}

#[test]
fn gap_in_time_is_a_warning_with_its_line() {
    let mut text = regular(20, 0.001);
    text.push_str("0.5,0\n0.501,0\n");
    let (records, warnings) = ok(&text);
    assert_eq!(records.len(), 22);
    let gaps: Vec<&LogWarning> = warnings
        .iter()
        .filter(|w| w.kind == WarningKind::TimeGap)
        .collect();
    assert_eq!(gaps.len(), 1, "{warnings:?}");
    assert_eq!(gaps[0].line, 22);
    assert!(records[20].issues.time_gap && !records[21].issues.time_gap);
    assert!(gaps[0].message.contains("0.019 to 0.5"), "{}", gaps[0]);
}

#[test]
fn dt_jitter_is_counted_and_the_first_ones_listed() {
    let mut text = String::from("t,phi\n");
    let mut t = 0.0;
    for k in 0..200 {
        text.push_str(&format!("{t},0\n"));
        // Every tenth step is 1.8 nominal steps: jitter, not a gap.
        t += if k % 10 == 9 { 0.0018 } else { 0.001 };
    }
    let options = ReaderOptions {
        max_reported: 5,
        ..ReaderOptions::default()
    };
    let mut reader = open(&text, options).unwrap();
    let mut rows = 0;
    let mut messages = Vec::new();
    while reader.next_record().unwrap().is_some() {
        rows += 1;
        messages.extend(
            reader
                .drain_warnings()
                .filter(|w| w.kind == WarningKind::TimeJitter)
                .map(|w| w.message),
        );
    }
    assert_eq!(rows, 200);
    assert_eq!(messages.len(), 5);
    // The steps as the log meant them, not a difference's rounding noise
    // (0.0018000000000000004 s against 0.0010000000000000009 s).
    assert!(
        messages
            .iter()
            .all(|m| m == "time step 0.0018 s against a nominal 0.001 s (jitter)"),
        "{messages:?}"
    );
    let s = reader.summary();
    assert_eq!(s.count(WarningKind::TimeJitter), 19);
    assert_eq!(s.count(WarningKind::TimeGap), 0);
    assert_eq!(s.warnings_not_listed, 14);
    assert!((s.nominal_dt.unwrap() - 0.001).abs() < 1e-12);
    assert!((s.max_dt.unwrap() - 0.0018).abs() < 1e-9);
}

#[test]
fn crlf_bom_comments_and_blank_lines_keep_true_line_numbers() {
    let text =
        "\u{feff}# rig 3, run 7\r\n\r\nt,phi\r\n# calibration pause\r\n0,0.1\r\n\r\n0.001,0.2\r\n";
    let (records, warnings) = ok(text);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(records.len(), 2);
    assert_eq!((records[0].line, records[0].sample.phi), (5, 0.1));
    assert_eq!((records[1].line, records[1].sample.phi), (7, 0.2));
    // The BOM on the header line itself.
    let (records, _) = ok("\u{feff}t,phi\r\n0,1\r\n");
    assert_eq!(records[0].sample.phi, 1.0);
}

#[test]
fn truncated_last_line_is_kept_with_missing_cells() {
    // A short line that ends with a line feed: its cells are whole.
    let (records, warnings) = ok("t,phi,gyro\n0,0.1,0.2\n0.001,0.1\n");
    assert_eq!(records.len(), 2);
    let last = &records[1];
    assert_eq!((last.line, last.t, last.sample.phi), (3, 0.001, 0.1));
    assert!(last.sample.gyro.is_nan());
    assert!(last.issues.truncated && last.issues.missing_values);
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].kind, WarningKind::TruncatedRow);
    assert!(warnings[0]
        .to_string()
        .starts_with("log.csv:3: 2 fields, the header has 3"));
    assert!(!warnings[0].to_string().contains("cut short"));
    // The input ends in the line (a log cut while written): its last cell may be cut short
    // (`0.1` of `0.1234`), so it reads as missing too (earlier: it was read as 0.1).
    let (records, warnings) = ok("t,phi,gyro\n0,0.1,0.2\n0.001,0.1");
    assert_eq!(records.len(), 2);
    let last = &records[1];
    assert_eq!((last.line, last.t), (3, 0.001));
    assert!(last.sample.phi.is_nan() && last.sample.gyro.is_nan());
    assert!(last.issues.truncated && last.issues.missing_values);
    assert_eq!(
        warnings[0].to_string(),
        "log.csv:3: 2 fields, the header has 3 (a truncated line?): the absent cells read as \
         missing; the input ends in this line, so its last cell `0.1` (field 2, `phi`) may be \
         cut short and reads as missing too"
    );
    // Cut in the time cell: the row is kept, its time missing and flagged.
    let (records, _) = ok("t,phi,gyro\n0,0.1,0.2\n0.00");
    assert_eq!(records.len(), 2);
    assert!(records[1].t.is_nan() && records[1].issues.bad_time);
    // A whole last line without a line feed is read as it is.
    let (records, warnings) = ok("t,phi,gyro\n0,0.1,0.2\n0.001,0.1,0.3");
    assert_eq!(records[1].sample.gyro, 0.3);
    assert!(warnings.is_empty());
}

#[test]
fn too_many_fields_is_an_error_but_a_trailing_comma_is_not() {
    let e = fails("t,phi\n0,1\n0.001,1,7\n", ReaderOptions::default());
    assert!(matches!(
        *e.kind,
        LogErrorKind::TooManyFields {
            found: 3,
            expected: 2
        }
    ));
    assert_eq!(e.to_string(), "log.csv:3: 3 fields, the header has 2");
    let (records, _) = ok("t,phi\n0,1,\n");
    assert_eq!(records[0].sample.phi, 1.0);
}

#[test]
fn angles_that_look_like_degrees_are_warned_once_per_column() {
    let text = "t,phi,gyro,theta\n0,10,0,10\n0.001,45,100,45\n0.002,50,0,50\n";
    let (records, warnings) = ok(text);
    assert_eq!(records[1].sample.phi, 45.0, "not converted without --deg");
    let deg: Vec<&LogWarning> = warnings
        .iter()
        .filter(|w| w.kind == WarningKind::LooksLikeDegrees)
        .collect();
    assert_eq!(deg.len(), 3, "{deg:?}");
    assert_eq!((deg[0].column, deg[0].line), (Some(Column::Phi), 2));
    assert!(deg[0].message.contains("--deg phi"), "{}", deg[0]);
    assert_eq!((deg[1].column, deg[1].line), (Some(Column::Theta), 2));
    assert_eq!((deg[2].column, deg[2].line), (Some(Column::Gyro), 3));
    assert!(deg[2].message.contains("--deg gyro"), "{}", deg[2]);
    // Radians that stay within a turn are not warned about.
    let (_, warnings) = ok("t,phi,theta\n0,3.1,-3.1\n");
    assert!(warnings.is_empty());
}

#[test]
fn degrees_option_converts_chosen_columns_only() {
    // gyro 90: read as rad/s it is within the default physical bound (100 rad/s).
    let text = "t,phi,gyro,theta,ax\n0,90,90,-45,90\n";
    let all = ReaderOptions {
        degrees: "all".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let (records, warnings, error) = read_all(text, all);
    assert!(error.is_none() && warnings.is_empty(), "{warnings:?}");
    let r = records[0];
    assert!((r.sample.phi - PI / 2.0).abs() < 1e-15);
    assert!((r.sample.gyro - PI / 2.0).abs() < 1e-15);
    assert!((r.theta.unwrap() + PI / 4.0).abs() < 1e-15);
    assert_eq!(r.sample.ax, 90.0, "accelerometer is never converted");

    let phi_only = ReaderOptions {
        degrees: "phi".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let (records, _, _) = read_all(text, phi_only);
    assert!((records[0].sample.phi - PI / 2.0).abs() < 1e-15);
    assert_eq!(records[0].sample.gyro, 90.0);
    let reader = open(
        text,
        ReaderOptions {
            degrees: "phi".parse().unwrap(),
            ..ReaderOptions::default()
        },
    )
    .unwrap();
    assert!(reader.columns().to_string().contains("phi (deg)"));
}

#[test]
fn column_map_reads_other_names() {
    let text = "time_s,enc_angle,gz,phi\n0,0.5,0.25,9\n";
    let options = ReaderOptions {
        map: "t=time_s,phi=enc_angle,gyro=gz".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let reader = open(text, options.clone()).unwrap();
    let cols = reader.columns();
    assert_eq!(
        cols.status(Column::Phi).source.as_deref(),
        Some("enc_angle")
    );
    assert!(cols.status(Column::Phi).mapped);
    assert_eq!(cols.ignored, vec!["phi".to_string()]);
    assert!(cols
        .to_string()
        .starts_with("columns: t <- time_s, phi <- enc_angle, gyro <- gz"));
    let (records, _, error) = read_all(text, options);
    assert!(error.is_none());
    assert_eq!(
        (records[0].t, records[0].sample.phi, records[0].sample.gyro),
        (0.0, 0.5, 0.25)
    );
}

#[test]
fn a_header_column_mapped_elsewhere_does_not_also_feed_its_own_name() {
    let options = ReaderOptions {
        map: "theta=phi".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let reader = open("t,phi\n0,1\n", options).unwrap();
    assert!(reader.columns().has(Column::Theta));
    assert!(!reader.columns().has(Column::Phi));
}

#[test]
fn mapping_onto_an_absent_column_is_an_error() {
    let options = ReaderOptions {
        map: "phi=enc".parse().unwrap(),
        ..ReaderOptions::default()
    };
    let e = fails("t,encoder\n0,1\n", options);
    assert!(matches!(*e.kind, LogErrorKind::MappedSourceMissing { .. }));
    let msg = e.to_string();
    assert!(
        msg.starts_with("log.csv:1: --map phi=enc: no column `enc`"),
        "{msg}"
    );
    assert!(msg.contains("t, encoder"), "{msg}");
}

#[test]
fn quoted_header_and_cells() {
    let (records, _) = ok("\"t\",\"phi\"\n\"0\",\"0.5\"\n");
    assert_eq!(records[0].sample.phi, 0.5);
    let e = fails("t,phi\n0,\"0.5\n", ReaderOptions::default());
    assert!(matches!(*e.kind, LogErrorKind::UnterminatedQuote));
    assert_eq!(
        e.to_string(),
        "log.csv:2: column 2 (`phi`): a quoted field is not closed on its line"
    );
}

#[test]
fn invalid_utf8_is_an_error_not_a_panic() {
    let bytes: &[u8] = b"t,phi\n0,\xff\n";
    let mut reader = LogReader::new(bytes, "log.csv", ReaderOptions::default()).unwrap();
    let e = reader.next_record().unwrap_err();
    assert!(matches!(*e.kind, LogErrorKind::NotANumber { .. }));
    assert_eq!(e.line, Some(2));
    let e = LogReader::new(
        &b"t,\xffphi\n0,1\n"[..],
        "log.csv",
        ReaderOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(*e.kind, LogErrorKind::InvalidUtf8));
}

#[test]
fn utf16_file_is_named_as_such() {
    let bytes: &[u8] = b"\xFF\xFEt\x00,\x00p\x00\n\x00";
    let e = LogReader::new(bytes, "log.csv", ReaderOptions::default()).unwrap_err();
    assert!(matches!(*e.kind, LogErrorKind::Utf16), "{e}");
    assert_eq!(
        e.to_string(),
        "log.csv:1: the file is UTF-16 text; save it as UTF-8 (or ASCII)"
    );
}

#[test]
fn missing_file_names_it() {
    let e = LogReader::open("/nonexistent/log.csv", ReaderOptions::default()).unwrap_err();
    assert!(matches!(*e.kind, LogErrorKind::Io(_)));
    assert!(
        e.to_string()
            .starts_with("/nonexistent/log.csv: cannot read"),
        "{e}"
    );
}

#[test]
fn iterator_yields_every_row_then_stops_after_an_error() {
    let reader = open("t\n0\n1\nx\n3\n", ReaderOptions::default()).unwrap();
    let items: Vec<Result<LogRecord, LogError>> = reader.collect();
    assert_eq!(items.len(), 3);
    assert!(items[0].is_ok() && items[1].is_ok() && items[2].is_err());
}

#[test]
fn streaming_from_a_file_gives_one_record_per_row() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    writeln!(f, "t,phi,gyro,ax,ay,theta").unwrap();
    let n = 50_000;
    for k in 0..n {
        let t = k as f64 * 1e-3;
        writeln!(f, "{t},{},{},0,9.8,{}", t.sin(), t.cos(), t.sin()).unwrap();
    }
    drop(f);
    let mut reader = LogReader::open(&path, ReaderOptions::default()).unwrap();
    let mut count = 0u64;
    let mut last_line = 0;
    while let Some(r) = reader.next_record().unwrap() {
        count += 1;
        assert_eq!(r.line, last_line + 1 + u64::from(last_line == 0));
        last_line = r.line;
    }
    assert_eq!(count, n);
    assert_eq!(reader.summary().rows, n);
    assert_eq!(reader.summary().total_warnings(), 0, "{}", reader.summary());
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    /// Reads everything and checks the invariants: rows are in line order, one per data
    /// line at most, and any value is finite or NaN (never an infinity).
    fn check(bytes: &[u8]) {
        let Ok(mut reader) = LogReader::new(bytes, "fuzz.csv", ReaderOptions::default()) else {
            return;
        };
        let lines = bytes.iter().filter(|&&b| b == b'\n').count() as u64 + 1;
        let mut last = 0;
        while let Ok(Some(r)) = reader.next_record() {
            assert!(r.line > last && r.line <= lines);
            last = r.line;
            for v in [r.t, r.sample.phi, r.sample.gyro, r.sample.ax, r.sample.ay] {
                assert!(v.is_finite() || v.is_nan());
            }
        }
        let _ = reader.drain_warnings().count();
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            check(&bytes);
        }

        #[test]
        fn csv_like_text(body in "[-0-9.,#\"eEnaif \r\n\t]{0,300}") {
            check(format!("t,phi,gyro\n{body}").as_bytes());
        }
    }
}

#[test]
fn a_rounded_time_column_is_an_error_that_says_so_not_a_unit_hint() {
    // 1 kHz rows with t written `%.1f` (each stamp 100 times) or `%.0f` (1000 times).
    // Before: `%.0f` was refused as "time in milliseconds? --time-unit ms" and `%.1f` ran
    // with 99 % of the rows flagged bad_time_step and alg2 1.30 deg RMS instead of 0.72.
    let log = |digits: usize, rows: usize| {
        let mut text = String::from("t,phi\n");
        for k in 0..rows {
            text.push_str(&format!("{:.*},0.1\n", digits, k as f64 * 1e-3));
        }
        text
    };
    let e = fails(&log(1, 3000), ReaderOptions::default());
    assert_eq!(
        e.to_string(),
        "log.csv:1453: column 1 (`t`): 1436 of the first 1451 time steps are zero: each stamp \
         repeats for about 97 rows and then steps by 0.100 s, at about 967 rows per second: \
         the time was written rounded (to 0.100 s) or rows share a stamp; write `t` with more \
         digits, one time per row"
    );
    let e = fails(&log(0, 16_000), ReaderOptions::default());
    assert!(
        e.to_string()
            .contains("the time was written rounded (to 1.00 s)"),
        "{e}"
    );
    assert!(!e.to_string().contains("milliseconds"), "{e}");
    // --time-unit does not change that.
    let ms = ReaderOptions {
        time_unit: Some(TimeUnit::Ms),
        ..ReaderOptions::default()
    };
    assert!(fails(&log(1, 3000), ms).to_string().contains("rounded"));
    // A time that never increases.
    let e = fails("t,phi\n5,0\n5,0\n5,0\n5,0\n", ReaderOptions::default());
    assert_eq!(
        e.to_string(),
        "log.csv:5: column 1 (`t`): the time never increases (4 rows at one stamp): is `t` the \
         time column (--map t=NAME)?"
    );
    // Whole stamps, and a few repeated ones among steps, are read as before.
    let (records, _) = ok(&log(3, 3000));
    assert_eq!(records.len(), 3000);
    let mut text = log(3, 100);
    text.push_str("0.099,0.1\n0.099,0.1\n0.1,0.1\n");
    let (records, warnings) = ok(&text);
    assert_eq!(records.len(), 103);
    assert!(warnings
        .iter()
        .all(|w| w.kind == WarningKind::TimeNotIncreasing));
}

#[test]
fn a_header_line_in_the_middle_is_named_as_one() {
    // Two logs joined, or a logger restarted into the same stream. Before: `column 1
    // (`t`): not a number: `t``, which points at a cell, not at what happened.
    let e = fails(
        "# log\nt,phi\n0,1\n0.001,1\n# restart\nt,phi\n0,1\n",
        ReaderOptions::default(),
    );
    assert_eq!(
        e.to_string(),
        "log.csv:6: the header again (as on line 2): two logs joined, or a logger that \
         restarted into the same file or stream? remove this line, or split the log here"
    );
    let e = fails("t,phi\n0,1\nphi,t\n", ReaderOptions::default());
    assert!(
        e.to_string()
            .starts_with("log.csv:3: a new header (phi, t; line 1 has t, phi): two logs joined"),
        "{e}"
    );
    // A word in a data cell is still a cell that is not a number.
    let e = fails("t,phi\n0,1\n0.001,t\n", ReaderOptions::default());
    assert_eq!(
        e.to_string(),
        "log.csv:3: column 2 (`phi`): not a number: `t`"
    );
}

#[test]
fn a_header_that_names_the_other_unit_is_warned_about_on_line_1() {
    use pendtilt::io::{ColumnMap, DegreeColumns};
    let read = |header: &str, map: &str, deg: &str| -> Vec<String> {
        let text = format!("{header}\n0,0.01,0.02,0,9.8\n0.001,0.01,0.02,0,9.8\n");
        let options = ReaderOptions {
            map: if map.is_empty() {
                ColumnMap::new()
            } else {
                map.parse().unwrap()
            },
            degrees: if deg.is_empty() {
                DegreeColumns::none()
            } else {
                deg.parse().unwrap()
            },
            ..ReaderOptions::default()
        };
        let (records, warnings, error) = read_all(&text, options);
        assert!(error.is_none() && records.len() == 2, "{error:?}");
        warnings
            .iter()
            .filter(|w| w.kind == WarningKind::UnitMismatch)
            .map(|w| w.to_string())
            .collect()
    };
    // Degrees in the name, read as radians: file, line 1, the column, the fix.
    let w = read(
        "t,phi (deg),gyro[deg/s],ax,ay",
        "phi=phi (deg),gyro=gyro[deg/s]",
        "",
    );
    assert_eq!(
        w,
        [
            "log.csv:1: column `phi (deg)` (phi): its name says degrees, and it is read in \
             radians (no --deg): read it with --deg phi",
            "log.csv:1: column `gyro[deg/s]` (gyro): its name says deg/s, and it is read in \
             rad/s (no --deg): read it with --deg gyro"
        ]
    );
    let w = read("t,phi,gyro_deg_s,ax,ay", "gyro=gyro_deg_s", "");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].ends_with("read it with --deg gyro"), "{w:?}");
    for h in ["gyro_dps", "gyro (°/s)", "Gyro_Degrees"] {
        assert_eq!(
            read(&format!("t,phi,{h},ax,ay"), &format!("gyro={h}"), "").len(),
            1,
            "{h}"
        );
    }
    // Radians in the name, read with --deg.
    let w = read(
        "t,phi_rad,gyro[rad/s],ax,ay",
        "phi=phi_rad,gyro=gyro[rad/s]",
        "phi,gyro",
    );
    assert_eq!(
        w[1],
        "log.csv:1: column `gyro[rad/s]` (gyro): its name says rad/s, and it is read in deg/s \
         (--deg): leave gyro out of --deg"
    );
    // Right as read, or saying nothing about units: not a word.
    for (header, map, deg) in [
        (
            "t,phi (deg),gyro[deg/s],ax,ay",
            "phi=phi (deg),gyro=gyro[deg/s]",
            "phi,gyro",
        ),
        (
            "t,phi_rad,gyro[rad/s],ax,ay",
            "phi=phi_rad,gyro=gyro[rad/s]",
            "",
        ),
        ("t,phi,gyro,ax,ay", "", ""),
        ("t,phi,gyro,ax,ay", "", "phi,gyro"),
        (
            "t,enc_angle,gradient,ax,ay",
            "phi=enc_angle,gyro=gradient",
            "",
        ),
        ("t,phi,radius_gyro,ax,ay", "gyro=radius_gyro", "gyro"),
        ("t,phi,gyro,ax_deg,ay", "ax=ax_deg", ""),
    ] {
        assert!(read(header, map, deg).is_empty(), "{header} {map} {deg}");
    }
}

#[test]
fn a_missing_column_whose_name_carries_a_unit_is_suggested_with_the_unit_option() {
    let text = "t,phi_deg,gyro[rad/s],ax,ay\n0,1,0.02,0,9.8\n";
    let r = open(text, ReaderOptions::default()).unwrap();
    let c = r.columns().to_string();
    assert!(
        c.contains("phi (the header has `phi_deg`: --map phi=phi_deg --deg phi?)")
            && c.contains("gyro (the header has `gyro[rad/s]`: --map 'gyro=gyro[rad/s]'?)"),
        "{c}"
    );
}

/// Two logs joined without a second header (or a logger whose clock restarted): the time
/// goes back by more than the restart gap and runs on from there. The estimators, which
/// refuse a time before the last one they took, would hold every later row (earlier: a
/// 12 s ride made of two 6 s halves ran with exit 0, the second half's 6000 rows held and
/// flagged, alg2 4.68 deg RMS against 0.70, and one warning about "the sample"). Now an
/// error on the row that runs on, naming the line to split at with the commands; a step
/// back shorter than the restart gap and a single stray stamp are kept and flagged as
/// before, the warning saying how long the estimators hold.
#[test]
fn time_that_goes_back_and_runs_on_is_two_logs_an_error_naming_the_split() {
    let mut text = regular(1000, 0.001);
    text.push_str(&regular(30, 0.001)["t,phi\n".len()..]);
    let (records, _, error) = read_all(&text, ReaderOptions::default());
    let e = error.expect("two logs joined must not read").to_string();
    assert_eq!(records.len(), 1001, "every row before the error was given");
    assert!(records[1000].issues.bad_time);
    assert!(
        e.starts_with("log.csv:1003: column 1 (`t`): the time went back on line 1002 (0.999 then 0 s) and runs on from there (0.001 s here): two logs joined"),
        "{e}"
    );
    assert!(
        e.contains("split the log at line 1002: `head -n 1001 log.csv > first.csv; (sed -n 1p log.csv; tail -n +1002 log.csv) > second.csv`"),
        "{e}"
    );
    // One stray stamp far back, then the log goes on: kept, flagged, no error.
    let mut stray = regular(1000, 0.001);
    stray.push_str("0.2,0\n1.0,0\n1.001,0\n");
    let (records, warnings) = ok(&stray);
    assert_eq!(records.len(), 1003);
    let bad: Vec<bool> = records[999..].iter().map(|r| r.issues.bad_time).collect();
    assert_eq!(bad, vec![false, true, false, false]);
    let back = warnings
        .iter()
        .find(|w| w.kind == WarningKind::TimeNotIncreasing)
        .unwrap();
    assert!(
        back.message.contains("until the time passes 0.999 s again"),
        "{back}"
    );
    // A step back of 0.2 s (a clock set back, a chunk sent twice) that runs on: kept.
    let mut short = regular(1000, 0.001);
    for k in 0..400 {
        short.push_str(&format!("{},0\n", 0.8 + k as f64 * 0.001));
    }
    let (records, _) = ok(&short);
    assert_eq!(records.len(), 1400);
    assert_eq!(records.iter().filter(|r| r.issues.bad_time).count(), 1);
}

/// A units line under the header and a logger's marker of a missing reading (`NA`, `-`,
/// `null`, ...) are still errors (nothing is guessed), but say what the text likely is
/// and what to do, in the planar and the 3-D reader (earlier: `not a number: `s`` and
/// `not a number: `NA`` alone). A units line made a comment, as said, reads.
#[test]
fn a_units_line_or_a_missing_marker_says_what_to_do() {
    let units = "t,phi,gyro\ns,rad,rad/s\n0,0.1,0.2\n0.001,0.1,0.2\n";
    let e = fails(units, ReaderOptions::default()).to_string();
    assert_eq!(
        e,
        "log.csv:2: column 1 (`t`): not a number: `s`; the first row under the header is \
         text: a units line? make it a comment with `#` (`sed -i '2s/^/#/' log.csv`) or \
         delete it"
    );
    let (records, _) = ok(&units.replace("\ns,rad", "\n#s,rad"));
    assert_eq!(records.len(), 2);
    for marker in ["NA", "N/A", "null", "None", "-", "?"] {
        let text = format!("t,phi,gyro\n0,0.1,0.2\n0.001,{marker},0.2\n");
        let e = fails(&text, ReaderOptions::default()).to_string();
        assert_eq!(
            e,
            format!(
                "log.csv:3: column 2 (`phi`): not a number: `{marker}`; if `{marker}` marks a \
                 missing reading, leave the cell empty (or write nan): an empty cell reads as \
                 missing, and the estimators hold and flag the sample"
            )
        );
    }
    // A word in a later row is no units line; a plain typo gets no hint.
    let e = fails("t,phi\n0,0.1\nabc,def\n", ReaderOptions::default()).to_string();
    assert_eq!(e, "log.csv:3: column 1 (`t`): not a number: `abc`");
    // The 3-D reader says the same.
    let head = "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az";
    let three = |body: &str| {
        pendtilt::io::Log3dReader::new(format!("{head}\n{body}").as_bytes(), "log.csv")
            .unwrap()
            .collect::<Result<Vec<_>, _>>()
            .unwrap_err()
            .to_string()
    };
    let e = three("s,rad,rad,rad/s,rad/s,rad/s,m/s^2,m/s^2,m/s^2\n0,0,0,0,0,0,0,0,9.8\n");
    assert!(
        e.ends_with(
            "a units line? make it a comment with `#` (`sed -i '2s/^/#/' log.csv`) or delete it"
        ),
        "{e}"
    );
    let e = three("0,0,0,0,0,0,0,0,9.8\n0.001,0,0,NA,0,0,0,0,9.8\n");
    assert!(
        e.starts_with(
            "log.csv:3: column 4 (`gyro_x`): not a number: `NA`; if `NA` marks a missing reading"
        ),
        "{e}"
    );
}

/// A header in capitals: the planar hint gives the whole `--map` at once, and following
/// it reads the log; a 3-D header in capitals is named as one (earlier: `did you mean
/// `T`? (--map t=T)`, one column per round; on a 3-D log in capitals that hint led to
/// `--map t=T,ax=AX,ay=AY`, which ran the planar `accel` on the 3-D axes, exit 0).
#[test]
fn a_header_in_capitals_gets_one_whole_map_and_a_3d_one_is_named() {
    let upper = "T,PHI,GYRO,AX,AY\n0,0.1,0.2,0.3,9.8\n0.001,0.1,0.2,0.3,9.8\n";
    let e = fails(upper, ReaderOptions::default()).to_string();
    assert!(
        e.ends_with("did you mean `T`? (--map t=T,phi=PHI,gyro=GYRO,ax=AX,ay=AY)"),
        "{e}"
    );
    let map = "t=T,phi=PHI,gyro=GYRO,ax=AX,ay=AY"
        .parse::<pendtilt::io::ColumnMap>()
        .unwrap();
    let (records, _, error) = read_all(
        upper,
        ReaderOptions {
            map,
            ..ReaderOptions::default()
        },
    );
    assert!(error.is_none(), "{error:?}");
    assert_eq!((records.len(), records[1].sample.ay), (2, 9.8));

    let upper3d = "T,PHI_X,PHI_Y,GYRO_X,GYRO_Y,GYRO_Z,AX,AY,AZ\n0,0,0,0,0,0,0,0,9.8\n";
    let want = "log.csv:1: a 3-D log (MODEL.md 7.6) with its column names in capitals: its \
                columns are read by their names in lower case (t, phi_x, phi_y, gyro_x, ...); \
                write the header in lower case: `sed -i '1s/.*/\\L&/' log.csv`";
    let e = fails(upper3d, ReaderOptions::default()).to_string();
    assert!(e.starts_with(want), "{e}");
    let map = "t=T,ax=AX,ay=AY"
        .parse::<pendtilt::io::ColumnMap>()
        .unwrap();
    let options = ReaderOptions {
        map,
        ..ReaderOptions::default()
    };
    let e = fails(upper3d, options).to_string();
    assert!(e.starts_with(want), "{e}");
}

/// NUL bytes (an SD-card logger's preallocated space it never wrote, a write cut by a
/// power loss) are removed and said once, by line and count, never printed: a line of them
/// alone is blank, a line they end is cut (earlier: 4096 NULs after the last line gave
/// one more row, all missing with t NaN, and a warning that printed the 4096 NULs).
#[test]
fn nul_padding_after_the_last_line_is_no_row_and_is_said_without_the_bytes() {
    let mut text = regular(20, 0.001).into_bytes();
    text.extend(std::iter::repeat_n(0u8, 4096));
    let text = String::from_utf8(text).unwrap();
    let (records, warnings) = ok(&text);
    assert_eq!(records.len(), 20, "no row made of NULs");
    assert!(records.iter().all(|r| !r.issues.bad_time));
    // Counted as what they are, not as a cut row (the summary said `truncated_row 1`).
    assert!(warnings.iter().all(|w| w.kind == WarningKind::NulBytes));
    assert!(records.iter().all(|r| !r.issues.truncated));
    let said: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        said,
        vec![
            "log.csv:22: 4096 NUL byte(s) from line 22 on (space a logger allocated and never \
              wrote, or a write a power loss cut): removed, a line of them alone read as \
              blank, a line they end as cut (its last cell may be cut short)"
        ]
    );
    // A line the NULs cut: kept, its last cell read as missing, as a cut last line.
    let cut = format!("t,phi,gyro\n0,0.1,0.2\n0.001,0.1{}", "\0".repeat(100));
    let (records, warnings) = ok(&cut);
    assert_eq!(records.len(), 2);
    assert!(records[1].sample.phi.is_nan() && records[1].issues.truncated);
    assert!(warnings.iter().all(|w| !w.to_string().contains('\0')));
    // The 3-D reader likewise, through `estimate`.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("nul3d.csv");
    let mut three = String::from("t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az\n");
    for k in 0..50 {
        three.push_str(&format!("{},0,0,0,0,0,0,0,9.80665\n", k as f64 * 1e-3));
    }
    three.push_str(&"\0".repeat(512));
    std::fs::write(&log, three).unwrap();
    let out = dir.path().join("est.csv");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_pendtilt"))
        .args([
            "estimate",
            log.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("nul3d.csv:52: 512 NUL byte(s) from line 52 on"),
        "{e}"
    );
    assert!(!e.contains('\0'));
    assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), 51);
}

/// A header with a trailing comma (every row too) reads as without it, and the report of
/// the columns names the empty field instead of an empty name (earlier: `ignored: `).
#[test]
fn a_trailing_comma_on_every_line_names_its_unnamed_field() {
    let text = "t,phi,\n0,0.1,\n0.001,0.2,\n";
    let reader = open(text, ReaderOptions::default()).unwrap();
    assert_eq!(
        reader.columns().to_string(),
        "columns: t, phi; missing: gyro, ax, ay, theta; ignored: (unnamed field 3)"
    );
    let (records, warnings) = ok(text);
    assert_eq!(records.len(), 2);
    assert!(warnings.is_empty(), "{warnings:?}");
}
