//! `fastbrdf shader`: one model as a self-contained shader function (WGSL, or GLSL, HLSL and
//! MSL translated by naga), or as a BRDF Explorer `.brdf` file. Needs no GPU.

use crate::CliError;
use crate::model_args::{ModelArgs, Use};
use fastbrdf::ModelSpec;
use fastbrdf_gpu::export::{Form, Lang, export_form};
use std::path::PathBuf;

const SHADER_METAL_HELP: &str = "A named metal (see `fastbrdf metals`): f = conductor, eta and \
k per R, G, B channel. A coloured model (this, or any parameter given as R,G,B) exports three \
channel functions fb_<id>_r/_g/_b and fb_<id>_rgb returning vec3 (literal coefficients only)";

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf shader --model cook-torrance --param alpha=0.2 --param f=schlick --lang glsl\n  \
fastbrdf shader --model flog-normalized --param n=100 --lang hlsl --out flog.hlsl\n  \
fastbrdf shader --model ward --param alpha_x=0.1 --param alpha_y=0.4 --lang brdf-explorer --out ward.brdf\n  \
fastbrdf shader --all --lang msl --out shaders/\n  \
fastbrdf shader --model cook-torrance --material gold-paint --param f=schlick   (alpha, f0 from the fit)\n  \
fastbrdf shader --model cubic --lang glsl --runtime-params   (fb_cubic(c, p_n): n per pixel)\n  \
fastbrdf shader --model cook-torrance --param d=ggx --metal gold   (fb_cook_torrance_rgb(wi, wo) -> vec3)\n\n\
Output: a comment header (formula, source, parameters, documented error bounds, the command),\n\
then the library functions the model needs and `fb_<id>` (dashes as underscores). Lobes take\n\
(c), distributions (cos_h), Fresnel terms (cos_vh), shadowing (cos_v, cos_l, cos_h, cos_vh),\n\
BRDFs (wi, wo) in the local frame with the normal along +z. Coefficients are computed in f64\n\
for the given parameters and written as literals; with --runtime-params the model's numeric\n\
parameters become trailing arguments p_<name> (f32) and the coefficients are computed in the\n\
shader (for parameters that vary per pixel). --out writes atomically; --all writes every\n\
file or none. Exit codes: 0 ok, 2 bad model or parameter, 3 a file could not be written.",
    mut_arg("material", |a| a.conflicts_with("all")),
    mut_arg("metal", |a| a.help(SHADER_METAL_HELP).conflicts_with("all"))
)]
pub struct Args {
    /// Model id (see `fastbrdf models`).
    #[arg(long, required_unless_present = "all", conflicts_with = "all")]
    model: Option<String>,
    #[command(flatten)]
    model_args: ModelArgs,
    /// Output language.
    #[arg(long, default_value = "wgsl", value_parser = ["wgsl", "glsl", "hlsl", "msl", "brdf-explorer"])]
    lang: String,
    /// Write to this file instead of stdout (with --all: a folder, one file per model).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Every model, with default parameters (needs --out DIR).
    #[arg(long, requires = "out")]
    all: bool,
    /// Take the model's numeric parameters as trailing function arguments `p_<name>` and
    /// compute the coefficients in the shader (f32), instead of f64 literals.
    #[arg(long)]
    runtime_params: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let lang = Lang::parse(&a.lang).ok_or_else(|| CliError::input("unknown --lang"))?;
    let form = if a.runtime_params {
        Form::Runtime
    } else {
        Form::Literals
    };
    if a.all {
        let dir = a.out.as_ref().expect("clap: --all requires --out");
        if !a.model_args.param.params.is_empty() {
            return Err(CliError::input(
                "--all exports default parameters: drop --param, or export one --model",
            ));
        }
        // Build everything first: an error leaves no partial folder behind.
        let mut files = vec![];
        for e in fastbrdf::registry::all() {
            let text = export_form(&ModelSpec::new(e.info.id, &[])?, lang, form)?;
            files.push((format!("{}.{}", e.info.id, lang.extension()), text));
        }
        // All or nothing: the files are staged in a hidden folder and moved into place only
        // when every one was written (a full disk leaves no file and no temporary behind).
        let mut set = fastbrdf_io::OutputSet::new(dir)?;
        for (name, text) in &files {
            set.write(name, text.as_bytes())?;
        }
        set.commit()?;
        eprintln!(
            "wrote {} {} files to {}",
            files.len(),
            lang.name(),
            dir.display()
        );
        return Ok(());
    }
    let id = a.model.as_deref().expect("clap: --model or --all");
    // A BRDF Explorer file shades the model (a distribution as cook-torrance), so a metal
    // colours the BRDF it is shaded as; the other languages export the model itself.
    let use_ = if lang == Lang::BrdfExplorer && a.model_args.metal.metal.is_some() {
        Use::Shaded
    } else {
        Use::AsIs
    };
    let spec = a.model_args.spec(id, use_)?;
    let text = export_form(&spec, lang, form)?;
    match &a.out {
        Some(path) => fastbrdf_io::write_atomic(path, text.as_bytes())?,
        None => super::write_stdout(text.as_bytes())?,
    }
    Ok(())
}
