//! `fastbrdf render` and `fastbrdf compare`: pictures of a model, and of several models against
//! a reference with difference heat maps and RMSE / PSNR / FLIP (fastbrdf-render).

use super::analysis::bar;
use super::eval::parse_params;
use crate::CliError;
use fastbrdf_render::bump::Bump;
use fastbrdf_render::compare::{self, Cell};
use fastbrdf_render::film::{Film, parse_size, write_atomic};
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Light, RgbBrdf, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use fastbrdf_render::{RenderError, Result as RResult};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;

impl From<RenderError> for CliError {
    fn from(e: RenderError) -> Self {
        match e {
            RenderError::Output { .. } => CliError::io(e.to_string()),
            _ => CliError::input(e.to_string()),
        }
    }
}

/// Scene options shared by render, compare and demo.
#[derive(clap::Args, Clone, Debug)]
pub struct SceneArgs {
    /// An OBJ mesh to render instead of the built-in sphere (normals computed when absent;
    /// at most 256 MiB, read once, so pipes work; materials are not read). `face`: the
    /// embedded MediaPipe canonical face (Apache-2.0); a file named face: `./face`.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// An albedo texture (PNG or JPEG, sRGB), mapped by the mesh's texture coordinates (at most
    /// 256 MiB, 16384 pixels per side and 2^25 pixels); it multiplies --albedo. `skin`: the
    /// built-in procedural skin (1024x1024, pores, colour variation); a file named skin: `./skin`.
    #[arg(long)]
    pub texture: Option<PathBuf>,
    /// A light: dir:X,Y,Z[:R,G,B[:INTENSITY]] (direction towards the light) or
    /// point:X,Y,Z[:R,G,B[:INTENSITY]]; repeat for several. Default: one key light.
    /// Coordinates and colour x intensity at most 1e6 in magnitude.
    #[arg(long = "light", value_name = "SPEC")]
    pub lights: Vec<String>,
    /// Image size WIDTHxHEIGHT (at most 8192 per side and 2^25 pixels).
    #[arg(long, default_value = "512x512")]
    pub size: String,
    /// Supersampling: N samples along each axis of a pixel, N x N per pixel (1..16): the
    /// default 2 takes 4 samples per pixel, 4 takes 16; 1 is one sample at the centre.
    #[arg(long, default_value_t = 2)]
    pub spp: u32,
    /// Procedural micro-relief SCALE,DEPTH (features per unit, relative height), e.g. 40,0.6
    /// (scale at most 1e4, depth at most 1e3).
    #[arg(long)]
    pub bump: Option<String>,
    /// Diffuse and specular weights KD,KS (0 to 1e3 each) [default: 0.6,0.4; with --material:
    /// 1,0.4; with --metal: 0,1, a metal has no diffuse term].
    #[arg(long)]
    pub weights: Option<String>,
    /// Linear albedo R,G,B (0 to 1e3 each) [default: 0.8,0.8,0.8; with --material: the
    /// matching fit's diffuse kd].
    #[arg(long)]
    pub albedo: Option<String>,
    /// Exposure multiplier applied before sRGB encoding of PNG pictures (at most 1e6). EXR files
    /// hold the linear radiance, unscaled.
    #[arg(long, default_value_t = 1.0)]
    pub exposure: f32,
    /// Shadow rays for the lights: on (a light blocked by an object adds nothing) or off (every
    /// light reaches every surface facing it: the pictures before shadows). The GPU renderer
    /// (--gpu) casts the same shadow rays.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub shadows: OnOff,
    /// A ground plane under the object (grey, diffuse), to catch its shadow.
    #[arg(long)]
    pub floor: bool,
    /// Environment light: `sky` (built in: a sky gradient and a sun disc where the default key
    /// light is, no file needed), `white` (radiance 1 everywhere: the furnace) or a
    /// latitude-longitude HDR map FILE (Radiance .hdr or OpenEXR, 2:1, at most 8192x4096, 512
    /// MiB, finite non-negative texels; +y up, the centre column behind the subject).
    /// Importance-sampled; it replaces the ambient term and, unless --light is given, the
    /// default key light. CPU only.
    #[arg(long, value_name = "FILE|sky|white")]
    pub env: Option<String>,
    /// Environment samples per primary ray (each one map-sampled and one cosine-sampled
    /// direction, combined by multiple importance sampling), taken as progressive passes
    /// (1..4096); times N x N of --spp per pixel.
    #[arg(long, default_value_t = 16)]
    pub env_samples: u32,
}

