//! The CSV input of `eval`, `sample` and `measured eval`: read once and bounded, UTF-8
//! checked, its header checked, and every error naming the file, the line where the record
//! starts and the field.

use crate::CliError;
use fastbrdf_io::shorten;
use std::io::IsTerminal;
use std::path::Path;

/// The most characters of the input quoted in a message.
pub const QUOTE: usize = 40;

/// The CSV input of `command` (`--input FILE` or stdin), read once and at most `max_mib` MiB,
/// as UTF-8 text, with its name for messages.
pub fn read_input(
    input: Option<&Path>,
    max_mib: u64,
    command: &str,
) -> Result<(String, String), CliError> {
    let what = format!("{command} input (see --max-input-mib)");
    let limit = max_mib
        .checked_mul(1 << 20)
        .ok_or_else(|| CliError::input(format!("--max-input-mib {max_mib}: too large")))?;
    let (bytes, source) = match input {
        Some(path) => (
            fastbrdf_io::read_bounded(path, limit, &what)?,
            path.display().to_string(),
        ),
        None => {
            if std::io::stdin().is_terminal() {
                return Err(CliError::input(
                    "no input: pipe CSV into stdin or use --input FILE (see --help)",
                ));
            }
            (
                fastbrdf_io::read_reader_bounded(
                    std::io::stdin().lock(),
                    Path::new("<stdin>"),
                    limit,
                    &what,
                )?,
                "<stdin>".to_string(),
            )
        }
    };
    let text = fastbrdf_io::utf8_text(bytes, Path::new(&source))?;
    Ok((text, source))
}

/// A CSV reading error, naming the line where the record starts.
pub fn csv_error(source: &str, text: &str, e: &csv::Error) -> CliError {
    let line = e.position().map(|p| line_of(text, p));
    let at = line.map_or_else(String::new, |l| format!("line {l}: "));
    let what = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("expected {expected_len} fields, found {len}"),
        csv::ErrorKind::Utf8 { err, .. } => format!("field {} is not UTF-8 text", err.field() + 1),
        csv::ErrorKind::Io(err) => format!("cannot read: {err}"),
        _ => shorten(&e.to_string(), 200),
    };
    CliError::input(format!("{source}: {at}{what}"))
}

/// Line numbers of byte offsets, computed incrementally: records come in order, so the input is
/// scanned once in all (a line count from the start for every record made `eval` quadratic in
/// its input). A line ends at "\n", "\r\n" or a lone "\r", the csv crate's terminators.
pub struct Lines<'a> {
    bytes: &'a [u8],
    at: usize,
    line: u64,
}

impl<'a> Lines<'a> {
    pub fn new(text: &'a str) -> Self {
        Self {
            bytes: text.as_bytes(),
            at: 0,
            line: 1,
        }
    }

    /// The line where a record starts. The csv crate's own line count is one short for a
    /// record that follows blank lines (its position points at the skipped line break), so the
    /// line is computed from the byte offset, past any line breaks.
    pub fn of(&mut self, p: &csv::Position) -> u64 {
        let b = self.bytes;
        let mut target = usize::try_from(p.byte()).unwrap_or(usize::MAX).min(b.len());
        while target < b.len() && matches!(b[target], b'\n' | b'\r') {
            target += 1;
        }
        if target < self.at {
            (self.at, self.line) = (0, 1);
        }
        while self.at < target {
            match b[self.at] {
                b'\n' => self.line += 1,
                b'\r' if b.get(self.at + 1) != Some(&b'\n') => self.line += 1,
                _ => {}
            }
            self.at += 1;
        }
        self.line
    }
}

/// The line where a record starts (one-off; see [`Lines`]).
pub fn line_of(text: &str, p: &csv::Position) -> u64 {
    Lines::new(text).of(p)
}

/// A CSV reader over `text` (headers, fields trimmed), its header row and that row's line;
/// an input that already has one of the `outputs` columns is refused (the output would
/// carry it twice). Shared by `eval` and `sample`.
pub fn csv_headers<'a>(
    text: &'a str,
    source: &str,
    outputs: &[&str],
) -> Result<(csv::Reader<&'a [u8]>, csv::StringRecord, u64), CliError> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| csv_error(source, text, &e))?
        .clone();
    let hline = headers.position().map_or(1, |p| line_of(text, p));
    if let Some(v) = outputs.iter().find(|v| headers.iter().any(|h| h == **v)) {
        return Err(CliError::input(format!(
            "{source}: line {hline}: the input already has a '{v}' column"
        )));
    }
    Ok((reader, headers, hline))
}

/// The index of each of `names` in `headers`, each present exactly once; otherwise an error
/// naming the column and, for a missing one, what `needs` them (`sample`, `a measured BRDF`).
/// Shared by `sample` and `measured eval`.
pub fn required_columns(
    headers: &csv::StringRecord,
    names: &[&str],
    source: &str,
    hline: u64,
    needs: &str,
) -> Result<Vec<usize>, CliError> {
    names
        .iter()
        .map(|name| {
            let mut found = headers.iter().enumerate().filter(|(_, h)| h == name);
            match (found.next(), found.next()) {
                (Some((i, _)), None) => Ok(i),
                (None, _) => Err(CliError::input(format!(
                    "{source}: line {hline}: missing column '{name}' ({needs} needs columns {})",
                    names.join(",")
                ))),
                _ => Err(CliError::input(format!(
                    "{source}: line {hline}: column '{name}' appears more than once"
                ))),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::Lines;

    fn pos(byte: u64) -> csv::Position {
        let mut p = csv::Position::new();
        p.set_byte(byte);
        p
    }

    #[test]
    fn lines_end_at_lf_crlf_and_lone_cr() {
        let text = "a\nb\r\nc\rd\n\n\re";
        let mut l = Lines::new(text);
        assert_eq!(l.of(&pos(0)), 1);
        assert_eq!(l.of(&pos(2)), 2);
        assert_eq!(l.of(&pos(5)), 3);
        assert_eq!(l.of(&pos(7)), 4);
        // Blank lines before a record are skipped: "e" is on line 7.
        assert_eq!(l.of(&pos(9)), 7);
        // Out of order (never happens for records) still answers right.
        assert_eq!(l.of(&pos(2)), 2);
    }
}
