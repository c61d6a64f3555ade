//! `fastbrdf eval --model file:PATH`: a user's model on CSV rows of `wi`, `wo` (issue 31).
//! Every row is parsed first, then evaluated in one batch (one GPU dispatch, not one per row),
//! then written: the input columns plus `value` (a grey model) or `value_r,value_g,value_b`.
//! Directions are passed as given (not normalised; `nan` and `inf` are numbers): what a model
//! does with odd input is its own, and `fastbrdf conform` checks it.

use super::super::common::input::{Lines, QUOTE, csv_error, csv_headers, required_columns};
use crate::CliError;
use fastbrdf::user::UserBrdf;
use fastbrdf_io::shorten;

/// The input columns, in order.
const COLUMNS: [&str; 6] = ["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"];

/// The whole output CSV of `brdf` on the rows of `text` (read from `source`).
pub fn evaluate(brdf: &dyn UserBrdf, text: &str, source: &str) -> Result<String, CliError> {
    let values = super::value_columns(brdf.channels());
    let (mut reader, headers, hline) = csv_headers(text, source, values)?;
    let index = required_columns(&headers, &COLUMNS, source, hline, "a full BRDF")?;
    let mut records = Vec::new();
    let (mut wi, mut wo) = (Vec::new(), Vec::new());
    let mut lines = Lines::new(text);
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(source, text, &e))?;
        let line = record.position().map_or(0, |p| lines.of(p));
        let mut v = [0.0f64; 6];
        for (k, &i) in index.iter().enumerate() {
            let field = record.get(i).unwrap_or("");
            v[k] = field.parse().map_err(|_| {
                CliError::input(format!(
                    "{source}: line {line}, field {} ('{}'): '{}' is not a number",
                    i + 1,
                    COLUMNS[k],
                    shorten(field, QUOTE)
                ))
            })?;
        }
        wi.push([v[0], v[1], v[2]]);
        wo.push([v[3], v[4], v[5]]);
        records.push(record);
    }
    let c = brdf.channels();
    let mut out = vec![0.0; wi.len() * c];
    brdf.eval(&wi, &wo, &mut out).map_err(|e| CliError {
        code: crate::EXIT_CHECK_FAILED,
        message: format!("--model {}: {e}", brdf.name()),
    })?;
    let mut writer = csv::Writer::from_writer(Vec::new());
    let mut header_out: Vec<&str> = headers.iter().collect();
    header_out.extend(values);
    writer.write_record(&header_out).expect("writing to memory");
    for (k, record) in records.iter().enumerate() {
        let mut row: Vec<String> = record.iter().map(str::to_string).collect();
        row.extend(
            out[k * c..(k + 1) * c]
                .iter()
                .map(|x| (*x as f32).to_string()),
        );
        writer.write_record(&row).expect("writing to memory");
    }
    let bytes = writer.into_inner().expect("writing to memory");
    Ok(String::from_utf8(bytes).expect("CSV of UTF-8 input is UTF-8"))
}