/// A switch given as `on` or `off`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnOff {
    On,
    Off,
}

/// `--weights` when not given.
pub const DEFAULT_WEIGHTS: &str = "0.6,0.4";
/// `--albedo` when not given.
pub const DEFAULT_ALBEDO: &str = "0.8,0.8,0.8";

/// Largest kd, ks, albedo channel and bump depth: far beyond physical (1) but finite renders.
pub const MAX_WEIGHT: f32 = 1e3;
/// Largest `--exposure`.
pub const MAX_EXPOSURE: f32 = 1e6;
/// Largest bump scale (features per unit).
pub const MAX_BUMP_SCALE: f32 = 1e4;

fn floats(name: &str, s: &str, n: usize, max: f32) -> Result<Vec<f32>, CliError> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| CliError::input(format!("--{name} '{s}': not numbers")))?;
    if v.len() != n || v.iter().any(|x| !(0.0..=max).contains(x)) {
        return Err(CliError::input(format!(
            "--{name} '{s}': expected {n} numbers from 0 to {max}"
        )));
    }
    Ok(v)
}

impl SceneArgs {
    /// The scene spec and render options.
    pub fn spec(&self) -> Result<(SceneSpec, Options), CliError> {
        let (width, height) = parse_size(&self.size)?;
        let mut spec = SceneSpec::new();
        spec.mesh = self.mesh.clone();
        spec.shadows = self.shadows == OnOff::On;
        spec.floor = self.floor;
        spec.env = self.env.clone();
        if !(1..=fastbrdf_render::env::MAX_ENV_SAMPLES).contains(&self.env_samples) {
            return Err(CliError::input(format!(
                "--env-samples {}: must be 1 to {}",
                self.env_samples,
                fastbrdf_render::env::MAX_ENV_SAMPLES
            )));
        }
        spec.env_samples = self.env_samples;
        spec.texture = self.texture.clone();
        spec.lights = self
            .lights
            .iter()
            .map(|l| Light::parse(l))
            .collect::<RResult<_>>()?;
        if let Some(b) = &self.bump {
            let v = floats("bump", b, 2, MAX_BUMP_SCALE)?;
            if v[0] <= 0.0 || v[1] > MAX_WEIGHT {
                return Err(CliError::input(format!(
                    "--bump '{b}': the scale must be positive (at most {MAX_BUMP_SCALE}), the depth at most {MAX_WEIGHT}"
                )));
            }
            spec.bump = Some(Bump {
                scale: v[0],
                depth: v[1],
            });
        }
        let w = floats(
            "weights",
            self.weights.as_deref().unwrap_or(DEFAULT_WEIGHTS),
            2,
            MAX_WEIGHT,
        )?;
        (spec.kd, spec.ks) = (w[0], w[1]);
        let a = floats(
            "albedo",
            self.albedo.as_deref().unwrap_or(DEFAULT_ALBEDO),
            3,
            MAX_WEIGHT,
        )?;
        spec.albedo = Vec3::new(a[0], a[1], a[2]);
        if !(self.exposure > 0.0 && self.exposure <= MAX_EXPOSURE) {
            return Err(CliError::input(format!(
                "--exposure {}: must be positive and at most {MAX_EXPOSURE}",
                self.exposure
            )));
        }
        if !(1..=16).contains(&self.spp) {
            return Err(CliError::input(format!(
                "--spp {}: must be 1 to 16",
                self.spp
            )));
        }
        for note in setup::builtin_notes(&spec) {
            eprintln!("{note}");
        }
        Ok((
            spec,
            Options {
                width,
                height,
                spp: self.spp,
                shading: Shading::Batch,
            },
        ))
    }
}

/// Renders one model with a progress bar.
pub fn render_model(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    id: &str,
    params: &[(String, String)],
) -> Result<Film, CliError> {
    let specular = Arc::new(Specular::new(id, params)?);
    render_specular(spec, loaded, opts, specular)
}

/// Renders an RGB BRDF (a measured material, a fitted model): the whole BRDF, diffuse part
/// included, so the scene's weights are 0, 1 whatever --weights says (the texture and
/// --albedo colour only the diffuse term, which is 0 here).
pub fn render_rgb(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    label: &str,
    brdf: Arc<dyn RgbBrdf>,
) -> Result<Film, CliError> {
    let mut spec = spec.clone();
    (spec.kd, spec.ks) = (0.0, 1.0);
    render_specular(&spec, loaded, opts, Arc::new(Specular::rgb(label, brdf)))
}

