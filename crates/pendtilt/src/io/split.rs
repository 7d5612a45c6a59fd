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
    if !line.contains(&b'"') {
        let mut start = 0;
        for (i, &b) in line.iter().enumerate() {
            if b == delimiter {
                fields.push(trim(line, start, i));
                start = i + 1;
            }
        }
        fields.push(trim(line, start, line.len()));
        return Ok(());
    }
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
