//! The file as bytes and lines: empty, header only, line endings and byte order marks,
//! a cut last line, invalid UTF-8, UTF-16, NUL padding, a missing file; the iterator and
//! the stream; never a panic.
use crate::common::log_reader::{fails, ok, open, regular};
use pendtilt::io::{LogError, LogErrorKind, LogReader, LogRecord, ReaderOptions, WarningKind};

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