/// Renders one specular model with a progress bar.
pub fn render_specular(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    specular: Arc<Specular>,
) -> Result<Film, CliError> {
    let id = specular.id.clone();
    let scene = setup::scene(spec, loaded, specular);
    let pb = bar(1, "render");
    let film = render(&scene, opts, &|d, t| {
        pb.set_length(t as u64);
        pb.set_position(d as u64);
    })?;
    pb.finish_and_clear();
    film.check_finite()
        .map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
    Ok(film)
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf render --model flog --param n=50 --out flog.png\n  \
fastbrdf render --model ward --param alpha=0.3 --bump 40,0.6 --size 1024x1024 --out ward.exr\n  \
fastbrdf render --model cook-torrance --param alpha=0.35 --mesh face.obj --texture skin.jpg --light dir:0,0,1 --out face.png\n  \
fastbrdf render --model ward --param alpha=0.35 --mesh face --texture skin --albedo 1,1,1 --env sky --out face.png   (built-in face and skin)\n  \
fastbrdf render --gpu --model flog --param n=50 --floor --out flog-gpu.png\n  \
fastbrdf render --model ward --param alpha=0.2 --floor --light point:2,3,3:1,1,1:20 --out shadow.png\n  \
fastbrdf render --model cook-torrance --param alpha=0.3 --env sky --floor --out sky.png   (built-in sky, 16 samples)\n  \
fastbrdf render --model ward --param alpha=0.2 --env studio.hdr --env-samples 64 --out studio.exr\n  \
fastbrdf render --model pow --env white --weights 1,0 --albedo 1,1,1 --out furnace.exr   (uniform 1: the furnace)\n  \
fastbrdf render --model ward --material gold-paint --out gold-ward.png   (alpha = the fit's Ward alpha)\n  \
fastbrdf render --model cook-torrance --param d=ggx --param g=smith-ggx-correlated --param alpha=0.2 --metal gold --out gold.png   (coloured: see `fastbrdf metals`)"
)]
pub struct RenderArgs {
    /// Specular model id (a lobe, a distribution or a BRDF).
    #[arg(long)]
    model: String,
    /// A model parameter, NAME=VALUE; repeat for several.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// A MERL material (see `fastbrdf materials`) whose published fit supplies the model's n,
    /// alpha and f0 (Ngan et al. 2005); --param values win. It also sets the diffuse colour
    /// (--albedo: the fit's kd, a Lambert term kd/pi as the renderer's; diffuse weight 1) unless
    /// --albedo or --weights is given; the specular weight stays KS of --weights (one number,
    /// and lobes shade unnormalised, so the fit's RGB ks is not used).
    #[arg(long, value_name = "NAME")]
    material: Option<String>,
    /// A named metal (see `fastbrdf metals`: gold, silver, copper, aluminium, chromium,
    /// iron): f = conductor, eta and k per R, G, B channel, so the specular term is coloured
    /// (three channel models); --param values win.
    #[arg(long, value_name = "NAME")]
    metal: Option<String>,
    #[command(flatten)]
    scene: SceneArgs,
    /// Output file: .png (8-bit sRGB with an sRGB chunk, --exposure applied) or .exr (linear
    /// radiance, 32-bit float, scanline ZIP, no exposure).
    #[arg(long)]
    out: PathBuf,
    /// Render on the GPU (wgpu: Vulkan, Metal, DX12 or GL; Mesa's lavapipe without a GPU):
    /// the same picture as the CPU renderer, within 2/255 (fastbrdf-gpu's tests/render.rs).
    /// Grey models only: a coloured one (--metal, R,G,B values) is CPU-only for now, and so is
    /// --env. Shadows as on the CPU (--shadows on|off).
    #[arg(long)]
    gpu: bool,
}

/// Renders one model on the GPU; returns the film and the adapter's label.
fn render_model_gpu(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    id: &str,
    params: &[(String, String)],
) -> Result<(Film, String), CliError> {
    let specular = Arc::new(Specular::new(id, params)?);
    if specular.is_coloured() {
        // Before an adapter is looked for: the answer does not depend on the machine.
        return Err(CliError::input(format!(
            "--gpu: coloured specular ({id} with a parameter given as R,G,B, e.g. by --metal) is CPU-only for now: drop --gpu"
        )));
    }
    if spec.env.is_some() {
        return Err(CliError::input(
            "--gpu: environment lighting (--env) is CPU-only: drop --gpu (the GPU renderer is a rasteriser without rays to sample the map with)".to_string(),
        ));
    }
    let scene = setup::scene(spec, loaded, specular);
    let gpu = fastbrdf_gpu::Gpu::new()?;
    let pb = bar(1, "render (GPU)");
    let film = fastbrdf_gpu::render::render_with_progress(
        &gpu.device,
        &gpu.queue,
        &scene,
        opts,
        &|d, t| {
            pb.set_length(t as u64);
            pb.set_position(d as u64);
        },
    )?;
    pb.finish_and_clear();
    Ok((film, gpu.label()))
}

