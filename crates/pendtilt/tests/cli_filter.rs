//! End-to-end tests of `pendtilt filter`: the binary on small CSV fixtures in a tempdir.

use pendtilt_core::filters::fir::{design_lowpass, magnitude_response, FirSlice, Window};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Output;

mod common;
use common::{pendtilt, run_on, s, stderr, write};

/// Asserts a clean failure: exit code 1, an `error:` message, no panic.
fn assert_error(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "expected failure, stderr: {err}");
    assert!(err.starts_with("error: "), "stderr: {err}");
    assert!(!err.contains("panicked"), "stderr: {err}");
    err
}

/// `t,a,label,b` at `rate` Hz: a = slow sine + 80 Hz vibration, b = ramp with noise-like
/// wiggle, label = text (passed through).
fn fixture(rows: usize, rate: f64) -> (String, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut text = String::from("t,a,label,b\n");
    let (mut t, mut a, mut b) = (vec![], vec![], vec![]);
    for k in 0..rows {
        let tk = k as f64 / rate;
        let ak = 0.3 * (2.0 * std::f64::consts::PI * 2.0 * tk).sin()
            + 0.05 * (2.0 * std::f64::consts::PI * 80.0 * tk).sin();
        let bk = 0.01 * k as f64 + 0.02 * ((k * 7919 % 101) as f64 / 101.0 - 0.5);
        writeln!(text, "{tk},{ak},row{k},{bk}").unwrap();
        t.push(tk);
        a.push(ak);
        b.push(bk);
    }
    (text, t, a, b)
}

/// Parsed output: header names and rows of raw cells.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// What the core library gives for `x` with `taps` (the reference for the command).
fn core_filter(taps: &[f64], x: &[f64]) -> Vec<f64> {
    let mut hist = vec![0.0; taps.len()];
    let mut fir = FirSlice::new(taps, &mut hist).unwrap();
    x.iter().map(|&v| fir.update(v)).collect()
}

/// The command's rate: (rows - 1) / (t_last - t_first).
fn rate_of(t: &[f64]) -> f64 {
    (t.len() - 1) as f64 / (t[t.len() - 1] - t[0])
}

fn design(n_taps: usize, cutoff: f64, rate: f64, window: Window) -> Vec<f64> {
    let mut taps = vec![0.0; n_taps];
    design_lowpass(cutoff, rate, window, &mut taps).unwrap();
    taps
}

fn column(rows: &[Vec<String>], i: usize) -> Vec<f64> {
    rows.iter().map(|r| r[i].parse::<f64>().unwrap()).collect()
}

fn assert_close(got: &[f64], want: &[f64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((g - w).abs() <= tol, "{what} row {k}: {g} vs {w}");
    }
}

#[test]
fn default_filters_numeric_columns_like_the_core_filter() {
    let dir = tempfile::tempdir().unwrap();
    let (text, t, a, b) = fixture(300, 1000.0);
    let input = write(dir.path(), "in.csv", &text);
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &[], s(&out));
    assert!(o.status.success(), "stderr: {}", stderr(&o));
    assert!(stderr(&o).contains("on: a, b"), "summary: {}", stderr(&o));

    let (header, rows) = read_csv(&out);
    assert_eq!(header, ["t", "a", "label", "b"]);
    assert_eq!(rows.len(), 300, "one output row per input row");
    let taps = design(51, 20.0, rate_of(&t), Window::Hamming);
    // The command prints the shortest round-trip text, so the values are the core's.
    assert_close(&column(&rows, 1), &core_filter(&taps, &a), 1e-15, "a");
    assert_close(&column(&rows, 3), &core_filter(&taps, &b), 1e-15, "b");
    // Time and text pass through byte for byte.
    let input_rows: Vec<&str> = text.lines().skip(1).collect();
    for (k, r) in rows.iter().enumerate() {
        let cells: Vec<&str> = input_rows[k].split(',').collect();
        assert_eq!(r[0], cells[0], "t row {k}");
        assert_eq!(r[2], cells[2], "label row {k}");
    }
    // And the filter did something: the 80 Hz vibration (gain ~1e-3 at 1 kHz) is gone.
    let filtered_a = column(&rows, 1);
    let err: f64 = (100..300)
        .map(|k| {
            let want = 0.3
                * magnitude_response(&taps, 2.0, 1000.0)
                * (2.0 * std::f64::consts::PI * 2.0 * (t[k] - 0.025)).sin();
            (filtered_a[k] - want).abs()
        })
        .fold(0.0, f64::max);
    assert!(err < 1e-3, "residual vibration {err}");
}

