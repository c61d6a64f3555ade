//! `fastbrdf sample` (importance sampling of a BRDF on CSV rows) and `fastbrdf chi2` (its
//! chi-square goodness-of-fit test), issue 15. The library samples (`fastbrdf::sample`) and
//! tests (`fastbrdf::chi2`); this module parses, prints and draws.

use super::common::input::{Lines, QUOTE, csv_error, csv_headers, read_input, required_columns};
use crate::CliError;
use crate::model_args::{ParamArgs, Use};
use fastbrdf::chi2;
use fastbrdf::sample::Strategy;
use fastbrdf::{Brdf, Model, ModelSpec, Real};
use fastbrdf_analysis::chi2 as analysis_chi2;
use fastbrdf_io::shorten;

const STRATEGY_HELP: &str = "Strategies: auto (the model's default), cosine (every BRDF), lobe \
(closed-form lobe: phong/blinn-phong with pow, power*, sg*; ward-pow; the default there), \
d-cos (half vector from D cos: cook-torrance with beckmann(-ct), ggx, beckmann-pow; ward), \
vndf (visible normals: cook-torrance with beckmann(-ct) or ggx; the default there), twin (the \
exact twin's sampling weighted by f/pdf: other lobes, beckmann-power*, ward-pow, ward-power16). \
An invalid combination is an error naming the valid ones.";

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  printf 'wo_x,wo_y,wo_z,u1,u2\\n0.5,0,0.866,0.3,0.7\\n' | fastbrdf sample --model cook-torrance --param d=ggx --param alpha=0.2\n  \
fastbrdf sample --model phong --param n=100 --strategy lobe --precision f64 --input rows.csv\n  \
printf 'wo_x,wo_y,wo_z,wi_x,wi_y,wi_z\\n0,0,1,0,0,1\\n' | fastbrdf sample --model lambert --pdf\n\n\
Input: CSV with a header and columns wo_x,wo_y,wo_z,u1,u2 (u in [0, 1)); with --pdf,\n\
wo_x,wo_y,wo_z,wi_x,wi_y,wi_z. Other columns are passed through. Output: the input columns\n\
then wi_x,wi_y,wi_z,weight,pdf (weight = f(wi, wo) cos theta_i / pdf); a row that yields no\n\
sample (the draw fell below the horizon or has density 0: the strategy's missing mass) gives\n\
0,0,0,0,0. With --pdf: the input columns then pdf. Local frame: normal +z, wo and wi point\n\
away from the surface. Errors name the file, the line and the field; exit code 2 for bad\n\
input (nothing on stdout), 3 when stdout cannot be written.\n\n\
Strategies: auto (the model's default), cosine (every BRDF), lobe, d-cos, vndf, twin (see\n\
the book's docs/book/src/sampling.md); an invalid combination is an error naming the valid ones."
)]
pub struct SampleArgs {
    /// Model id: a full BRDF (see `fastbrdf models --kind brdf`).
    #[arg(long)]
    model: String,
    #[command(flatten)]
    params: ParamArgs,
    /// Sampling strategy: auto, cosine, lobe, d-cos, vndf, twin.
    #[arg(long, default_value = "auto", help = STRATEGY_HELP)]
    strategy: String,
    /// Arithmetic precision.
    #[arg(long, default_value = "f32", value_parser = ["f32", "f64"])]
    precision: String,
    /// Evaluate the pdf of given (wo, wi) rows instead of sampling.
    #[arg(long)]
    pdf: bool,
    /// Read CSV from this file instead of stdin.
    #[arg(long)]
    input: Option<std::path::PathBuf>,
    /// The most input read, in MiB (the input is refused beyond it, before any output).
    #[arg(long, default_value_t = 256, value_name = "MIB")]
    max_input_mib: u64,
}

/// The BRDF of `spec` in precision `T`, and the strategy resolved for it.
fn brdf<T: Real>(
    spec: &ModelSpec,
    strategy: &str,
) -> Result<(Box<dyn Brdf<T>>, Strategy), CliError> {
    let id = spec.id();
    let b = match spec.model::<T>()? {
        Model::Brdf(b) => b,
        m => {
            return Err(CliError::input(format!(
                "{id} is a {} model: only full BRDFs sample (a lobe through phong or blinn-phong's lobe=, a distribution through cook-torrance's d=)",
                m.kind().name()
            )));
        }
    };
    let s = Strategy::parse(strategy).ok_or_else(|| {
        CliError::input(format!(
            "--strategy '{}': expected one of {}",
            shorten(strategy, QUOTE),
            Strategy::ALL.map(|s| s.name()).join(", ")
        ))
    })?;
    let s = b
        .resolve(s)
        .map_err(|e| CliError::input(format!("{id}: {e}")))?;
    Ok((b, s))
}

