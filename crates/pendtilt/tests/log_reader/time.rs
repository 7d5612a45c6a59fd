//! The time column: repeated, backwards, missing, gapped, jittered, rounded, or running
//! back and on (two logs joined).
use crate::common::log_reader::{fails, ok, open, read_all, regular};
use pendtilt::io::{LogWarning, ReaderOptions, TimeUnit, WarningKind};

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