#[test]
fn columns_option_selects_what_is_filtered() {
    let dir = tempfile::tempdir().unwrap();
    let (text, t, _a, b) = fixture(120, 500.0);
    let input = write(dir.path(), "in.csv", &text);
    let out = dir.path().join("out.csv");
    let o = run_on(
        "filter",
        &input,
        &[
            "--columns",
            "b",
            "--order",
            "10",
            "--cutoff",
            "40",
            "--window",
            "hann",
        ],
        s(&out),
    );
    assert!(o.status.success(), "stderr: {}", stderr(&o));
    let (_, rows) = read_csv(&out);
    assert_eq!(rows.len(), 120);
    let taps = design(11, 40.0, rate_of(&t), Window::Hann);
    assert_close(&column(&rows, 3), &core_filter(&taps, &b), 1e-15, "b");
    // `a` was not asked for: copied unchanged.
    for (k, line) in text.lines().skip(1).enumerate() {
        assert_eq!(rows[k][1], line.split(',').nth(1).unwrap(), "a row {k}");
    }
}

#[test]
fn missing_column_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(50, 1000.0);
    let input = write(dir.path(), "in.csv", &text);
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &["--columns", "a,phi_deg"], s(&out));
    let err = assert_error(&o);
    assert!(err.contains("'phi_deg'"), "{err}");
    assert!(err.contains("in.csv"), "{err}");
    assert!(err.contains("t, a, label, b"), "lists the columns: {err}");
    assert!(!out.exists(), "no output after a failed check");
}

#[test]
fn missing_time_column_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "in.csv", "time,a\n0,1\n0.001,2\n");
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &[], s(&out));
    let err = assert_error(&o);
    assert!(err.contains("no time column 't'"), "{err}");
    // ...and --time-column maps it.
    let o = run_on("filter", &input, &["--time-column", "time"], s(&out));
    assert!(o.status.success(), "stderr: {}", stderr(&o));
    assert_eq!(read_csv(&out).1.len(), 2);
}

#[test]
fn non_numeric_cell_names_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(40, 1000.0);
    // Data row 6 is on line 7 (the header is line 1); corrupt its `b` (field 4).
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<String> = lines[6].split(',').map(str::to_string).collect();
    cells[3] = "oops".to_string();
    lines[6] = cells.join(",");
    let input = write(dir.path(), "bad.csv", &(lines.join("\n") + "\n"));
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &[], s(&out));
    let err = assert_error(&o);
    assert!(err.contains("bad.csv:7:"), "{err}");
    assert!(err.contains("column 'b' (field 4)"), "{err}");
    assert!(err.contains("'oops'"), "{err}");
    assert!(!out.exists());
}

#[test]
fn bad_cutoff_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(60, 1000.0);
    let input = write(dir.path(), "in.csv", &text);
    let out = dir.path().join("out.csv");
    let run = |cutoff: &str| run_on("filter", &input, &[&format!("--cutoff={cutoff}")], s(&out));
    let err = assert_error(&run("500"));
    assert!(err.contains("Nyquist"), "{err}");
    assert!(err.contains("500 Hz"), "{err}");
    let err = assert_error(&run("0"));
    assert!(err.contains("--cutoff 0 Hz must be positive"), "{err}");
    let err = assert_error(&run("-3"));
    assert!(err.contains("must be positive"), "{err}");
    let err = assert_error(&run("NaN"));
    assert!(err.contains("must be positive"), "{err}");
    assert!(!out.exists());
    // Just below Nyquist is a valid design.
    assert!(run("499").status.success());
}

