//! `fastbrdf eval`: evaluate one model on CSV rows.
//!
//! Input: CSV with a header. Required columns by kind: lobes `cos`; distributions `cos_h`;
//! shadowing `cos_v` (and `cos_l` for the two-sided term; the V-cavity also `cos_h`,
//! `cos_vh`); Fresnel `cos_vh`; full BRDFs `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z`. Other columns are
//! passed through. Output: the input columns plus `value`. Any malformed or out-of-domain row is
//! an error naming its line (where the record starts) and field (exit code 2), quoting at most
//! 40 characters of the input, and nothing is written to stdout. The input is read once and at
//! most `--max-input-mib` MiB (default 256) of it: `/dev/zero` or an endless pipe is refused.

use super::common::input::{Lines, QUOTE, csv_error, csv_headers, read_input};
use crate::CliError;
use crate::model_args::{ModelArgs, Use};
use fastbrdf::{Model, Real};
use fastbrdf_io::shorten;

mod user;

const EVAL_METAL_HELP: &str = "A named metal (see `fastbrdf metals`): f = conductor, eta and k \
per R, G, B channel; the output then has value_r, value_g, value_b instead of value";

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  printf 'cos\\n1\\n0.9\\n' | fastbrdf eval --model flog --param n=20\n  \
fastbrdf eval --model cook-torrance --param alpha=0.2 --param f=schlick --input pairs.csv\n  \
printf 'cos\\n1\\n0.99\\n' | fastbrdf eval --model pow --material gold-paint   (n = 36.8, the fit's)\n  \
printf 'cos_vh\\n1\\n0.5\\n' | fastbrdf eval --model fresnel-conductor --metal gold   (value_r,value_g,value_b)\n\n\
Output: CSV, the input columns then `value` (a coloured model, --metal or a parameter given\n\
as R,G,B: `value_r,value_g,value_b`). Errors name the file, the line where the record\n\
starts and the field; exit code 2 for bad input (nothing on stdout), 3 when stdout cannot be\n\
written.",
    mut_arg("metal", |a| a.help(EVAL_METAL_HELP))
)]
pub struct Args {
    /// Model id (see `fastbrdf models`), or a user's model `file:PATH` (a BRDF Explorer
    /// `.brdf` file, a `.wgsl` or `.glsl` function; evaluated on the GPU, in f32).
    #[arg(long)]
    model: String,
    #[command(flatten)]
    model_args: ModelArgs,
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

pub fn run(a: &Args) -> Result<(), CliError> {
    if let Some(user) = a.model_args.user(&a.model)? {
        let (text, source) = read_input(a.input.as_deref(), a.max_input_mib, "eval")?;
        let out = user::evaluate(&*user, &text, &source)?;
        return super::write_stdout(out.as_bytes());
    }
    let spec = a.model_args.spec(&a.model, Use::AsIs)?;
    let (text, source) = read_input(a.input.as_deref(), a.max_input_mib, "eval")?;
    // A coloured model (a parameter given as R,G,B) is three channel models.
    fn models<T: Real>(spec: &fastbrdf::ModelSpec) -> Result<Vec<Model<T>>, CliError> {
        Ok(spec
            .channel_specs()
            .iter()
            .map(|c| c.model::<T>())
            .collect::<Result<_, _>>()?)
    }
    let out = if a.precision == "f64" {
        evaluate(models::<f64>(&spec)?, &text, &source)?
    } else {
        evaluate(models::<f32>(&spec)?, &text, &source)?
    };
    super::write_stdout(out.as_bytes())
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
