//! `fastbrdf compare`: several models against a reference (a model or measured data) with
//! difference heat maps and RMSE / PSNR / FLIP (fastbrdf-render).

use super::common::gltf_scene;
use super::common::pictures::{Entry, Scores, check_compare, compare_models};
use super::common::scene::{SceneArgs, SceneFileArg, check_out, material_and_metal};
use crate::CliError;
use crate::model_args::{Chosen, ModelArgs, Use};
use fastbrdf_render::film::write_atomic;
use fastbrdf_render::setup;
use fastbrdf_render::user::UserRgb;
use std::path::PathBuf;
use std::sync::Arc;

const COMPARE_MATERIAL_HELP: &str = "A MERL material (see `fastbrdf materials`): each model and \
the reference take their n, alpha and f0 from its published fit (Ngan et al. 2005; Ward's alpha \
for ward-*, the Beckmann m for the others); --param values win. The diffuse colour comes from the \
reference's fit, as in `render`";

const COMPARE_METAL_HELP: &str = "A named metal (see `fastbrdf metals`) for the reference and \
every model: f = conductor, eta and k per R, G, B channel (coloured pictures). Every compared \
model must take f, eta and k (cook-torrance, or a distribution shaded as cook-torrance): a model \
that cannot be gold would be compared grey against gold, so it is an error";

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf compare --models flog,schlick,cubic-rational --reference pow --param n=100 --out cmp.png\n  \
fastbrdf compare --models ward-pow,ward-power16 --reference ward --param alpha=0.3 --bump 40,0.6 --json --out ward.png\n  \
fastbrdf compare --models flog,power16-tuned --reference pow --material gold-paint --out gold.png\n  \
fastbrdf compare --models ggx,beckmann-power16 --reference cook-torrance --param alpha=0.2 --metal gold --out au.png\n  \
fastbrdf compare --models flog,schlick --reference pow --param n=100 --env sky --out cmp-sky.png\n  \
fastbrdf compare --models ward,cook-torrance --measured blue-rubber.binary --param alpha=0.29 --weights 0.3,0.05 --out rubber.png\n  \
fastbrdf compare --scene scene.glb --set g=smith-ggx-correlated-fast,f=schlick-sg --set diffuse=burley --json --out sets.png   (approximation sets against a glTF scene's materials)",
    mut_arg("params", |a| a.help("A parameter, NAME=VALUE, given to every model that takes it; repeat for several")),
    mut_arg("material", |a| a.help(COMPARE_MATERIAL_HELP)),
    mut_arg("metal", |a| a.help(COMPARE_METAL_HELP))
)]
pub struct CompareArgs {
    /// Models to compare (comma-separated ids).
    #[arg(
        long,
        value_delimiter = ',',
        required_unless_present = "scene",
        conflicts_with = "scene"
    )]
    models: Vec<String>,
    /// The reference model id.
    #[arg(
        long,
        required_unless_present_any = ["measured", "scene"],
        conflicts_with_all = ["measured", "scene"]
    )]
    reference: Option<String>,
    #[command(flatten)]
    scene_file: SceneFileArg,
    /// With --scene: an approximation set, NAME=VALUE[,NAME=VALUE...] given to every
    /// material of the scene (e.g. g=smith-ggx-correlated-fast,f=schlick-sg); repeat for
    /// several. Each is rendered and compared with the materials as written (the reference;
    /// --param values go to both), and timed: its render's time per pixel and the shading
    /// cost alone (ns per BRDF evaluation) are printed.
    #[arg(long = "set", value_name = "SET")]
    sets: Vec<String>,
    /// A measured material (MERL .binary, see `fastbrdf measured`) as the reference instead of
    /// a model. It is the whole BRDF (diffuse included), so it renders with weights 0,1; the
    /// models render with the scene's --weights and --albedo (give them the material's
    /// diffuse colour and weights to compare like with like; `fastbrdf fit-measured` fits
    /// both).
    #[arg(long, value_name = "FILE", conflicts_with = "scene")]
    measured: Option<PathBuf>,
    #[command(flatten)]
    model_args: ModelArgs,
    #[command(flatten)]
    scene: SceneArgs,
    /// The grid picture (.png).
    #[arg(long, default_value = "fastbrdf-out/compare.png")]
    out: PathBuf,
    /// Print the metrics as JSON: {"reference", "metrics": [{model, rmse, psnr, flip,
    /// rmse_linear, psnr_linear, psnr_linear_peak, flip_reinhard}]}. rmse/psnr/flip: on the
    /// clipped 8-bit sRGB pictures; *_linear: on the linear HDR film (no exposure; PSNR against
    /// the reference's peak channel value, psnr_linear_peak); flip_reinhard: FLIP after the tone
    /// map x/(1+x) with the exposure. PSNR is null when infinite.
    #[arg(long)]
    json: bool,
}

