//! The specular term of a material: a model spec as batch kernels and scalar models per
//! colour channel ([`Specular`]), or an RGB BRDF evaluated by lookups ([`RgbBrdf`]), with a
//! base colour texture's [`Tint`]. A leaf below `scene` and `maps` (re-exported by `scene`).

use crate::error::{RenderError, Result};
use crate::texture::Texture;
use fastbrdf::batch::Kernel;
use fastbrdf::{Model, ModelSpec};
use std::sync::Arc;

/// One channel of a specular model: a BRDF in batch and scalar form.
pub struct Channel {
    /// The channel's grey spec (`ModelSpec::channel_specs`).
    pub spec: ModelSpec,
    pub kernel: Kernel,
    pub scalar: Box<dyn fastbrdf::Brdf<f32>>,
}

impl Channel {
    fn new(spec: ModelSpec) -> Result<Self> {
        let kernel = Kernel::new(&spec)?;
        let Model::Brdf(scalar) = spec.model::<f32>()? else {
            unreachable!("shaded specs are BRDFs")
        };
        Ok(Self {
            spec,
            kernel,
            scalar,
        })
    }
}

/// An RGB BRDF evaluated one direction pair at a time: a measured material (MERL's lookup,
/// `fastbrdf::measured::MeasuredBrdf`) or a fitted model with per-channel albedos. Directions
/// in the local frame (normal +z), no cosine factor; values are linear R, G, B.
pub trait RgbBrdf: Send + Sync {
    fn eval_rgb(&self, wi: [f32; 3], wo: [f32; 3]) -> [f32; 3];
    /// Row `j` of `cols` (`wi` x, y, z, `wo` x, y, z) into `out[j]` (`out` is cleared first):
    /// the renderer's one call per batch, for evaluators that work in batches (a user's shader
    /// on the GPU, [`crate::user::UserRgb`]). By default [`Self::eval_rgb`] per row.
    fn eval_rgb_batch(&self, cols: [&[f32]; 6], out: &mut Vec<[f32; 3]>) {
        out.clear();
        out.extend((0..cols[0].len()).map(|j| {
            self.eval_rgb(
                [cols[0][j], cols[1][j], cols[2][j]],
                [cols[3][j], cols[4][j], cols[5][j]],
            )
        }));
    }
    /// The first evaluation failure (a GPU evaluator's lost device), which the batch methods
    /// cannot return: a caller asks after rendering and fails with it. `None` by default.
    fn failure(&self) -> Option<String> {
        None
    }
}

/// MERL's nearest-bin lookup: the bin is found in f64 (`eval_rgb_f32`), the value rounded to
/// f32.
impl RgbBrdf for fastbrdf::measured::MeasuredBrdf {
    fn eval_rgb(&self, wi: [f32; 3], wo: [f32; 3]) -> [f32; 3] {
        self.eval_rgb_f32(wi, wo)
    }
}

/// The specular model of a material: a model spec turned into a BRDF, in batch and scalar
/// form; grey (one channel, weighting R, G and B alike) or coloured (three: R, G, B), when a
/// parameter is given as `R,G,B` (`ModelSpec::is_coloured`). Or, from [`Specular::rgb`], an
/// RGB BRDF evaluated by scalar lookups (measured data, fitted models): then `channels` is
/// empty, `brdf` is `None` and `rgb` holds it.
pub struct Specular {
    /// The model's id (as given, before shading), or an RGB BRDF's label.
    pub id: String,
    /// The BRDF actually evaluated ([`shading_brdf`] of the spec given); `None` for an RGB
    /// BRDF.
    pub brdf: Option<ModelSpec>,
    /// One channel (grey) or three (R, G, B); none for an RGB BRDF.
    pub channels: Vec<Channel>,
    /// An RGB BRDF evaluated by scalar lookups instead of the channels' kernels.
    pub rgb: Option<Arc<dyn RgbBrdf>>,
    /// A texture that scales one parameter in which the BRDF is affine (a glTF base colour
    /// texture): the value at a hit is `zero + t * (this - zero)` per channel, `t` the texel.
    /// CPU renderer only.
    pub tint: Option<Tint>,
}

/// A [`Specular`]'s texture: `f(t) = f_zero + t (f - f_zero)` per channel, exact for a BRDF
/// affine in the textured parameter (glTF's base colour: the texel times the factor).
pub struct Tint {
    /// Linear texels, sampled at the hit's texture coordinates.
    pub texture: Arc<Texture>,
    /// The model with the textured parameter at 0.
    pub zero: Arc<Specular>,
}

impl Specular {
    /// Lobes become the lobe of `n . h` (`blinn-phong`, `norm = none`: the seeds' pictures),
    /// distributions the `d` of `cook-torrance` (alpha passed on), BRDFs stay as they are
    /// ([`shading_brdf`]).
    pub fn new(spec: &ModelSpec) -> Result<Self> {
        let brdf = shading_brdf(spec)?;
        let channels = brdf
            .channel_specs()
            .into_iter()
            .map(Channel::new)
            .collect::<Result<_>>()?;
        Ok(Self {
            id: spec.id().into(),
            brdf: Some(brdf),
            channels,
            rgb: None,
            tint: None,
        })
    }

    /// An RGB BRDF (a measured material, a fitted model) named `label`, shaded by scalar
    /// lookups in f32 (`RgbBrdf::eval_rgb`); the whole BRDF, diffuse part included, so a scene
    /// usually gives it the weights 0, 1. With the environment light only the map's
    /// directions are used for it (no BRDF sampling); the GPU renderer refuses it unless given
    /// the user's shader (`fastbrdf_gpu::render::render_user`).
    pub fn rgb(label: &str, brdf: Arc<dyn RgbBrdf>) -> Self {
        Self {
            id: label.into(),
            brdf: None,
            channels: Vec::new(),
            rgb: Some(brdf),
            tint: None,
        }
    }

    /// Whether the model is coloured (three channels, or an RGB BRDF).
    pub fn is_coloured(&self) -> bool {
        self.channels.len() == 3 || self.rgb.is_some()
    }
}

/// The BRDF that shading with `spec` evaluates: the core crate's policy
/// (`ModelSpec::shaded`), its refusal as this crate's error.
pub fn shading_brdf(spec: &ModelSpec) -> Result<ModelSpec> {
    match spec.shaded() {
        Ok(brdf) => Ok(brdf),
        Err(fastbrdf::Error::WrongKind { found, .. }) => Err(RenderError::Invalid(format!(
            "'{}' is a {found}, not something to shade with: give a lobe, a distribution or a BRDF",
            spec.id()
        ))),
        Err(e) => Err(e.into()),
    }
}