pub fn run_sample(a: &SampleArgs) -> Result<(), CliError> {
    let spec = a.params.spec(&a.model, Use::AsIs)?;
    if spec.is_coloured() {
        return Err(CliError::input(
            "sample: a coloured parameter (R,G,B) is three models; sample one channel at a time",
        ));
    }
    let (text, source) = read_input(a.input.as_deref(), a.max_input_mib, "sample")?;
    let out = if a.precision == "f64" {
        let (b, s) = brdf::<f64>(&spec, &a.strategy)?;
        rows(b.as_ref(), s, a.pdf, &text, &source)?
    } else {
        let (b, s) = brdf::<f32>(&spec, &a.strategy)?;
        rows(b.as_ref(), s, a.pdf, &text, &source)?
    };
    super::write_stdout(out.as_bytes())
}

/// Samples (or evaluates the pdf of) every row; the whole output CSV.
fn rows<T: Real + std::str::FromStr>(
    b: &dyn Brdf<T>,
    s: Strategy,
    pdf_mode: bool,
    text: &str,
    source: &str,
) -> Result<String, CliError> {
    let (inputs, outputs): (&[&str], &[&str]) = if pdf_mode {
        (&["wo_x", "wo_y", "wo_z", "wi_x", "wi_y", "wi_z"], &["pdf"])
    } else {
        (
            &["wo_x", "wo_y", "wo_z", "u1", "u2"],
            &["wi_x", "wi_y", "wi_z", "weight", "pdf"],
        )
    };
    let (mut reader, headers, hline) = csv_headers(text, source, outputs)?;
    let index = required_columns(&headers, inputs, source, hline, "sample")?;
    let mut writer = csv::Writer::from_writer(Vec::new());
    let mut header_out: Vec<&str> = headers.iter().collect();
    header_out.extend(outputs);
    writer.write_record(&header_out).expect("writing to memory");
    let mut lines = Lines::new(text);
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(source, text, &e))?;
        let line = record.position().map_or(0, |p| lines.of(p));
        let field_err = |k: usize, why: String| {
            CliError::input(format!(
                "{source}: line {line}, field {} ('{}'): {why}",
                index[k] + 1,
                inputs[k]
            ))
        };
        let mut x: Vec<T> = Vec::with_capacity(index.len());
        for (k, &i) in index.iter().enumerate() {
            let field = record.get(i).unwrap_or("");
            let v: T = field.parse().map_err(|_| {
                field_err(k, format!("'{}' is not a number", shorten(field, QUOTE)))
            })?;
            if !v.is_finite() {
                return Err(field_err(k, format!("{v} is not a finite number")));
            }
            x.push(v);
        }
        let direction = |k: usize, name: &str| -> Result<[T; 3], CliError> {
            let w = [x[k], x[k + 1], x[k + 2]];
            if fastbrdf::vec3::normalize(w).is_none() {
                return Err(field_err(k, format!("{name} is a zero-length vector")));
            }
            if !fastbrdf::vec3::above_cos_min(w) {
                return Err(field_err(
                    k,
                    format!(
                        "{name} is below the horizon or grazing (cos theta < {}): the local frame's normal is +z and both directions point away from the surface",
                        fastbrdf::vec3::COS_MIN
                    ),
                ));
            }
            Ok(w)
        };
        let wo = direction(0, "wo")?;
        let mut out: Vec<String> = record.iter().map(str::to_string).collect();
        if pdf_mode {
            let wi = direction(3, "wi")?;
            out.push(b.pdf(wo, wi, s).to_string());
        } else {
            for k in [3, 4] {
                if !(x[k] >= T::zero() && x[k] < T::one()) {
                    return Err(field_err(k, format!("{} is outside [0, 1)", x[k])));
                }
            }
            match b.sample(wo, [x[3], x[4]], s) {
                Some(r) => {
                    out.extend(r.wi.iter().map(|v| v.to_string()));
                    out.push(r.weight.to_string());
                    out.push(r.pdf.to_string());
                }
                None => out.extend(std::iter::repeat_n("0".to_string(), 5)),
            }
        }
        writer.write_record(&out).expect("writing to memory");
    }
    let bytes = writer.into_inner().expect("writing to memory");
    Ok(String::from_utf8(bytes).expect("CSV of UTF-8 input is UTF-8"))
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf chi2 --model cook-torrance --param d=ggx --param alpha=0.1 --theta-i 60\n  \
fastbrdf chi2 --model phong --param n=1000 --strategy twin --json\n  \
fastbrdf chi2 --model ward --param alpha_x=0.1 --param alpha_y=0.4 --full --out ward.png\n\n\
Draws --samples directions for wo at --theta-i (azimuth 0), histograms them on --res x 2 --res\n\
bins of the upper hemisphere (theta, phi), integrates the pdf over every bin for the expected\n\
counts, pools bins expecting fewer than 5 (Mitsuba's rule; the draws with no sample are one\n\
more cell against the pdf's missing mass) and prints the p-value. Passes when p > 0.01.\n\
--full: Mitsuba's sizes (101 x 202 bins, 1e6 samples). Exit code 1 when the test fails, 2 for\n\
bad usage, 3 when an output cannot be written."
)]
pub struct Chi2Args {
    /// Model id: a full BRDF.
    #[arg(long)]
    model: String,
    #[command(flatten)]
    params: ParamArgs,
    /// Angle of wo from the normal, in degrees, in [0, 90).
    #[arg(long, default_value_t = 45.0, value_name = "DEG")]
    theta_i: f64,
    /// Sampling strategy: auto, cosine, lobe, d-cos, vndf, twin.
    #[arg(long, default_value = "auto", help = STRATEGY_HELP)]
    strategy: String,
    /// Number of samples (default 100000; 1000000 with --full).
    #[arg(long)]
    samples: Option<usize>,
    /// Bins in theta (phi gets twice as many; default 10; 101 with --full).
    #[arg(long)]
    res: Option<usize>,
    /// Random seed.
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Mitsuba's sizes: 101 x 202 bins, 1e6 samples.
    #[arg(long)]
    full: bool,
    /// Sample in this precision (the pdf is evaluated in f64).
    #[arg(long, default_value = "f64", value_parser = ["f32", "f64"])]
    precision: String,
    /// Print the numbers as JSON.
    #[arg(long)]
    json: bool,
    /// Write a PNG: observed and expected histograms side by side, and their difference.
    #[arg(long, value_name = "PNG")]
    out: Option<std::path::PathBuf>,
}