/// Each environment sample is a pass over every primary sample: the comparison's work cap
/// counts them (`models` renders and the reference).
fn check_env_work(
    spec: &fastbrdf_render::setup::SceneSpec,
    opts: &fastbrdf_render::render::Options,
    models: usize,
) -> Result<(), CliError> {
    if spec.env.is_none() {
        return Ok(());
    }
    let samples = (models as u64 + 1)
        * u64::from(opts.width)
        * u64::from(opts.height)
        * u64::from(opts.spp).pow(2)
        * u64::from(spec.env_samples);
    let cap = fastbrdf_render::compare::MAX_COMPARE_SAMPLES;
    if samples > cap {
        return Err(CliError::input(format!(
            "the comparison would trace {samples} environment samples ({} renders of {}x{} at {}x{} samples per pixel, {} environment samples each): at most {cap}; use a smaller --size, --spp, --env-samples or fewer models",
            models + 1,
            opts.width,
            opts.height,
            opts.spp,
            opts.spp,
            spec.env_samples
        )));
    }
    Ok(())
}

/// `compare --scene FILE --set ...`: approximation sets against the scene's materials.
fn compare_gltf(
    a: &CompareArgs,
    file: &std::path::Path,
    spec: &fastbrdf_render::setup::SceneSpec,
    opts: &fastbrdf_render::render::Options,
) -> Result<(), CliError> {
    check_out(&a.out, &["png"])?;
    if a.sets.is_empty() {
        return Err(CliError::input(
            "--scene: give one or more approximation sets to compare with the scene's materials, e.g. --set g=smith-ggx-correlated-fast,f=schlick-sg",
        ));
    }
    let sets = a
        .sets
        .iter()
        .map(|s| Ok((s.clone(), gltf_scene::parse_set(s)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    check_compare(opts, sets.len())?;
    check_env_work(spec, opts, sets.len())?;
    let common = a.model_args.param.pairs()?;
    let loaded = gltf_scene::load(file, spec)?;
    let c = gltf_scene::compare_sets(&loaded, spec, opts, a.scene.exposure, &common, &sets)?;
    write_atomic(
        &a.out,
        &fastbrdf_render::film::png_bytes(&c.rgb, c.width, c.height)?,
    )?;
    let (ref_ns, ref_eval, results) = (c.reference_ns_per_pixel, c.reference_ns_per_eval, c.sets);
    eprintln!("wrote {}", a.out.display());
    let file = loaded.scene.file.clone();
    if a.json {
        let rows: Vec<serde_json::Value> = results
            .iter()
            .map(|r| {
                let mut v = r.scores.json();
                v["set"] = serde_json::json!(r.label);
                v["ns_per_pixel"] = serde_json::json!(r.ns_per_pixel);
                v["ns_per_eval"] = serde_json::json!(r.ns_per_eval);
                v
            })
            .collect();
        let mut out = fastbrdf_analysis::render_json::comparison("the scene's materials", rows);
        out["scene"] = serde_json::json!(file);
        out["reference_ns_per_pixel"] = serde_json::json!(ref_ns);
        out["reference_ns_per_eval"] = serde_json::json!(ref_eval);
        out["warnings"] = serde_json::json!(loaded.scene.warnings);
        println!(
            "{}",
            serde_json::to_string_pretty(&out).expect("serialisable")
        );
    } else {
        println!(
            "{:<44} {:>9} {:>7} | {:>12} {:>9} {:>8} | {:>9} {:>8}   (against {file}'s materials: {ref_ns:.0} ns/pixel, {ref_eval:.1} ns/eval)",
            "set", "PSNR dB", "FLIP", "RMSE linear", "PSNR dB", "FLIP rh", "ns/pixel", "ns/eval"
        );
        for r in &results {
            let (s, l) = (&r.scores.srgb, &r.scores.linear);
            println!(
                "{:<44} {:>9.2} {:>7.4} | {:>12.5} {:>9.2} {:>8.4} | {:>9.0} {:>8.1}",
                fastbrdf_io::shorten(&r.label, 44),
                s.psnr,
                s.flip,
                l.rmse,
                l.psnr,
                l.flip_reinhard,
                r.ns_per_pixel,
                r.ns_per_eval
            );
        }
        println!(
            "sRGB: clipped 8-bit pictures as written; linear: the HDR film; ns/pixel: each render's wall time over its pixels, the least of up to {} renders within {} s ({} threads); ns/eval: shading alone, one BRDF evaluation by the batch kernels (one thread, {} direction pairs, the mean over the materials)",
            gltf_scene::TIMING_RENDERS,
            gltf_scene::TIMING_SECONDS,
            rayon::current_num_threads(),
            gltf_scene::COST_PAIRS
        );
    }
    Ok(())
}

pub fn run_compare(a: &CompareArgs) -> Result<(), CliError> {
    let (mut spec, opts) = a.scene.spec()?;
    if let Some(file) = &a.scene_file.scene {
        return compare_gltf(a, file, &spec, &opts);
    }
    if let Some(set) = a.sets.first() {
        return Err(CliError::input(format!(
            "--set {set}: approximation sets are for --scene FILE (a glTF scene's materials)"
        )));
    }
    // With --measured, the first model stands for the reference where one is needed.
    let ref_id = a.reference.clone().unwrap_or_else(|| a.models[0].clone());
    material_and_metal(&mut spec, &a.scene, &a.model_args, &ref_id)?;
    check_out(&a.out, &["png"])?;
    check_compare(&opts, a.models.len())?;
    check_env_work(&spec, &opts, a.models.len())?;
    // One spec per model (each takes the --param values it can use), the reference first.
    let ids: Vec<&str> = a
        .reference
        .iter()
        .chain(&a.models)
        .map(String::as_str)
        .collect();
    let mut chosen = a.model_args.chosen(&ids, Use::Shaded)?.into_iter();
    let entry = |id: &str, c: Chosen| match c {
        Chosen::Spec(s) => Entry::new(id, s),
        Chosen::User(u) => Entry::rgb(id, Arc::new(UserRgb::new(u))),
    };
    let reference = match &a.measured {
        Some(file) => {
            let b = fastbrdf::measured::MeasuredBrdf::read(file)?;
            Entry::rgb(&format!("measured {}", file.display()), Arc::new(b))
        }
        None => entry(&ref_id, chosen.next().expect("one model per id")),
    };
    let ref_name = match &a.measured {
        Some(file) => file.display().to_string(),
        None => ref_id.clone(),
    };
    let models: Vec<Entry> = a
        .models
        .iter()
        .zip(chosen)
        .map(|(m, c)| entry(m, c))
        .collect();
    let loaded = setup::load(&spec)?;
    let (rgb, gw, gh, metrics) =
        compare_models(&spec, &loaded, &opts, a.scene.exposure, &reference, &models)?;
    write_atomic(&a.out, &fastbrdf_render::film::png_bytes(&rgb, gw, gh)?)?;
    eprintln!("wrote {}", a.out.display());
    if a.json {
        let rows: Vec<serde_json::Value> = metrics.iter().map(Scores::json).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&fastbrdf_analysis::render_json::comparison(
                &ref_name, rows
            ))
            .expect("serialisable")
        );
    } else {
        println!(
            "{:<24} {:>10} {:>9} {:>7} | {:>12} {:>9} {:>8}   (against {}; peak {:.4})",
            "model",
            "RMSE sRGB",
            "PSNR dB",
            "FLIP",
            "RMSE linear",
            "PSNR dB",
            "FLIP rh",
            ref_name,
            metrics.first().map_or(0.0, |m| m.linear.peak)
        );
        for m in &metrics {
            println!(
                "{:<24} {:>10.5} {:>9.2} {:>7.4} | {:>12.5} {:>9.2} {:>8.4}",
                m.srgb.model,
                m.srgb.rmse,
                m.srgb.psnr,
                m.srgb.flip,
                m.linear.rmse,
                m.linear.psnr,
                m.linear.flip_reinhard
            );
        }
        println!(
            "sRGB: clipped 8-bit pictures as written; linear: the HDR film (no exposure), PSNR against the reference's peak, FLIP after the Reinhard tone map x/(1+x)"
        );
    }
    Ok(())
}
