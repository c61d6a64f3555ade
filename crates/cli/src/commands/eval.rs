//! `fastbrdf eval`: evaluate one model on CSV rows.
//!
//! Input: CSV with a header. Required columns by kind: lobes `cos`; distributions `cos_h`;
//! shadowing `cos_v` (and `cos_l` for the two-sided term; the V-cavity also `cos_h`,
//! `cos_vh`); Fresnel `cos_vh`; full BRDFs `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z`. Other columns are
//! passed through. Output: the input columns plus `value`. Any malformed or out-of-domain row is
//! an error naming its line (where the record starts) and field (exit code 2), quoting at most
//! 40 characters of the input, and nothing is written to stdout. The input is read once and at
//! most `--max-input-mib` MiB (default 256) of it: `/dev/zero` or an endless pipe is refused.

use crate::CliError;
use fastbrdf::{Model, Real, registry};
use fastbrdf_io::shorten;
use std::io::IsTerminal;
use std::path::Path;

/// The most characters of the input quoted in a message.
const QUOTE: usize = 40;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  printf 'cos\\n1\\n0.9\\n' | fastbrdf eval --model flog --param n=20\n  \
fastbrdf eval --model cook-torrance --param alpha=0.2 --param f=schlick --input pairs.csv\n  \
printf 'cos\\n1\\n0.99\\n' | fastbrdf eval --model pow --material gold-paint   (n = 36.8, the fit's)\n  \
printf 'cos_vh\\n1\\n0.5\\n' | fastbrdf eval --model fresnel-conductor --metal gold   (value_r,value_g,value_b)\n\n\
Output: CSV, the input columns then `value` (a coloured model, --metal or a parameter given\n\
as R,G,B: `value_r,value_g,value_b`). Errors name the file, the line where the record\n\
starts and the field; exit code 2 for bad input (nothing on stdout), 3 when stdout cannot be\n\
written."
)]
pub struct Args {
    /// Model id (see `fastbrdf models`).
    #[arg(long)]
    model: String,
    /// A parameter, NAME=VALUE; repeat for several.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// A MERL material (see `fastbrdf materials`) whose published fit supplies the model's n,
    /// alpha and f0 (Ngan et al. 2005); --param values win.
    #[arg(long, value_name = "NAME")]
    material: Option<String>,
    /// A named metal (see `fastbrdf metals`): f = conductor, eta and k per R, G, B channel;
    /// the output then has value_r, value_g, value_b instead of value.
    #[arg(long, value_name = "NAME")]
    metal: Option<String>,
    /// Arithmetic precision.
    #[arg(long, default_value = "f32", value_parser = ["f32", "f64"])]
    precision: String,
    /// Read CSV from this file instead of stdin.
    #[arg(long)]
    input: Option<std::path::PathBuf>,
    /// The most input read, in MiB (the input is refused beyond it, before any output).
    #[arg(long, default_value_t = 256, value_name = "MIB")]
    max_input_mib: u64,
}

/// Splits `NAME=VALUE` strings.
pub fn parse_params(params: &[String]) -> Result<Vec<(String, String)>, CliError> {
    params
        .iter()
        .map(|p| {
            p.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .ok_or_else(|| {
                    CliError::input(format!(
                        "--param '{}': expected NAME=VALUE",
                        shorten(p, QUOTE)
                    ))
                })
        })
        .collect()
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let params = super::materials::with_material(
        a.material.as_deref(),
        &a.model,
        &parse_params(&a.params)?,
    )?;
    let params = super::metals::with_metal(a.metal.as_deref(), &a.model, &params, false)?;
    // A coloured model (a parameter given as R,G,B) is three channel models.
    let lists = match fastbrdf::colour::channels(&a.model, &params)? {
        None => vec![params],
        Some(three) => three.to_vec(),
    };
    let givens: Vec<Vec<(&str, &str)>> = lists
        .iter()
        .map(|l| l.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect())
        .collect();
    let (text, source) = read_input(a.input.as_deref(), a.max_input_mib, "eval")?;
    fn build<T: Real>(id: &str, givens: &[Vec<(&str, &str)>]) -> Result<Vec<Model<T>>, CliError> {
        Ok(givens
            .iter()
            .map(|g| registry::build::<T>(id, g))
            .collect::<Result<_, _>>()?)
    }
    let out = if a.precision == "f64" {
        evaluate(build::<f64>(&a.model, &givens)?, &text, &source)?
    } else {
        evaluate(build::<f32>(&a.model, &givens)?, &text, &source)?
    };
    super::write_stdout(out.as_bytes())
}

