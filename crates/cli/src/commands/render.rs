//! `fastbrdf render`: a picture of one model (fastbrdf-render on the CPU, fastbrdf-gpu with
//! `--gpu`).

use super::common::gltf_scene;
use super::common::pictures::{render_rgb, render_specular, specular};
use super::common::progress::bar;
use super::common::scene::{SceneArgs, SceneFileArg, check_out, material_and_metal};
use crate::CliError;
use crate::model_args::{ModelArgs, Use};
use fastbrdf::ModelSpec;
use fastbrdf_gpu::user::{GpuBrdf, UserError, UserErrorKind, UserShader};
use fastbrdf_render::film::Film;
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::{Scene, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use fastbrdf_render::user::UserRgb;
use std::path::PathBuf;
use std::sync::Arc;

const RENDER_MATERIAL_HELP: &str = "A MERL material (see `fastbrdf materials`) whose published \
fit supplies the model's n, alpha and f0 (Ngan et al. 2005); --param values win. It also sets the \
diffuse colour (--albedo: the fit's kd, a Lambert term kd/pi as the renderer's; diffuse weight 1) \
unless --albedo or --weights is given; the specular weight stays KS of --weights (one number, and \
lobes shade unnormalised, so the fit's RGB ks is not used)";

const RENDER_METAL_HELP: &str = "A named metal (see `fastbrdf metals`: gold, silver, copper, \
aluminium, chromium, iron): f = conductor, eta and k per R, G, B channel, so the specular term is \
coloured (three channel models); --param values win";

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
fastbrdf render --model cook-torrance --param d=ggx --param g=smith-ggx-correlated --param alpha=0.2 --metal gold --out gold.png   (coloured: see `fastbrdf metals`)\n  \
fastbrdf render --scene scene.glb --env sky --out scene.png   (a glTF scene: its camera, lights unless --light/--env, materials as gltf-pbr)\n  \
fastbrdf render --scene scene.gltf --param f=schlick-sg --out sg.png   (a shortcut choice given to every material)\n  \
fastbrdf render --gpu --scene scene.glb --out scene-gpu.png   (the same picture on the GPU)",
    mut_arg("params", |a| a.help("A model parameter, NAME=VALUE; repeat for several")),
    mut_arg("material", |a| a.help(RENDER_MATERIAL_HELP)),
    mut_arg("metal", |a| a.help(RENDER_METAL_HELP))
)]
pub struct RenderArgs {
    /// Specular model id (a lobe, a distribution or a BRDF), or a user's model `file:PATH` (a
    /// BRDF Explorer `.brdf` file, a `.wgsl` or `.glsl` function: the whole BRDF, rendered
    /// with weights 0,1, its values from the GPU evaluator; with --gpu its shader runs in the
    /// GPU renderer's). Not with --scene (every material of a glTF scene is gltf-pbr).
    #[arg(
        long,
        required_unless_present = "scene",
        conflicts_with = "scene",
        default_value = "",
        hide_default_value = true
    )]
    model: String,
    #[command(flatten)]
    scene_file: SceneFileArg,
    #[command(flatten)]
    model_args: ModelArgs,
    #[command(flatten)]
    scene: SceneArgs,
    /// Output file: .png (8-bit sRGB with an sRGB chunk, --exposure applied) or .exr (linear
    /// radiance, 32-bit float, scanline ZIP, no exposure).
    #[arg(long)]
    out: PathBuf,
    /// Render on the GPU (wgpu: Vulkan, Metal, DX12 or GL; Mesa's lavapipe without a GPU):
    /// the same picture as the CPU renderer with --aa grid, within 2/255 (fastbrdf-gpu's
    /// tests/render.rs). Grey models and users' models (file:PATH, their shader spliced into
    /// the GPU's): a coloured registry model (--metal, R,G,B values) is CPU-only for now. With --scene, the
    /// glTF scene's materials (gltf-pbr, coloured, anisotropy along the tangents; base colour,
    /// metallic-roughness, normal, occlusion and emissive textures) on the GPU. Shadows
    /// as on the CPU (--shadows on|off). With --env, the map sampled per sample with the CPU's
    /// random numbers (--sampler), by map directions (a sun apart as on the CPU, --env-sun),
    /// cosine directions and a GGX lobe of the model's roughness: without a specular term the
    /// CPU's picture to rounding, with one the same in the limit (the CPU samples the BRDF
    /// itself).
    #[arg(long)]
    gpu: bool,
    /// Render N times in this process and report each render's time (for timing; the
    /// picture written is the first: renders are deterministic, every one is the same). The
    /// first is a fresh process's render (its threads started, its memory first touched; on
    /// the GPU its first draws, which may compile the driver's shader variants); the later
    /// ones a warm process's, as `tools/equal_error.py` times Mitsuba 3's render after a
    /// warm-up render. With --gpu on one device, each render's draws reported too.
    #[arg(long, default_value_t = 1, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=100))]
    repeat: u32,
}