pub fn run_render(a: &RenderArgs) -> Result<(), CliError> {
    let (mut spec, opts) = a.scene.spec()?;
    super::materials::diffuse(&mut spec, &a.scene, a.material.as_deref(), &a.model)?;
    super::metals::weights(&mut spec, &a.scene, a.metal.as_deref());
    check_out(&a.out, &["png", "exr"])?;
    let loaded = setup::load(&spec)?;
    let t = std::time::Instant::now();
    let params = super::materials::with_material(
        a.material.as_deref(),
        &a.model,
        &parse_params(&a.params)?,
    )?;
    let params = super::metals::with_metal(a.metal.as_deref(), &a.model, &params, true)?;
    let (film, on) = if a.gpu {
        let (film, label) = render_model_gpu(&spec, &loaded, &opts, &a.model, &params)?;
        (film, format!(", GPU: {label}"))
    } else {
        (
            render_model(&spec, &loaded, &opts, &a.model, &params)?,
            String::new(),
        )
    };
    let rendered = t.elapsed().as_secs_f64();
    film.save(&a.out, a.scene.exposure)?;
    let total = t.elapsed().as_secs_f64();
    let env = match &spec.env {
        Some(e) => format!(", environment {e} x {} samples", spec.env_samples),
        None => String::new(),
    };
    eprintln!(
        "wrote {} ({}x{}, {} samples/pixel ({}x{}{env}), {:.3} s: render {:.3} s, encode and write {:.3} s{on})",
        a.out.display(),
        opts.width,
        opts.height,
        opts.spp * opts.spp,
        opts.spp,
        opts.spp,
        total,
        rendered,
        total - rendered
    );
    Ok(())
}

pub fn check_out(path: &Path, exts: &[&str]) -> Result<(), CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if !exts.contains(&ext.as_str()) {
        return Err(CliError::input(format!(
            "--out {}: the file must end in .{}",
            path.display(),
            exts.join(" or .")
        )));
    }
    Ok(())
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf compare --models flog,schlick,cubic-rational --reference pow --param n=100 --out cmp.png\n  \
fastbrdf compare --models ward-pow,ward-power16 --reference ward --param alpha=0.3 --bump 40,0.6 --json --out ward.png\n  \
fastbrdf compare --models flog,power16-tuned --reference pow --material gold-paint --out gold.png\n  \
fastbrdf compare --models ggx,beckmann-power16 --reference cook-torrance --param alpha=0.2 --metal gold --out au.png\n  \
fastbrdf compare --models flog,schlick --reference pow --param n=100 --env sky --out cmp-sky.png\n  \
fastbrdf compare --models ward,cook-torrance --measured blue-rubber.binary --param alpha=0.29 --weights 0.3,0.05 --out rubber.png"
)]
pub struct CompareArgs {
    /// Models to compare (comma-separated ids).
    #[arg(long, value_delimiter = ',', required = true)]
    models: Vec<String>,
    /// The reference model id.
    #[arg(
        long,
        required_unless_present = "measured",
        conflicts_with = "measured"
    )]
    reference: Option<String>,
    /// A measured material (MERL .binary, see `fastbrdf measured`) as the reference instead of
    /// a model. It is the whole BRDF (diffuse included), so it renders with weights 0,1; the
    /// models render with the scene's --weights and --albedo (give them the material's
    /// diffuse colour and weights to compare like with like; `fastbrdf fit-measured` fits
    /// both).
    #[arg(long, value_name = "FILE")]
    measured: Option<PathBuf>,
    /// A parameter, NAME=VALUE, given to every model that takes it; repeat for several.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// A MERL material (see `fastbrdf materials`): each model and the reference take their n,
    /// alpha and f0 from its published fit (Ngan et al. 2005; Ward's alpha for ward-*, the
    /// Beckmann m for the others); --param values win. The diffuse colour comes from the
    /// reference's fit, as in `render`.
    #[arg(long, value_name = "NAME")]
    material: Option<String>,
    /// A named metal (see `fastbrdf metals`) for the reference and every model: f =
    /// conductor, eta and k per R, G, B channel (coloured pictures). Every compared model must
    /// take f, eta and k (cook-torrance, or a distribution shaded as cook-torrance): a model
    /// that cannot be gold would be compared grey against gold, so it is an error.
    #[arg(long, value_name = "NAME")]
    metal: Option<String>,
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