#[test]
fn time_column_must_increase_and_be_uniform() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.csv");
    let go = |name: &str, text: &str, extra: &[&str]| {
        let input = write(dir.path(), name, text);
        let mut args = vec!["filter", input.to_str().unwrap()];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap()]);
        pendtilt(&args)
    };
    // A repeated time on line 4.
    let err = assert_error(&go("dup.csv", "t,a\n0,1\n0.01,1\n0.01,1\n0.03,1\n", &[]));
    assert!(err.contains("dup.csv:4:"), "{err}");
    assert!(err.contains("strictly increasing"), "{err}");
    // A dropped sample: the step into line 6 is twice the others.
    let gap = "t,a\n0,1\n0.01,1\n0.02,1\n0.03,1\n0.05,1\n0.06,1\n0.07,1\n";
    let err = assert_error(&go("gap.csv", gap, &[]));
    assert!(err.contains("gap.csv:6:"), "{err}");
    assert!(err.contains("--max-jitter"), "{err}");
    // Accepted when the user says so.
    assert!(go("gap.csv", gap, &["--max-jitter", "1"]).status.success());
    // Text in the time column.
    let err = assert_error(&go("txt.csv", "t,a\n0,1\nx,1\n", &[]));
    assert!(
        err.contains("txt.csv:3: column 't' (field 1): 'x'"),
        "{err}"
    );
    // Too short to have a rate.
    let err = assert_error(&go("one.csv", "t,a\n0,1\n", &[]));
    assert!(err.contains("at least 2"), "{err}");
}

#[test]
fn ragged_row_is_an_error_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "rag.csv", "t,a,b\n0,1,2\n0.1,1\n0.2,1,2\n");
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &[], s(&out));
    let err = assert_error(&o);
    assert!(err.contains("rag.csv:3:"), "{err}");
    assert!(err.contains("2 fields but the header has 3"), "{err}");
}

#[test]
fn one_output_row_per_input_row_for_any_length() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.csv");
    for rows in [2usize, 3, 25, 26, 51, 52, 200] {
        let (text, ..) = fixture(rows, 1000.0);
        let input = write(dir.path(), "in.csv", &text);
        for extra in [&[][..], &["--compensate-delay"][..]] {
            let mut args = vec!["filter", input.to_str().unwrap(), "-o"];
            args.push(out.to_str().unwrap());
            args.extend_from_slice(extra);
            let o = pendtilt(&args);
            assert!(o.status.success(), "{rows} rows {extra:?}: {}", stderr(&o));
            let (_, got) = read_csv(&out);
            assert_eq!(got.len(), rows, "{rows} rows {extra:?}");
            // Rows stay in order: the time column is the input's.
            for (k, r) in got.iter().enumerate() {
                assert_eq!(r[2], format!("row{k}"));
            }
        }
    }
}

#[test]
fn compensate_delay_shifts_by_half_the_order() {
    let dir = tempfile::tempdir().unwrap();
    let (text, t, a, _) = fixture(400, 1000.0);
    let input = write(dir.path(), "in.csv", &text);
    let out = dir.path().join("out.csv");
    let o = run_on(
        "filter",
        &input,
        &["--compensate-delay", "--columns", "a"],
        s(&out),
    );
    assert!(o.status.success(), "stderr: {}", stderr(&o));
    let (_, rows) = read_csv(&out);
    let got = column(&rows, 1);
    // Row k holds the core filter's output 25 samples later; the end holds the last input.
    let mut padded = a.clone();
    padded.extend(std::iter::repeat_n(a[a.len() - 1], 25));
    let taps = design(51, 20.0, rate_of(&t), Window::Hamming);
    let want = core_filter(&taps, &padded);
    assert_close(&got, &want[25..], 1e-15, "compensated a");
    // So the slow sine is now in phase with the input (its 80 Hz part is removed).
    let g = magnitude_response(&taps, 2.0, 1000.0);
    for k in 60..340 {
        let slow = 0.3 * (2.0 * std::f64::consts::PI * 2.0 * t[k]).sin();
        assert!((got[k] - g * slow).abs() < 1e-3, "row {k}");
    }
    // An odd order cannot be compensated by whole rows.
    let o = run_on(
        "filter",
        &input,
        &["--compensate-delay", "--order", "51"],
        s(&out),
    );
    let err = assert_error(&o);
    assert!(err.contains("even --order"), "{err}");
}