/// What `finish` reports besides the first render's time: the model's set-up, where timed
/// apart, and the later renders' times (`--repeat`).
#[derive(Default)]
struct Times {
    set_up: Option<f64>,
    later: Vec<f64>,
}

/// `--repeat`: runs `render` `n` times (at least once) and returns the first result and
/// the seconds of each later run, whose results (the same as the first) are dropped.
fn repeated<T>(
    n: u32,
    render: impl Fn() -> Result<T, CliError>,
) -> Result<(T, Vec<f64>), CliError> {
    let first = render()?;
    let later = (1..n)
        .map(|_| {
            let t = std::time::Instant::now();
            drop(render()?);
            Ok(t.elapsed().as_secs_f64())
        })
        .collect::<Result<_, CliError>>()?;
    Ok((first, later))
}

/// Renders one model on the GPU ([`gpu_repeated`]: `repeat` times).
fn render_model_gpu(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    (id, model): (&str, &ModelSpec),
    repeat: u32,
) -> Result<(RenderedGpu, Vec<f64>), CliError> {
    if model.is_coloured() {
        // Before an adapter is looked for: the answer does not depend on the machine.
        return Err(CliError::input(format!(
            "--gpu: coloured specular ({id} with a parameter given as R,G,B, e.g. by --metal) is CPU-only for now: drop --gpu"
        )));
    }
    // The plan is built once, in the spec: the scene's specular term and the GPU's shader
    // both come from it.
    let mut specular = Specular::new(model)?;
    specular.id = id.into();
    let scene = setup::scene(spec, loaded, Arc::new(specular));
    render_scene_gpu(&scene, opts, repeat)
}

/// Renders `scene` on a new device ([`fastbrdf_gpu::render::render_with_progress`]),
/// `repeat` times ([`gpu_repeated`]), the device's creation in the first render's set-up.
fn render_scene_gpu(
    scene: &Scene,
    opts: &Options,
    repeat: u32,
) -> Result<(RenderedGpu, Vec<f64>), CliError> {
    let t0 = std::time::Instant::now();
    let gpu = fastbrdf_gpu::Gpu::new()?;
    gpu_repeated(repeat, &gpu, t0, |progress| {
        Ok(fastbrdf_gpu::render::render_with_progress(
            &gpu.device,
            &gpu.queue,
            scene,
            opts,
            progress,
        )?)
    })
}

