//! Text checks and text for messages: UTF-8 naming the line and column of the first bad
//! byte, and user text shortened to fit on one line of an error message.

use crate::error::{IoError, input_err};
use std::path::Path;

/// Converts `bytes` (read from `name`) to text, naming the line and column (1-based, columns in
/// bytes) of the first byte that is not UTF-8.
pub fn utf8_text(bytes: Vec<u8>, name: &Path) -> Result<String, IoError> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let (line, col) = line_col(bytes, at);
        input_err(
            name,
            format!(
                "line {line}, column {col}: not UTF-8 text (byte 0x{:02x})",
                bytes[at]
            ),
        )
    })
}

/// Line and column (1-based; columns count bytes) of byte offset `at` in `bytes`.
pub fn line_col(bytes: &[u8], at: usize) -> (usize, usize) {
    let before = &bytes[..at.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let col = at
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1)
        + 1;
    (line, col)
}

/// Shortens `s` for an error message: at most `max` characters, the rest replaced by
/// "... (N more bytes)". Control characters are escaped so a message stays on one line.
pub fn shorten(s: &str, max: usize) -> String {
    let mut out = String::new();
    for (taken, (i, ch)) in s.char_indices().enumerate() {
        if taken == max {
            out.push_str(&format!("... ({} more bytes)", s.len() - i));
            return out;
        }
        out.extend(ch.escape_debug());
    }
    out
}

/// Shortens a path (or any text whose end matters, as a file's extension does) for an error
/// message: at most about `max` characters, its first and last halves kept and the middle
/// replaced by "...(N bytes)..." (a text the marker would not make shorter is kept whole).
/// Control characters are escaped as by [`shorten`].
pub fn shorten_middle(s: &str, max: usize) -> String {
    let n = s.chars().count();
    if n <= max.saturating_add(16) {
        return s.chars().flat_map(char::escape_debug).collect();
    }
    let (head, tail) = (max / 2, max - max / 2);
    let cut = s.char_indices().nth(head).map_or(s.len(), |(i, _)| i);
    let resume = s.char_indices().nth(n - tail).map_or(s.len(), |(i, _)| i);
    let mut out: String = s[..cut].chars().flat_map(char::escape_debug).collect();
    out.push_str(&format!("...({} bytes)...", resume - cut));
    out.extend(s[resume..].chars().flat_map(char::escape_debug));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shorten_middle_keeps_both_ends() {
        assert_eq!(shorten_middle("a/b.txt", 7), "a/b.txt");
        // The marker would not make these shorter.
        assert_eq!(shorten_middle("abcdefghij.txt", 8), "abcdefghij.txt");
        assert_eq!(shorten_middle("a\nbcdefg", 0), "a\\nbcdefg");
        let long = format!("/tmp/{}/x.txt", "d".repeat(100));
        assert_eq!(
            shorten_middle(&long, 20),
            "/tmp/ddddd...(91 bytes)...dddd/x.txt"
        );
        let accents = format!("{}x", "\u{e9}".repeat(30));
        assert_eq!(shorten_middle(&accents, 2), "\u{e9}...(58 bytes)...x");
        let controls = format!("\n{}\t", "y".repeat(40));
        assert_eq!(shorten_middle(&controls, 4), "\\ny...(38 bytes)...y\\t");
    }

    #[test]
    fn non_utf8_names_line_and_column() {
        let e = utf8_text(b"a,b\n\n1,\xff2\n".to_vec(), Path::new("in.csv")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "in.csv: line 3, column 3: not UTF-8 text (byte 0xff)"
        );
        assert_eq!(line_col(b"ab", 0), (1, 1));
        assert_eq!(line_col(b"a\nb", 2), (2, 1));
    }

    #[test]
    fn shorten_caps_and_escapes() {
        assert_eq!(shorten("abc", 5), "abc");
        assert_eq!(shorten("abcdef", 3), "abc... (3 more bytes)");
        assert_eq!(shorten("a\nb", 5), "a\\nb");
        let long = "x".repeat(10_000_000);
        assert!(shorten(&long, 40).len() < 80);
    }
}