pub fn run_chi2(a: &Chi2Args) -> Result<(), CliError> {
    let spec = a.params.spec(&a.model, Use::AsIs)?;
    if !(a.theta_i >= 0.0 && a.theta_i < 90.0) {
        return Err(CliError::input(format!(
            "--theta-i {}: expected degrees in [0, 90)",
            a.theta_i
        )));
    }
    let cfg = analysis_chi2::config(a.full, a.samples, a.res, a.seed)
        .map_err(|e| CliError::input(format!("--{e}")))?;
    let (b64, s) = brdf::<f64>(&spec, &a.strategy)?;
    let t = a.theta_i.to_radians();
    let wo = [t.sin(), 0.0, t.cos()];
    let b32 = if a.precision == "f32" {
        Some(brdf::<f32>(&spec, &a.strategy)?.0)
    } else {
        None
    };
    let out = chi2::run_brdf(b64.as_ref(), b32.as_deref(), wo, s, &cfg, 1);
    if let Some(path) = &a.out {
        fastbrdf_io::write_atomic(path, &analysis_chi2::picture(&out).map_err(CliError::io)?)?;
    }
    let report = if a.json {
        let v = analysis_chi2::json(&out, &a.model, s, a.theta_i, &spec);
        format!("{}\n", serde_json::to_string_pretty(&v).expect("JSON"))
    } else {
        format!(
            "{} [{}] theta_i = {} deg, {} samples, {} x {} bins ({} pooled)\n\
             chi2 = {:.2}, dof = {}, p = {:.4e}: {} at {}\n\
             pdf integral {:.6}; no sample {} (expected {:.1}){}\n",
            a.model,
            s.name(),
            a.theta_i,
            out.samples,
            out.res_theta,
            out.res_phi,
            out.pooled,
            out.chi2,
            out.dof,
            out.p_value,
            if out.passed { "PASS" } else { "FAIL" },
            out.threshold,
            out.pdf_integral,
            out.missing_observed,
            out.missing_expected,
            if out.impossible {
                "; draws fell where the pdf is 0"
            } else {
                ""
            }
        )
    };
    super::write_stdout(report.as_bytes())?;
    if out.passed {
        Ok(())
    } else {
        Err(CliError {
            code: crate::EXIT_CHECK_FAILED,
            message: format!("chi-square test failed: p = {:.3e}", out.p_value),
        })
    }
}