/// A GPU render run `repeat` times on one device (`--repeat`), the progress bar on the first:
/// the first film, the adapter's label with the first render's set-up and draws ("ADAPTER;
/// set-up X s, draws Y s (then Z s: --repeat 2)", the later renders' draws in brackets) and
/// the later renders' whole times. `render` passes its progress callback to the renderer,
/// which reports progress 0 once everything is set up (device, pipelines, buffers) and before
/// its first draw: from there on the time is the draws' (and the read-backs'), the part a
/// faster GPU shortens; the set-up is mostly the driver's shader compilation, which
/// tools/equal_error.py leaves out as it leaves out Mitsuba's JIT compilation. The first
/// draws of a process may still compile (lavapipe builds a shader's variants at its first
/// draw): the later ones are a warm device's.
fn gpu_repeated(
    repeat: u32,
    gpu: &fastbrdf_gpu::Gpu,
    t0: std::time::Instant,
    render: impl Fn(&dyn Fn(usize, usize)) -> Result<Film, CliError>,
) -> Result<(RenderedGpu, Vec<f64>), CliError> {
    use std::time::Instant;
    // One render from `start`: its film and, once it reported its first draw, the seconds
    // from `start` to it and from it to the end.
    let once = |start: Instant, progress: &dyn Fn(usize, usize)| {
        let draws = std::cell::Cell::new(None);
        let film = render(&|d, t| {
            if d == 0 && draws.get().is_none() {
                draws.set(Some(Instant::now()));
            }
            progress(d, t);
        })?;
        let timed = draws
            .get()
            .map(|s| ((s - start).as_secs_f64(), s.elapsed().as_secs_f64()));
        Ok::<_, CliError>((film, timed))
    };
    let pb = bar(1, "render (GPU)");
    let (film, first) = once(t0, &|d, t| {
        pb.set_length(t as u64);
        pb.set_position(d as u64);
    })?;
    pb.finish_and_clear();
    let (mut later, mut later_draws) = (Vec::new(), Vec::new());
    for _ in 1..repeat {
        let t = Instant::now();
        let (_, timed) = once(t, &|_, _| {})?;
        later.push(t.elapsed().as_secs_f64());
        later_draws.extend(timed.map(|(_, d)| d));
    }
    let mut label = gpu.label();
    if let Some((set_up, draws)) = first {
        label += &format!("; set-up {set_up:.4} s, draws {draws:.4} s");
        if !later_draws.is_empty() {
            let each: Vec<String> = later_draws.iter().map(|s| format!("{s:.4} s")).collect();
            label += &format!(" (then {}: --repeat {repeat})", each.join(", "));
        }
    }
    Ok(((film, label), later))
}

/// A GPU render's film and the adapter's label with its times ([`gpu_repeated`]).
type RenderedGpu = (Film, String);

/// A user's failure as the CLI's: the file's errors exit 2, the GPU's 1.
fn user_error(e: UserError) -> CliError {
    CliError {
        code: match e.kind {
            UserErrorKind::Input => crate::EXIT_INPUT,
            UserErrorKind::Gpu => crate::EXIT_CHECK_FAILED,
        },
        message: e.message,
    }
}

/// Renders a user's model (`file:PATH`) on the GPU: its shader spliced into the render shader
/// (`fastbrdf_gpu::render::render_user`), the whole BRDF with weights 0, 1 as on the CPU;
/// returns the film and the adapter's label. The scene is the CPU's (its RGB BRDF the
/// shader's compute evaluator on the same device, which the GPU renderer does not call).
fn render_user_gpu(
    a: &RenderArgs,
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
) -> Result<(RenderedGpu, Vec<f64>), CliError> {
    let path = a
        .model
        .strip_prefix(crate::model_args::USER_PREFIX)
        .unwrap_or("");
    if path.is_empty() {
        return Err(CliError::input(
            "--model file:: no path after 'file:' (e.g. --model file:my.brdf)",
        ));
    }
    for (flag, given) in [
        ("--material", &a.model_args.material.material),
        ("--metal", &a.model_args.metal.metal),
    ] {
        if let Some(m) = given {
            return Err(CliError::input(format!(
                "{flag} {m}: a user's model ({}) takes its values from --param only",
                a.model
            )));
        }
    }
    // The file and the values are checked before a device is opened.
    let shader = UserShader::load(std::path::Path::new(path)).map_err(user_error)?;
    let given = a.model_args.param.pairs()?;
    let values = shader.values(&given).map_err(user_error)?;
    let t0 = std::time::Instant::now();
    let gpu = fastbrdf_gpu::Gpu::new()?;
    let brdf = GpuBrdf::new(&gpu.device, &gpu.queue, shader.clone(), &given).map_err(user_error)?;
    let mut whole = spec.clone();
    (whole.kd, whole.ks) = (0.0, 1.0);
    let specular = Specular::rgb(&a.model, Arc::new(UserRgb::new(Arc::new(brdf))));
    let scene = setup::scene(&whole, loaded, Arc::new(specular));
    let ((film, label), later) = gpu_repeated(a.repeat, &gpu, t0, |progress| {
        Ok(fastbrdf_gpu::render::render_user(
            &gpu.device,
            &gpu.queue,
            &scene,
            opts,
            &shader,
            &values,
            progress,
        )?)
    })?;
    film.check_finite()
        .map_err(|e| CliError::input(format!("--model {}: {e}", a.model)))?;
    Ok(((film, label), later))
}

