//! The scene options of `render`, `compare`, `fit-measured`, `measured render` (and what
//! `--material` and `--metal` change in the scene), and the check of an output's extension.

use crate::CliError;
use crate::model_args::ModelArgs;
use fastbrdf_render::Result as RResult;
use fastbrdf_render::bump::Bump;
use fastbrdf_render::film::parse_size;
use fastbrdf_render::render::{Options, Shading};
use fastbrdf_render::scene::Light;
use fastbrdf_render::setup::{self, SceneSpec};
use glam::Vec3;
use std::path::{Path, PathBuf};

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
    /// default key light. `render --gpu` renders it too.
    #[arg(long, value_name = "FILE|sky|white")]
    pub env: Option<String>,
    /// Environment samples per primary ray (each one map-sampled and one cosine-sampled
    /// direction, combined by multiple importance sampling), taken as progressive passes
    /// (1..4096); times N x N of --spp per pixel.
    #[arg(long, default_value_t = 16)]
    pub env_samples: u32,
    /// Where the environment light's random numbers come from: sobol (Owen-scrambled Sobol
    /// points, each primary sample's passes stratified) or independent (a hash per sample and
    /// pass: the renderer before 0.2; same expected picture, more noise).
    #[arg(long, value_enum, default_value_t = SamplerArg::Sobol)]
    pub sampler: SamplerArg,
    /// How the environment's light directions are drawn: apart (a sun, texels brighter than 64
    /// times the map's mean holding at least 5% of its light in at most 1/256 of its texels,
    /// and the rest of the map as two strategies, one direction of each per pass; the CPU and
    /// the GPU renderer) or with-map (every direction from the whole map: the renderers before
    /// the sun strategy; the same expected picture, more noise under a sun).
    #[arg(long, value_enum, default_value_t = SunArg::Apart)]
    pub env_sun: SunArg,
    /// Antialiasing: adaptive (one sample at each pixel's centre; N x N samples of --spp on a
    /// rotated grid only where the neighbourhood shows an edge: a normal or depth step, an
    /// albedo or light contrast; 2N x 2N at an object's outline without --env; with --env a
    /// centre-only pixel takes N x N times the passes) or grid (the N x N axis-aligned grid in
    /// every pixel, as the GPU renderer)
    #[arg(long, value_enum, default_value_t = AaArg::Adaptive)]
    pub aa: AaArg,
}

/// `--scene FILE`: a glTF 2.0 scene (`render` and `compare`).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct SceneFileArg {
    /// A glTF 2.0 scene (.gltf with its buffers beside it or as data URIs, or .glb; at most
    /// 256 MiB, buffers 1 GiB) instead of the sphere or --mesh: its meshes under their node
    /// transforms, its first camera (else a view framing the scene), its punctual lights
    /// unless --light or --env is given, and every material as the gltf-pbr model (base
    /// colour, metallic, roughness, KHR_materials_ior, _specular, _clearcoat, _sheen,
    /// _anisotropy, the base colour texture; --param values go to every material). What is
    /// not rendered (other textures, emission, animations...) is named in a warning on
    /// stderr. `render --gpu` renders it too.
    #[arg(
        long = "scene",
        value_name = "FILE",
        conflicts_with_all = ["mesh", "texture", "floor", "bump", "weights", "albedo", "material", "metal"]
    )]
    pub scene: Option<PathBuf>,
}

/// `--aa`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AaArg {
    Adaptive,
    Grid,
}

impl From<AaArg> for fastbrdf_render::render::Antialias {
    fn from(a: AaArg) -> Self {
        match a {
            AaArg::Adaptive => Self::Adaptive,
            AaArg::Grid => Self::Grid,
        }
    }
}

/// `--sampler`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerArg {
    Sobol,
    Independent,
}

impl From<SamplerArg> for fastbrdf_render::render::Sampler {
    fn from(s: SamplerArg) -> Self {
        match s {
            SamplerArg::Sobol => Self::Sobol,
            SamplerArg::Independent => Self::Independent,
        }
    }
}

/// `--env-sun`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SunArg {
    Apart,
    WithMap,
}

impl From<SunArg> for fastbrdf_render::setup::SunDraw {
    fn from(s: SunArg) -> Self {
        match s {
            SunArg::Apart => Self::Apart,
            SunArg::WithMap => Self::WithMap,
        }
    }
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
        spec.env_sun = self.env_sun.into();
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
                sampler: self.sampler.into(),
                aa: self.aa.into(),
            },
        ))
    }
}

/// The output `path` must end in one of `exts` (any case).
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

/// What `--material` and `--metal` change in the scene of model `id` (the reference of a
/// comparison): with a material, the diffuse colour from the fit that goes with the model (its
/// kd: the fits' Lambert term is kd / pi, as the renderer's) unless `--albedo` is given, and
/// the diffuse weight 1 unless `--weights` is given (the specular weight is left alone: it is
/// one number here, the fit's ks is RGB, and lobes shade unnormalised); with a metal, the
/// weights KD,KS 0,1 unless `--weights` is given (a metal has no diffuse term; the specular
/// colour is the metal's).
pub fn material_and_metal(
    spec: &mut SceneSpec,
    scene: &SceneArgs,
    model: &ModelArgs,
    id: &str,
) -> Result<(), CliError> {
    fastbrdf_analysis::model_spec::scene_colour(
        spec,
        id,
        model.material.get()?,
        model.metal.metal.is_some(),
        scene.albedo.is_some(),
        scene.weights.is_some(),
    );
    Ok(())
}
