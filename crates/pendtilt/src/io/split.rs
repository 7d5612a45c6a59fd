//! Splitting one CSV line into fields.
//!
//! The log reader reads line by line (so that every message can give the true line
//! number, comment and blank lines included) and splits each line here. Fields may be
//! quoted with `"` (RFC 4180, `""` inside quotes is a literal quote); a quoted field may
//! not span lines. Whitespace around fields is trimmed.

/// Why a line could not be split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SplitError {
    /// A `"` opened a field and the line ended before it closed. Carries the 0-based field.
    UnterminatedQuote(usize),
}

/// Splits `line` (without its line end) at `delimiter` into `fields`, as byte ranges
/// of `line`. A quoted field's range is its content between the quotes (a doubled quote
/// stays doubled; see [`unquote`]).
pub(crate) fn split_fields(
    line: &[u8],
    delimiter: u8,
    fields: &mut Vec<(usize, usize)>,
) -> Result<(), SplitError> {
    fields.clear();
    // Fast path, one pass, eight bytes at a time: skip words that hold neither the
    // delimiter nor a quote; a quote sends the line to the general path.
    let mut start = 0;
    let mut i = 0;
    let mut words = line.chunks_exact(8);
    for chunk in &mut words {
        let word = <[u8; 8]>::try_from(chunk).map_or(u64::MAX, u64::from_le_bytes);
        if has_byte(word, delimiter) | has_byte(word, b'"') != 0 {
            for (k, &b) in chunk.iter().enumerate() {
                if b == delimiter {
                    fields.push(trim(line, start, i + k));
                    start = i + k + 1;
                } else if b == b'"' {
                    fields.clear();
                    return split_quoted(line, delimiter, fields);
                }
            }
        }
        i += 8;
    }
    for (k, &b) in words.remainder().iter().enumerate() {
        if b == delimiter {
            fields.push(trim(line, start, i + k));
            start = i + k + 1;
        } else if b == b'"' {
            fields.clear();
            return split_quoted(line, delimiter, fields);
        }
    }
    fields.push(trim(line, start, line.len()));
    Ok(())
}

/// Non-zero when some byte of `word` equals `b` (the classic SWAR zero-byte test).
#[inline]
fn has_byte(word: u64, b: u8) -> u64 {
    const LO: u64 = 0x0101_0101_0101_0101;
    const HI: u64 = 0x8080_8080_8080_8080;
    let x = word ^ (LO * u64::from(b));
    x.wrapping_sub(LO) & !x & HI
}

/// The general path of [`split_fields`], for lines with quotes.
fn split_quoted(
    line: &[u8],
    delimiter: u8,
    fields: &mut Vec<(usize, usize)>,
) -> Result<(), SplitError> {
    let mut i = 0;
    loop {
        // Skip leading blanks.
        while i < line.len() && is_blank(line[i]) {
            i += 1;
        }
        if i < line.len() && line[i] == b'"' {
            let start = i + 1;
            let mut j = start;
            let end = loop {
                if j >= line.len() {
                    return Err(SplitError::UnterminatedQuote(fields.len()));
                }
                if line[j] == b'"' {
                    if j + 1 < line.len() && line[j + 1] == b'"' {
                        j += 2;
                        continue;
                    }
                    break j;
                }
                j += 1;
            };
            fields.push((start, end));
            // Skip to the delimiter (anything after the closing quote is ignored).
            let mut k = end + 1;
            while k < line.len() && line[k] != delimiter {
                k += 1;
            }
            if k >= line.len() {
                return Ok(());
            }
            i = k + 1;
        } else {
            let start = i;
            let mut k = i;
            while k < line.len() && line[k] != delimiter {
                k += 1;
            }
            fields.push(trim(line, start, k));
            if k >= line.len() {
                return Ok(());
            }
            i = k + 1;
        }
    }
}

/// The text of a quoted field with doubled quotes undone.
pub(crate) fn unquote(field: &str) -> String {
    field.replace("\"\"", "\"")
}

fn is_blank(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

fn trim(line: &[u8], mut start: usize, mut end: usize) -> (usize, usize) {
    while start < end && is_blank(line[start]) {
        start += 1;
    }
    while end > start && is_blank(line[end - 1]) {
        end -= 1;
    }
    (start, end)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(s: &str) -> Vec<&str> {
        let mut f = Vec::new();
        split_fields(s.as_bytes(), b',', &mut f).unwrap();
        f.iter().map(|&(a, b)| &s[a..b]).collect()
    }

    #[test]
    fn plain_and_quoted() {
        assert_eq!(split("t, phi ,gyro"), vec!["t", "phi", "gyro"]);
        assert_eq!(split("1,,3"), vec!["1", "", "3"]);
        assert_eq!(split("1,"), vec!["1", ""]);
        assert_eq!(split(""), vec![""]);
        assert_eq!(split("\"a,b\", c"), vec!["a,b", "c"]);
        assert_eq!(split("x,\"say \"\"hi\"\"\""), vec!["x", "say \"\"hi\"\""]);
        assert_eq!(unquote("say \"\"hi\"\""), "say \"hi\"");
        assert_eq!(split("\"a\",\"\""), vec!["a", ""]);
    }

    #[test]
    fn word_at_a_time_path_matches_a_plain_split() {
        // Lines of every length around the 8-byte words, delimiters at every offset.
        for len in 0..40 {
            for every in 1..6 {
                let line: String = (0..len)
                    .map(|i| if i % every == every - 1 { ',' } else { 'x' })
                    .collect();
                let expected: Vec<&str> = line.split(',').collect();
                assert_eq!(split(&line), expected, "{line:?}");
                // A quote anywhere takes the general path with the same result here.
                let quoted = format!("{line},\"q\"");
                let mut e2 = expected.clone();
                e2.push("q");
                assert_eq!(split(&quoted), e2, "{quoted:?}");
            }
        }
        // High bytes (UTF-8) never match the delimiter test.
        assert_eq!(
            split("\u{e9}\u{e9}\u{e9}\u{e9},\u{ff}x"),
            vec!["\u{e9}\u{e9}\u{e9}\u{e9}", "\u{ff}x"]
        );
    }

    #[test]
    fn unterminated_quote() {
        let mut f = Vec::new();
        assert_eq!(
            split_fields(b"1,\"abc", b',', &mut f),
            Err(SplitError::UnterminatedQuote(1))
        );
    }

    #[test]
    fn other_delimiter() {
        let mut f = Vec::new();
        split_fields(b"t;phi", b';', &mut f).unwrap();
        assert_eq!(f, vec![(0, 1), (2, 5)]);
    }
}