pub fn run_render(a: &RenderArgs) -> Result<(), CliError> {
    let (mut spec, opts) = a.scene.spec()?;
    if let Some(file) = &a.scene_file.scene {
        return render_gltf(a, file, &spec, &opts);
    }
    material_and_metal(&mut spec, &a.scene, &a.model_args, &a.model)?;
    check_out(&a.out, &["png", "exr"])?;
    let loaded = setup::load(&spec)?;
    let t = std::time::Instant::now();
    if a.gpu && crate::model_args::is_user(&a.model) {
        return finish_gpu(
            a,
            &spec,
            &opts,
            render_user_gpu(a, &spec, &loaded, &opts)?,
            t,
        );
    }
    if let Some(user) = a.model_args.user(&a.model)? {
        // A user's model: the whole BRDF (weights 0, 1), shaded by the CPU renderer with its
        // values from the GPU evaluator, one dispatch per batch of hits.
        let user = Arc::new(UserRgb::new(user));
        let (film, later) = repeated(a.repeat, || {
            render_rgb(&spec, &loaded, &opts, &a.model, user.clone())
        })?;
        let times = Times {
            set_up: None,
            later,
        };
        return finish(a, &spec, &opts, film, t, String::new(), times);
    }
    let model = a.model_args.spec(&a.model, Use::Shaded)?;
    if a.gpu {
        let rendered = render_model_gpu(&spec, &loaded, &opts, (&a.model, &model), a.repeat)?;
        return finish_gpu(a, &spec, &opts, rendered, t);
    }
    // The model's set-up (its spec and kernels) is timed apart from the render, as
    // `tools/equal_error.py` times Mitsuba's `mi.render` apart from `load_dict`.
    let specular = specular(&a.model, &model)?;
    let set_up = Some(t.elapsed().as_secs_f64());
    let (film, later) = repeated(a.repeat, || {
        render_specular(&spec, &loaded, &opts, specular.clone())
    })?;
    finish(
        a,
        &spec,
        &opts,
        film,
        t,
        String::new(),
        Times { set_up, later },
    )
}

/// `render --scene FILE`: the glTF scene with its materials, `--param` given to every one.
fn render_gltf(
    a: &RenderArgs,
    file: &std::path::Path,
    spec: &SceneSpec,
    opts: &Options,
) -> Result<(), CliError> {
    check_out(&a.out, &["png", "exr"])?;
    let overrides = a.model_args.param.pairs()?;
    let t = std::time::Instant::now();
    let loaded = gltf_scene::load(file, spec)?;
    let (film, gpu, later) = if a.gpu {
        let ((film, label), later) = render_gltf_gpu(&loaded, spec, opts, &overrides, a.repeat)?;
        (film, format!(", GPU: {label}"), later)
    } else {
        let ((film, _), later) = repeated(a.repeat, || {
            gltf_scene::render_scene(&loaded, spec, opts, &overrides, "render", false)
        })?;
        (film, String::new(), later)
    };
    let s = &loaded.scene;
    let on = format!(
        ", scene {}: {} triangles, {} materials as {}, {} lights{}{gpu}",
        s.file,
        s.triangles(),
        s.materials.len(),
        fastbrdf_render::gltf::MODEL_ID,
        if !spec.lights.is_empty() {
            spec.lights.len()
        } else if spec.env.is_some() {
            0
        } else {
            s.lights.len()
        },
        if s.camera.is_some() {
            ", its camera"
        } else {
            ", a framing view"
        }
    );
    let times = Times {
        set_up: None,
        later,
    };
    finish(a, spec, opts, film, t, on, times)
}

