//! `fastbrdf eval`: evaluate one model on CSV rows.
//!
//! Input: CSV with a header. Required columns by kind: lobes `cos`; distributions `cos_h`;
//! shadowing `cos_v` (and `cos_l` for the two-sided term; the V-cavity also `cos_h`,
//! `cos_vh`); Fresnel `cos_vh`; full BRDFs `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z`. Other columns are
//! passed through. Output: the input columns plus `value`. Any malformed or out-of-domain row is
//! an error naming its line and column (exit code 2), and nothing is written to stdout.

use crate::CliError;
use fastbrdf::{Model, Real, registry};
use std::io::{IsTerminal, Read, Write};

#[derive(clap::Args)]
pub struct Args {
    /// Model id (see `fastbrdf models`).
    #[arg(long)]
    model: String,
    /// A parameter, NAME=VALUE; repeat for several.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Arithmetic precision.
    #[arg(long, default_value = "f32", value_parser = ["f32", "f64"])]
    precision: String,
    /// Read CSV from this file instead of stdin.
    #[arg(long)]
    input: Option<std::path::PathBuf>,
}

/// Splits `NAME=VALUE` strings.
pub fn parse_params(params: &[String]) -> Result<Vec<(String, String)>, CliError> {
    params
        .iter()
        .map(|p| {
            p.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .ok_or_else(|| CliError::input(format!("--param '{p}': expected NAME=VALUE")))
        })
        .collect()
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let params = parse_params(&a.params)?;
    let given: Vec<(&str, &str)> = params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect();
    let (text, source) = match &a.input {
        Some(path) => (
            std::fs::read_to_string(path)
                .map_err(|e| CliError::input(format!("cannot read {}: {e}", path.display())))?,
            path.display().to_string(),
        ),
        None => {
            if std::io::stdin().is_terminal() {
                return Err(CliError::input(
                    "no input: pipe CSV into stdin or use --input FILE (see --help)",
                ));
            }
            let mut s = String::new();
            std::io::stdin()
                .read_to_string(&mut s)
                .map_err(|e| CliError::input(format!("cannot read stdin: {e}")))?;
            (s, "<stdin>".to_string())
        }
    };
    let out = if a.precision == "f64" {
        evaluate(registry::build::<f64>(&a.model, &given)?, &text, &source)?
    } else {
        evaluate(registry::build::<f32>(&a.model, &given)?, &text, &source)?
    };
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(out.as_bytes()).map_err(|e| CliError {
        code: 1,
        message: format!("cannot write output: {e}"),
    })?;
    Ok(())
}

/// Evaluates every row of `text` (CSV with a header); returns the whole output CSV.
pub fn evaluate<T: Real + std::str::FromStr>(
    model: Model<T>,
    text: &str,
    source: &str,
) -> Result<String, CliError> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| CliError::input(format!("{source}: cannot read the CSV header: {e}")))?
        .clone();
    if headers.iter().any(|h| h == "value") {
        return Err(CliError::input(format!(
            "{source}: line 1: the input already has a 'value' column"
        )));
    }
    let (req, opt) = model.columns();
    let mut index = Vec::new();
    for name in req {
        let i = headers.iter().position(|h| h == *name).ok_or_else(|| {
            CliError::input(format!(
                "{source}: line 1: missing column '{name}' (a {} needs columns {})",
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
    header_out.push("value");
    writer.write_record(&header_out).expect("writing to memory");
    let all_names: Vec<&str> = req.iter().chain(opt.iter()).copied().collect();
    for (row, record) in reader.records().enumerate() {
        let line = row + 2;
        let record = record.map_err(|e| match e.kind() {
            csv::ErrorKind::UnequalLengths {
                expected_len, len, ..
            } => CliError::input(format!(
                "{source}: line {line}: expected {expected_len} fields, found {len}"
            )),
            _ => CliError::input(format!("{source}: line {line}: {e}")),
        })?;
        let mut input = Vec::with_capacity(index.len());
        for (k, i) in index.iter().enumerate() {
            let v = match i {
                None => None,
                Some(i) => {
                    let field = record.get(*i).unwrap_or("");
                    let x: T = field.parse().map_err(|_| {
                        CliError::input(format!(
                            "{source}: line {line}, column '{}': '{field}' is not a number",
                            all_names[k]
                        ))
                    })?;
                    Some(x)
                }
            };
            input.push(v);
        }
        let value = model
            .try_eval_row(&input)
            .map_err(|e| CliError::input(format!("{source}: line {line}: {e}")))?;
        let mut out: Vec<String> = record.iter().map(str::to_string).collect();
        out.push(value.to_string());
        writer.write_record(&out).expect("writing to memory");
    }
    let bytes = writer.into_inner().expect("writing to memory");
    Ok(String::from_utf8(bytes).expect("CSV of UTF-8 input is UTF-8"))
}