/// The CSV input of `command` (`--input FILE` or stdin), read once and at most `max_mib` MiB,
/// as UTF-8 text, with its name for messages.
pub(crate) fn read_input(
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

/// The output columns of one model (grey) or three (the R, G, B channels of a coloured one).
fn value_columns(channels: usize) -> &'static [&'static str] {
    if channels == 3 {
        &["value_r", "value_g", "value_b"]
    } else {
        &["value"]
    }
}

/// Evaluates every row of `text` (CSV with a header) with one model (column `value`) or the
/// three channel models of a coloured one (`value_r`, `value_g`, `value_b`); returns the whole
/// output CSV.
pub fn evaluate<T: Real + std::str::FromStr>(
    models: Vec<Model<T>>,
    text: &str,
    source: &str,
) -> Result<String, CliError> {
    let model = &models[0];
    let values = value_columns(models.len());
    let (mut reader, headers, hline) = csv_headers(text, source, values)?;
    let (req, opt) = model.columns();
    // An input column named twice is ambiguous: refuse it rather than pick one.
    for name in req.iter().chain(opt.iter()) {
        if headers.iter().filter(|h| h == name).count() > 1 {
            return Err(CliError::input(format!(
                "{source}: line {hline}: column '{name}' appears more than once"
            )));
        }
    }
    let mut index = Vec::new();
    for name in req {
        let i = headers.iter().position(|h| h == *name).ok_or_else(|| {
            let optional = if opt.is_empty() {
                String::new()
            } else {
                format!(", optionally {}", opt.join(","))
            };
            CliError::input(format!(
                "{source}: line {hline}: missing column '{name}' (a {} model needs columns {}{optional})",
                model.kind().name(),
                req.join(",")
            ))
        })?;
        index.push(Some(i));
    }
    for name in opt {
        index.push(headers.iter().position(|h| h == *name));
    }
    let mut writer = csv::Writer::from_writer(Vec::new());
    let mut header_out: Vec<&str> = headers.iter().collect();
    header_out.extend(values);
    writer.write_record(&header_out).expect("writing to memory");
    let all_names: Vec<&str> = req.iter().chain(opt.iter()).copied().collect();
    let mut lines = Lines::new(text);
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(source, text, &e))?;
        // The line where the record starts (blank lines and quoted line breaks counted).
        let line = record.position().map_or(0, |p| lines.of(p));
        let mut input = Vec::with_capacity(index.len());
        for (k, i) in index.iter().enumerate() {
            let v = match i {
                None => None,
                Some(i) => {
                    let field = record.get(*i).unwrap_or("");
                    let x: T = field.parse().map_err(|_| {
                        CliError::input(format!(
                            "{source}: line {line}, field {} ('{}'): '{}' is not a number",
                            i + 1,
                            all_names[k],
                            shorten(field, QUOTE)
                        ))
                    })?;
                    Some(x)
                }
            };
            input.push(v);
        }
        let mut out: Vec<String> = record.iter().map(str::to_string).collect();
        for model in &models {
            let value = model.try_eval_row(&input).map_err(|e| {
                // Name the field of an out-of-domain input (a direction: its first component).
                let field = match &e {
                    fastbrdf::Error::Domain { input, .. } => headers
                        .iter()
                        .position(|h| h == input || h == format!("{input}_x"))
                        .map(|i| format!(", field {} ('{}')", i + 1, &headers[i])),
                    _ => None,
                };
                CliError::input(format!(
                    "{source}: line {line}{}: {e}",
                    field.unwrap_or_default()
                ))
            })?;
            out.push(value.to_string());
        }
        writer.write_record(&out).expect("writing to memory");
    }
    let bytes = writer.into_inner().expect("writing to memory");
    Ok(String::from_utf8(bytes).expect("CSV of UTF-8 input is UTF-8"))
}

/// A CSV reading error, naming the line where the record starts.
pub(crate) fn csv_error(source: &str, text: &str, e: &csv::Error) -> CliError {
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
pub(crate) struct Lines<'a> {
    bytes: &'a [u8],
    at: usize,
    line: u64,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(text: &'a str) -> Self {
        Self {
            bytes: text.as_bytes(),
            at: 0,
            line: 1,
        }
    }

    /// The line where a record starts. The csv crate's own line count is one short for a
    /// record that follows blank lines (its position points at the skipped line break), so the
    /// line is computed from the byte offset, past any line breaks.
    pub(crate) fn of(&mut self, p: &csv::Position) -> u64 {
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
pub(crate) fn line_of(text: &str, p: &csv::Position) -> u64 {
    Lines::new(text).of(p)
}

/// A CSV reader over `text` (headers, fields trimmed), its header row and that row's line;
/// an input that already has one of the `outputs` columns is refused (the output would
/// carry it twice). Shared by `eval` and `sample`.
pub(crate) fn csv_headers<'a>(
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
pub(crate) fn required_columns(
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