/// Renders a glTF scene on the GPU (`fastbrdf_gpu::render`: coloured materials, base colour
/// textures, shadows, the environment light); returns the film and the adapter's label. What
/// the GPU renderer does not draw is refused (exit 2) before an adapter is looked for.
fn render_gltf_gpu(
    l: &gltf_scene::Loaded,
    spec: &SceneSpec,
    opts: &Options,
    overrides: &[(String, String)],
    repeat: u32,
) -> Result<(RenderedGpu, Vec<f64>), CliError> {
    let specs = l.scene.specs(overrides)?;
    let scene = l.scene.scene(spec, l.env.clone(), &specs)?;
    fastbrdf_gpu::render::check(&scene)?;
    let ((film, label), later) = render_scene_gpu(&scene, opts, repeat)?;
    film.check_finite()
        .map_err(|e| CliError::input(format!("--scene {}: {e}", l.scene.file)))?;
    Ok(((film, label), later))
}

/// [`finish`] for a GPU render: its film and the adapter's label.
fn finish_gpu(
    a: &RenderArgs,
    spec: &SceneSpec,
    opts: &Options,
    ((film, label), later): (RenderedGpu, Vec<f64>),
    t: std::time::Instant,
) -> Result<(), CliError> {
    let on = format!(", GPU: {label}");
    let times = Times {
        set_up: None,
        later,
    };
    finish(a, spec, opts, film, t, on, times)
}

/// Writes the picture and reports what was rendered, how and how long it took: from `t`, of
/// which `times.set_up` seconds (where timed apart) went to the model's set-up before the
/// render and `times.later` to the renders after the first (`--repeat`), reported apart.
fn finish(
    a: &RenderArgs,
    spec: &SceneSpec,
    opts: &Options,
    film: Film,
    t: std::time::Instant,
    on: String,
    times: Times,
) -> Result<(), CliError> {
    let Times { set_up, later } = times;
    // The GPU renders the N x N grid in every pixel (no adaptive antialiasing).
    let gpu_opts;
    let opts = if a.gpu {
        gpu_opts = Options {
            aa: fastbrdf_render::render::Antialias::Grid,
            ..*opts
        };
        &gpu_opts
    } else {
        opts
    };
    let until_rendered = t.elapsed().as_secs_f64();
    let rendered = until_rendered - set_up.unwrap_or(0.0) - later.iter().sum::<f64>();
    // "render X s (then Y s, Z s: --repeat 3)": the later renders, a warm process's.
    let then = if later.is_empty() {
        String::new()
    } else {
        let each: Vec<String> = later.iter().map(|s| format!("{s:.4} s")).collect();
        format!(" (then {}: --repeat {})", each.join(", "), later.len() + 1)
    };
    film.save(&a.out, a.scene.exposure)?;
    let total = t.elapsed().as_secs_f64();
    let set_up = set_up.map_or(String::new(), |s| format!("model set-up {s:.4} s, "));
    let env = match &spec.env {
        Some(e) => format!(
            ", environment {e} x {} samples, {} sampler{}",
            spec.env_samples,
            opts.sampler.name(),
            match spec.env_sun {
                fastbrdf_render::setup::SunDraw::Apart => "",
                fastbrdf_render::setup::SunDraw::WithMap => ", every direction from the whole map",
            }
        ),
        None => String::new(),
    };
    eprintln!(
        "wrote {} ({}x{}, {} samples/pixel ({}x{} {}{env}), {:.4} s: {set_up}render {:.4} s{then}, encode and write {:.4} s{on})",
        a.out.display(),
        opts.width,
        opts.height,
        opts.spp * opts.spp,
        opts.spp,
        opts.spp,
        opts.aa.name(),
        total,
        rendered,
        total - until_rendered
    );
    Ok(())
}