#[test]
fn empty_cell_is_missing_and_the_filter_recovers() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("t,a\n");
    for k in 0..40 {
        let v = if k == 10 { String::new() } else { "2".into() };
        writeln!(text, "{},{v}", k as f64 * 0.01).unwrap();
    }
    let input = write(dir.path(), "in.csv", &text);
    let out = dir.path().join("out.csv");
    let o = run_on(
        "filter",
        &input,
        &["--order", "4", "--cutoff", "10"],
        s(&out),
    );
    assert!(o.status.success(), "stderr: {}", stderr(&o));
    let got = column(&read_csv(&out).1, 1);
    for (k, y) in got.iter().enumerate() {
        if (10..15).contains(&k) {
            assert!(y.is_nan(), "row {k} should be NaN: {y}");
        } else {
            assert!((y - 2.0).abs() < 1e-12, "row {k}: {y}");
        }
    }
}

#[test]
fn unknown_window_and_huge_order_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(30, 1000.0);
    let input = write(dir.path(), "in.csv", &text);
    let o = run_on("filter", &input, &["--window", "kaiser"], "-");
    assert_eq!(o.status.code(), Some(2), "clap usage error");
    assert!(stderr(&o).contains("unknown window"), "{}", stderr(&o));
    let o = run_on("filter", &input, &["--order", "18446744073709551615"], "-");
    let err = assert_error(&o);
    assert!(err.contains("larger than the maximum"), "{err}");
}

#[test]
fn refuses_to_overwrite_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(30, 1000.0);
    let input = write(dir.path(), "in.csv", &text);
    let o = run_on("filter", &input, &[], s(&input));
    let err = assert_error(&o);
    assert!(err.contains("is the same file as INPUT"), "{err}");
    assert_eq!(std::fs::read_to_string(&input).unwrap(), text);
}

#[test]
fn says_how_many_rows_a_missing_sample_spread_to() {
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(1000, 1000.0);
    // Column a: one NaN at data row 100 and one empty cell at row 500 (both far from the
    // end), column b clean. With order 20 each missing sample makes the 21 outputs from
    // its row on NaN: 2 x 21 = 42 rows.
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for (row, cell) in [(100, "NaN"), (500, "")] {
        let mut f: Vec<String> = lines[row + 1].split(',').map(str::to_string).collect();
        f[1] = cell.to_string();
        lines[row + 1] = f.join(",");
    }
    let input = write(dir.path(), "in.csv", &(lines.join("\n") + "\n"));
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &["--order", "20"], s(&out));
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("column 'a': 2 missing or NaN cell(s) made 42 output row(s) NaN"),
        "{err}"
    );
    assert!(!err.contains("column 'b'"), "{err}");
    let (_, rows) = read_csv(&out);
    let nan_rows = rows.iter().filter(|r| r[1] == "NaN").count();
    assert_eq!(nan_rows, 42);
}

#[test]
fn a_log_shorter_than_the_filter_is_said_to_be_all_start_up() {
    // 3 rows through the 51-tap filter gave the first value back three times, silently.
    let dir = tempfile::tempdir().unwrap();
    let (text, ..) = fixture(3, 1000.0);
    let input = write(dir.path(), "short.csv", &text);
    let out = dir.path().join("out.csv");
    let o = run_on("filter", &input, &[], s(&out));
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(
            "short.csv: 3 rows, fewer than the filter's 51 taps: every output row is within \
             its start-up"
        ),
        "{err}"
    );
    assert_eq!(read_csv(&out).1.len(), 3, "one row per input row");
    // A log as long as the filter: no warning.
    let (text, ..) = fixture(51, 1000.0);
    let input = write(dir.path(), "long.csv", &text);
    let o = run_on("filter", &input, &[], s(&out));
    assert!(!stderr(&o).contains("start-up"), "{}", stderr(&o));
}
