//! Shared by the log_reader tests: a reader over text, reading it whole, and a good log.
use pendtilt::io::{LogError, LogReader, LogRecord, LogWarning, ReaderOptions};

pub fn open(text: &str, options: ReaderOptions) -> Result<LogReader<&[u8]>, LogError> {
    LogReader::new(text.as_bytes(), "log.csv", options)
}

/// Reads everything: the records, the warnings, and the error that stopped the read.
pub fn read_all(
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

pub fn ok(text: &str) -> (Vec<LogRecord>, Vec<LogWarning>) {
    let (records, warnings, error) = read_all(text, ReaderOptions::default());
    if let Some(e) = error {
        panic!("unexpected error: {e}");
    }
    (records, warnings)
}

pub fn fails(text: &str, options: ReaderOptions) -> LogError {
    let (_, _, error) = read_all(text, options);
    error.expect("expected an error")
}

pub fn regular(n: usize, dt: f64) -> String {
    let mut s = String::from("t,phi\n");
    for k in 0..n {
        s.push_str(&format!("{},0\n", k as f64 * dt));
    }
    s
}
