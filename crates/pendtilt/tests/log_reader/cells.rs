//! The cells: numbers read, text named with its line and column, NaN, infinite and empty
//! cells kept as missing samples, angles in degrees warned about or converted.
use crate::common::log_reader::{ok, open, read_all};
use pendtilt::io::{Column, LogErrorKind, LogWarning, ReaderOptions, WarningKind};
use std::f64::consts::PI;

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
