//! Splitting trajectory text into numbered data lines of finite numbers.

use super::TrajectoryError;

/// One data line: its 1-based number in the file and its whitespace-separated tokens.
pub(crate) struct RawLine<'a> {
    pub number: usize,
    pub tokens: Vec<&'a str>,
}

/// Data lines of `text`: blank lines and lines starting with `#` are skipped.
pub(crate) fn raw_lines(text: &str) -> impl Iterator<Item = RawLine<'_>> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            return None;
        }
        Some(RawLine {
            number: i + 1,
            tokens: line.split_whitespace().collect(),
        })
    })
}

/// Fails with `Empty` when `text` holds no data line.
pub(crate) fn first_line<'a>(text: &'a str, file: &str) -> Result<RawLine<'a>, TrajectoryError> {
    raw_lines(text)
        .next()
        .ok_or_else(|| TrajectoryError::Empty {
            file: file.to_string(),
        })
}

/// Parses a line that must have exactly `expected` finite numbers.
pub(crate) fn numbers(
    line: &RawLine<'_>,
    expected: usize,
    file: &str,
) -> Result<Vec<f64>, TrajectoryError> {
    if line.tokens.len() != expected {
        return Err(TrajectoryError::ColumnCount {
            file: file.to_string(),
            line: line.number,
            expected: expected.to_string(),
            found: line.tokens.len(),
        });
    }
    line.tokens
        .iter()
        .enumerate()
        .map(|(i, token)| number(token, file, line.number, i + 1))
        .collect()
}

fn number(token: &str, file: &str, line: usize, column: usize) -> Result<f64, TrajectoryError> {
    let value: f64 = token.parse().map_err(|_| TrajectoryError::NotANumber {
        file: file.to_string(),
        line,
        column,
        token: token.to_string(),
    })?;
    if !value.is_finite() {
        return Err(TrajectoryError::NonFinite {
            file: file.to_string(),
            line,
            column,
            token: token.to_string(),
        });
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skips_comments_and_blanks_and_keeps_line_numbers() {
        let text = "# header\n\n1 2 3\n  # indented comment\n4 5 6\n";
        let lines: Vec<_> = raw_lines(text).collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0].number, 3);
        assert_eq!(lines[1].number, 5);
    }

    #[test]
    fn rejects_nan_and_garbage_with_position() {
        let nan = raw_lines("1 nan 3").next().unwrap();
        let msg = numbers(&nan, 3, "a.txt").unwrap_err().to_string();
        assert_eq!(msg, "a.txt line 1, column 2: value 'nan' is not finite");
        let bad = raw_lines("\n1 x 3").next().unwrap();
        let msg = numbers(&bad, 3, "a.txt").unwrap_err().to_string();
        assert_eq!(msg, "a.txt line 2, column 2: 'x' is not a number");
    }

    #[test]
    fn wrong_count_names_line() {
        let line = raw_lines("1 2").next().unwrap();
        let msg = numbers(&line, 8, "gt.tum").unwrap_err().to_string();
        assert_eq!(msg, "gt.tum line 1: expected 8 numbers, found 2");
    }
}
