//! Pictures shared by `render`, `compare`, `demo`, `fit-measured` and `measured render`: one
//! model (a validated spec) or an RGB BRDF rendered with a progress bar, and a comparison grid
//! with difference heat maps and scores.

use super::progress::bar;
use crate::CliError;
use fastbrdf::ModelSpec;
use fastbrdf_render::compare::{self, Cell};
use fastbrdf_render::film::Film;
use fastbrdf_render::render::{Options, render};
use fastbrdf_render::scene::{RgbBrdf, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use std::sync::Arc;

/// Renders one model with a progress bar: `spec` is what shading evaluates (a spec built
/// for [`Use::Shaded`](crate::model_args::Use)), `label` the model as the user named it (for
/// messages).
pub fn render_model(
    spec: &SceneSpec,
    loaded: &setup::Loaded,
    opts: &Options,
    label: &str,
    model: &ModelSpec,
) -> Result<Film, CliError> {
    render_specular(spec, loaded, opts, specular(label, model)?)
}

/// The specular term that shading with `model` evaluates (its kernels built), labelled
/// `label`: what [`render_model`] renders, built apart where the set-up is timed apart.
pub fn specular(label: &str, model: &ModelSpec) -> Result<Arc<Specular>, CliError> {
    let mut specular = Specular::new(model)?;
    specular.id = label.into();
    Ok(Arc::new(specular))
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
    let scene = setup::scene(spec, loaded, Arc::clone(&specular));
    let pb = bar(1, "render");
    let film = render(&scene, opts, &|d, t| {
        pb.set_length(t as u64);
        pb.set_position(d as u64);
    })?;
    pb.finish_and_clear();
    if let Some(e) = specular.rgb.as_ref().and_then(|b| b.failure()) {
        // A user's model evaluated on the GPU failed mid-render (its device was lost).
        return Err(CliError {
            code: crate::EXIT_CHECK_FAILED,
            message: format!("--model {id}: {e}"),
        });
    }
    film.check_finite()
        .map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
    Ok(film)
}

/// One model of a comparison: its label and what is rendered.
pub struct Entry {
    pub label: String,
    /// The model as the user named it (for messages).
    pub id: String,
    what: What,
}

enum What {
    /// A registry model: the spec shading evaluates.
    Model(ModelSpec),
    /// An RGB BRDF (measured data, a fitted model), rendered with weights 0, 1 (see
    /// [`render_rgb`]).
    Rgb(Arc<dyn RgbBrdf>),
}

impl Entry {
    /// Model `id` as shaded by `spec`, labelled `id` and the values given to it (those that
    /// shading adds, such as a distribution's `d`, left out).
    pub fn new(id: &str, spec: ModelSpec) -> Self {
        Self {
            label: label(id, &spec),
            id: id.into(),
            what: What::Model(spec),
        }
    }

    /// An RGB BRDF labelled `label`.
    pub fn rgb(label: &str, brdf: Arc<dyn RgbBrdf>) -> Self {
        Self {
            label: label.into(),
            id: label.into(),
            what: What::Rgb(brdf),
        }
    }

    /// Renders the entry: the registry model, or the RGB BRDF with weights 0, 1.
    pub fn render(
        &self,
        spec: &SceneSpec,
        loaded: &setup::Loaded,
        opts: &Options,
    ) -> Result<Film, CliError> {
        match &self.what {
            What::Rgb(b) => render_rgb(spec, loaded, opts, &self.label, b.clone()),
            What::Model(m) => render_model(spec, loaded, opts, &self.id, m),
        }
    }
}

/// `id k=v ...`: model `id` and the values `spec` was given, less those shading `id` adds
/// (the library's, which Python's `compare` labels with too).
pub use fastbrdf_analysis::model_spec::label;

/// The scores of one model: on the clipped 8-bit sRGB pictures and on the linear film.
pub struct Scores {
    pub srgb: compare::Metrics,
    pub linear: compare::LinearMetrics,
}

impl Scores {
    /// The JSON object: numbers only, PSNR null when infinite; field names say the space.
    pub fn json(&self) -> serde_json::Value {
        fastbrdf_analysis::render_json::scores(&self.srgb, &self.linear)
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
