//! `fastbrdf fit-measured`: a registry BRDF (with per-channel diffuse and specular albedos)
//! fitted to a MERL file (`fastbrdf_analysis::measured_fit`), with a picture of the measured
//! material beside the fit.

use super::common::pictures::{Entry, compare_models};
use super::common::progress::bar;
use super::common::scene::{SceneArgs, check_out};
use crate::model_args::{self, ParamArgs, Use};
use crate::{CliError, outln};
use fastbrdf::measured::MeasuredBrdf;
use fastbrdf_analysis::measured_fit::{self, Data, Metric, Options, Problem};
use std::path::PathBuf;
use std::sync::Arc;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf fit-measured --data blue-rubber.binary --model ward\n  \
fastbrdf fit-measured --data gold-metallic-paint.binary --model cook-torrance --param f=schlick --param d=ggx --out gold-fit.png\n  \
fastbrdf fit-measured --data brass.binary --model blinn-phong --metric low-log --samples 20000 --json\n\n\
The fitted model is, per colour channel c: rho_d[c]/pi + rho_s[c] * f(wi, wo), f the registry\n\
BRDF with its own numeric parameters shared by R, G and B (Ngan, Matusik and Durand 2005).\n\
--param fixes choices and values; every other numeric parameter the model reads is fitted over\n\
its documented range (see `fastbrdf models --kind brdf`), except Schlick's f90: it trades\n\
exactly against rho_s (only the products f0 rho_s and f90 rho_s are determined), so it is\n\
held at 1 unless --free f90 asks for it. After the fit, the parameters along a flat direction\n\
of the model at the optimum (not determined by the data: the column-normalised Jacobian of\n\
cos f has a singular value below 1e-5) are named in a warning on stderr. Data: the valid bins (all channels\n\
measured) with both directions within 80 degrees of the normal, at their centre directions;\n\
a fixed-seed subsample of --samples of them (deterministic). Metrics, over samples and\n\
channels, cos = the incident cosine, m measured, f fitted:\n  \
ngan-l2  sqrt(mean((cos (m - f))^2))                      (Ngan et al. 2005)\n  \
low-log  sqrt(mean((ln(1 + cos m) - ln(1 + cos f))^2))    (Low et al. 2012)\n  \
max      max |cos (m - f)|\n\
Optimiser: argmin's Nelder-Mead from --restarts starts (the defaults, then a low-discrepancy\n\
sequence over the ranges), the best polished once. For ngan-l2 the albedos are solved exactly\n\
(non-negative least squares per channel) and only the model's parameters are searched; for\n\
low-log and max the ngan-l2 fit is the start of a joint search of parameters and albedos.\n\
The picture (--out, default fastbrdf-out/fit-measured.png; --size etc. as in `render`): the\n\
measured material and the fit rendered alike (weights 0,1: both are the whole BRDF), with a\n\
difference heat map.\n\n\
--json prints {\"data\": FILE, \"model\": ID, \"metric\": NAME, \"samples\": N, \"eligible\": N,\n\
\"fixed\": {NAME: VALUE}, \"params\": {NAME: NUMBER}, \"rho_d\": [R, G, B], \"rho_s\": [R, G, B],\n\
\"residuals\": {\"ngan-l2\": X, \"low-log\": X, \"max\": X}, \"evaluations\": N, \"runs\": N,\n\
\"fit_seconds\": X, \"picture\": FILE, \"held\": {NAME: NUMBER}, \"undetermined\": [NAME]}\n\
(fixed values are numbers where they parse as one; held: parameters left at their default,\n\
not fitted; undetermined: the fitted quantities the data do not determine, rho_d and rho_s\n\
for the albedos, empty when all are).\n\
Errors: a malformed file, an unknown model, a non-BRDF or a bad --param is exit 2 naming it,\n\
with nothing on stdout and no picture written.",
    mut_arg("params", |a| a.help("Fix a parameter, NAME=VALUE (a choice such as f=schlick, or a number); repeat"))
)]
pub struct Args {
    /// The measured material: a MERL `.binary` file.
    #[arg(long, value_name = "FILE")]
    data: PathBuf,
    /// The BRDF to fit (a registry id of kind brdf).
    #[arg(long)]
    model: String,
    #[command(flatten)]
    params: ParamArgs,
    /// Fit a parameter that is otherwise held at its default (f90); repeat. A NAME that is
    /// fitted already or that the model with these choices does not read is refused (exit 2).
    #[arg(long = "free", value_name = "NAME")]
    free: Vec<String>,
    /// The metric minimised: ngan-l2, low-log or max.
    #[arg(long, default_value = "ngan-l2", value_parser = ["ngan-l2", "low-log", "max"])]
    metric: String,
    /// Bins sampled from the file (fixed seed); 0 = every eligible bin.
    #[arg(long, default_value_t = measured_fit::DEFAULT_SAMPLES)]
    samples: usize,
    /// Nelder-Mead starts (1..64).
    #[arg(long, default_value_t = 6)]
    restarts: usize,
    /// The comparison picture (.png).
    #[arg(long, default_value = "fastbrdf-out/fit-measured.png")]
    out: PathBuf,
    #[command(flatten)]
    scene: SceneArgs,
    /// JSON with numbers instead of a table (shape above).
    #[arg(long)]
    json: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let metric = Metric::parse(&a.metric).expect("clap checks the value");
    if !(1..=64).contains(&a.restarts) {
        return Err(CliError::input(format!(
            "--restarts {}: must be 1 to 64",
            a.restarts
        )));
    }
    let (spec, opts) = a.scene.spec()?;
    check_out(&a.out, &["png"])?;
    let model = fastbrdf_io::shorten(&a.model, 64);
    let fixed = model_args::spec(&a.model, &a.params.pairs()?, None, None, Use::AsIs)
        .map_err(|e| CliError::input(format!("--model {model}: {}", e.message)))?;
    let problem = Problem::with_free(&fixed, true, &a.free).map_err(|e| {
        if e.starts_with("--free ") {
            // Already names the argument at fault.
            return CliError::input(e);
        }
        CliError::input(format!("--model {model}: {e}"))
    })?;
    let b = MeasuredBrdf::read(&a.data)?;
    let data = Data::from_measured(&b, a.samples);
    if data.is_empty() {
        return Err(CliError::input(format!(
            "{}: no valid (measured) bin within {} degrees of the normal",
            a.data.display(),
            measured_fit::MAX_THETA_DEG
        )));
    }
    let t = std::time::Instant::now();
    let pb = bar(1, "fit");
    let f = measured_fit::fit(
        &problem,
        &data,
        &Options {
            metric,
            restarts: a.restarts,
            ..Options::default()
        },
        &|d, n| {
            pb.set_length(n as u64);
            pb.set_position(d as u64);
        },
    )
    .map_err(|e| CliError::input(format!("{}: {e}", a.data.display())))?;
    pb.finish_and_clear();
    let seconds = t.elapsed().as_secs_f64();
    if !f.undetermined.is_empty() {
        eprintln!(
            "warning: the data do not determine {} separately: the fit moves along a flat \
             direction of the model (only a combination of them is measured); fix one with \
             --param NAME=VALUE",
            and_list(&f.undetermined)
        );
    }
    // The picture, before anything is printed: a failed write leaves stdout empty.
    let fitted = Arc::new(f.brdf()?);
    let label = {
        // Four significant digits for the fitted values: a label, not the result.
        let sig = |v: f64| {
            let d = if v == 0.0 {
                0
            } else {
                (3 - v.abs().log10().floor() as i32).max(0) as usize
            };
            let t = format!("{v:.d$}");
            if t.contains('.') {
                t.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                t
            }
        };
        let mut p: Vec<String> = fixed
            .given()
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        p.extend(
            f.problem
                .free
                .iter()
                .zip(&f.values)
                .map(|(q, v)| format!("{}={}", q.name, sig(*v))),
        );
        format!("fit: {} {}", a.model, p.join(" "))
    };
    let loaded = fastbrdf_render::setup::load(&spec)?;
    let reference = Entry::rgb(
        &format!("measured {}", a.data.display()),
        Arc::new(b) as Arc<dyn fastbrdf_render::scene::RgbBrdf>,
    );
    let models = [Entry::rgb(&label, fitted)];
    let (rgb, gw, gh, _) =
        compare_models(&spec, &loaded, &opts, a.scene.exposure, &reference, &models)?;
    fastbrdf_render::film::write_atomic(&a.out, &fastbrdf_render::film::png_bytes(&rgb, gw, gh)?)?;
    eprintln!("wrote {}", a.out.display());
    let r = &f.residuals;
    if a.json {
        let picture = a.out.display().to_string();
        let doc = fastbrdf_analysis::measured_json::fit(
            &fastbrdf_analysis::measured_json::FitReport {
                data: &a.data.display().to_string(),
                model: &a.model,
                fixed: &fixed,
                eligible: data.eligible,
                seconds,
                picture: Some(&picture),
            },
            &f,
        );
        outln!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("serialisable")
        );
        return Ok(());
    }
    let mut s = format!(
        "{}: {} fitted by {} on {} of {} eligible bins ({} Nelder-Mead runs, {} evaluations, {:.2} s)\n",
        a.data.display(),
        a.model,
        metric.name(),
        f.samples,
        data.eligible,
        f.runs,
        f.evaluations,
        seconds
    );
    for (k, v) in fixed.given() {
        s.push_str(&format!("  {k:<10} {v} (fixed)\n"));
    }
    for (k, v) in &f.problem.held {
        s.push_str(&format!(
            "  {k:<10} {v} (held: trades against rho_s; --free {k} to fit it)\n"
        ));
    }
    for (p, v) in f.problem.free.iter().zip(&f.values) {
        let note = if f.undetermined.iter().any(|u| u == p.name) {
            ", not determined by the data"
        } else {
            ""
        };
        s.push_str(&format!(
            "  {:<10} {v:.6} (fitted in [{}, {}]{note})\n",
            p.name, p.lo, p.hi
        ));
    }
    let rgb = |x: [f64; 3]| format!("{:.6}, {:.6}, {:.6}", x[0], x[1], x[2]);
    s.push_str(&format!("  rho_d      {}  (R, G, B)\n", rgb(f.rho_d)));
    s.push_str(&format!("  rho_s      {}  (R, G, B)\n", rgb(f.rho_s)));
    s.push_str(&format!(
        "residuals: ngan-l2 {:.6e}, low-log {:.6e}, max {:.6e}\n",
        r.ngan_l2, r.low_log, r.max
    ));
    super::write_stdout(s.as_bytes())
}

/// "a", "a and b", "a, b and c".
fn and_list(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}