/// Parameters of `params` that model `id` takes.
pub fn params_for(
    id: &str,
    params: &[(String, String)],
) -> Result<Vec<(String, String)>, CliError> {
    let e = fastbrdf::registry::find(id)?;
    let mut names: Vec<&str> = e.info.params.iter().map(|p| p.name).collect();
    if e.info.kind == fastbrdf::Kind::Distribution {
        names.extend(["g", "f", "f0", "eta", "k", "denominator"]);
    }
    Ok(params
        .iter()
        .filter(|(k, _)| names.contains(&k.as_str()))
        .cloned()
        .collect())
}

/// One model of a comparison: label, id and its own parameters.
pub struct Entry {
    pub label: String,
    pub id: String,
    pub params: Vec<(String, String)>,
    /// An RGB BRDF (measured data, a fitted model) rendered instead of the registry model
    /// `id` (see [`render_rgb`]).
    pub rgb: Option<Arc<dyn RgbBrdf>>,
}

impl Entry {
    /// An entry labelled by its id and parameters.
    pub fn new(id: &str, params: Vec<(String, String)>) -> Self {
        let p: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let label = if p.is_empty() {
            id.to_string()
        } else {
            format!("{id} {}", p.join(" "))
        };
        Self {
            label,
            id: id.into(),
            params,
            rgb: None,
        }
    }

    /// An RGB BRDF labelled `label`.
    pub fn rgb(label: &str, brdf: Arc<dyn RgbBrdf>) -> Self {
        Self {
            label: label.into(),
            id: label.into(),
            params: Vec::new(),
            rgb: Some(brdf),
        }
    }

    /// Renders the entry: the registry model, or the RGB BRDF with weights 0, 1.
    pub fn render(
        &self,
        spec: &SceneSpec,
        loaded: &setup::Loaded,
        opts: &Options,
    ) -> Result<Film, CliError> {
        match &self.rgb {
            Some(b) => render_rgb(spec, loaded, opts, &self.label, b.clone()),
            None => render_model(spec, loaded, opts, &self.id, &self.params),
        }
    }
}

/// The scores of one model: on the clipped 8-bit sRGB pictures and on the linear film.
pub struct Scores {
    pub srgb: compare::Metrics,
    pub linear: compare::LinearMetrics,
}

impl Scores {
    /// The JSON object: numbers only, PSNR null when infinite; field names say the space.
    pub fn json(&self) -> serde_json::Value {
        let finite = |x: f64| x.is_finite().then_some(x);
        serde_json::json!({
            "model": self.srgb.model,
            "rmse": self.srgb.rmse,
            "psnr": finite(self.srgb.psnr),
            "flip": self.srgb.flip,
            "rmse_linear": self.linear.rmse,
            "psnr_linear": finite(self.linear.psnr),
            "psnr_linear_peak": self.linear.peak,
            "flip_reinhard": self.linear.flip_reinhard,
        })
    }
}

/// Checks a comparison's size and work (see `compare::check_compare`) before anything is read
/// or rendered.
pub fn check_compare(opts: &Options, models: usize) -> Result<(), CliError> {
    Ok(compare::check_compare(
        models,
        opts.width,
        opts.height,
        opts.spp,
    )?)
}

/// Renders the reference and models, builds the grid; returns (grid rgb, w, h, scores).
pub fn compare_models(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    exposure: f32,
    reference: &Entry,
    models: &[Entry],
) -> Result<(Vec<u8>, u32, u32, Vec<Scores>), CliError> {
    check_compare(opts, models.len())?;
    let (w, h) = (opts.width, opts.height);
    let rf = reference.render(spec, loaded, opts)?;
    let r = rf.to_srgb8(exposure);
    let mut films = vec![];
    for m in models {
        films.push(m.render(spec, loaded, opts)?);
    }
    let tests: Vec<Vec<u8>> = films.iter().map(|f| f.to_srgb8(exposure)).collect();
    let metrics: Vec<Scores> = models
        .iter()
        .zip(&tests)
        .zip(&films)
        .map(|((m, t), f)| Scores {
            srgb: compare::metrics(&m.label, &r, t, w, h),
            linear: compare::linear_metrics(&rf, f, exposure),
        })
        .collect();
    let diffs: Vec<Vec<f32>> = tests.iter().map(|t| compare::difference(&r, t)).collect();
    let scale = diffs
        .iter()
        .flatten()
        .copied()
        .fold(0.0f32, f32::max)
        .max(1.0 / 255.0);
    let mut top = vec![Cell {
        label: format!("reference: {}", reference.label),
        rgb: r.clone(),
    }];
    let mut bottom = vec![Cell {
        label: "difference to the reference:".into(),
        rgb: vec![255; (w * h * 3) as usize],
    }];
    for ((m, t), (d, sc)) in models.iter().zip(&tests).zip(diffs.iter().zip(&metrics)) {
        top.push(Cell {
            label: m.label.clone(),
            rgb: t.clone(),
        });
        let mt = &sc.srgb;
        let psnr = if mt.psnr.is_finite() {
            format!("{:.1} dB", mt.psnr)
        } else {
            "inf dB".into()
        };
        bottom.push(Cell {
            label: format!("PSNR {psnr}, FLIP {:.3}", mt.flip),
            rgb: compare::heat_map(d, scale),
        });
    }
    let (rgb, gw, gh) = compare::grid(&[top, bottom], w, h, Some(scale))?;
    Ok((rgb, gw, gh, metrics))
}

pub fn run_compare(a: &CompareArgs) -> Result<(), CliError> {
    let (mut spec, opts) = a.scene.spec()?;
    // With --measured, the first model stands for the reference where one is needed.
    let ref_id = a.reference.clone().unwrap_or_else(|| a.models[0].clone());
    super::materials::diffuse(&mut spec, &a.scene, a.material.as_deref(), &ref_id)?;
    super::metals::weights(&mut spec, &a.scene, a.metal.as_deref());
    check_out(&a.out, &["png"])?;
    check_compare(&opts, a.models.len())?;
    if spec.env.is_some() {
        // Each environment sample is a pass over every primary sample: the work cap counts them.
        let samples = (a.models.len() as u64 + 1)
            * u64::from(opts.width)
            * u64::from(opts.height)
            * u64::from(opts.spp).pow(2)
            * u64::from(spec.env_samples);
        let cap = fastbrdf_render::compare::MAX_COMPARE_SAMPLES;
        if samples > cap {
            return Err(CliError::input(format!(
                "the comparison would trace {samples} environment samples ({} renders of {}x{} at {}x{} samples per pixel, {} environment samples each): at most {cap}; use a smaller --size, --spp, --env-samples or fewer models",
                a.models.len() + 1,
                opts.width,
                opts.height,
                opts.spp,
                opts.spp,
                spec.env_samples
            )));
        }
    }
    let params = parse_params(&a.params)?;
    for (k, _) in &params {
        let mut used = false;
        for id in a.models.iter().chain(a.reference.as_ref()) {
            used |= params_for(id, &[(k.clone(), String::new())])?.len() == 1;
        }
        if !used {
            return Err(CliError::input(format!(
                "--param {k}: none of the models takes it"
            )));
        }
    }
    let own = |id: &str| {
        let p =
            super::materials::with_material(a.material.as_deref(), id, &params_for(id, &params)?)?;
        super::metals::with_metal(a.metal.as_deref(), id, &p, true)
    };
    let reference = match &a.measured {
        Some(file) => {
            let b = fastbrdf::measured::MeasuredBrdf::read(file)?;
            Entry::rgb(&format!("measured {}", file.display()), Arc::new(b))
        }
        None => Entry::new(&ref_id, own(&ref_id)?),
    };
    let ref_name = match &a.measured {
        Some(file) => file.display().to_string(),
        None => ref_id.clone(),
    };
    let models: Vec<Entry> = a
        .models
        .iter()
        .map(|m| Ok(Entry::new(m, own(m)?)))
        .collect::<Result<_, CliError>>()?;
    let loaded = setup::load(&spec)?;
    let (rgb, gw, gh, metrics) =
        compare_models(&spec, &loaded, &opts, a.scene.exposure, &reference, &models)?;
    write_atomic(&a.out, &fastbrdf_render::film::png_bytes(&rgb, gw, gh)?)?;
    eprintln!("wrote {}", a.out.display());
    if a.json {
        let rows: Vec<serde_json::Value> = metrics.iter().map(Scores::json).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(
                &serde_json::json!({"reference": ref_name, "metrics": rows})
            )
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
