//! The scene's options from Python (the CLI's `SceneArgs`, named as Python's arguments) and
//! what a material or a metal changes in it.

use crate::MAX_ITEMS;
use crate::args::{seq, shown, u32_arg, weight_arg};
use crate::guard::value_error;
use fastbrdf::colour::Metal;
use fastbrdf_analysis::materials::Material;
use fastbrdf_analysis::model_spec;
use fastbrdf_render::bump::Bump;
use fastbrdf_render::render::{Options, Shading};
use fastbrdf_render::scene::Light;
use fastbrdf_render::setup::SceneSpec;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Largest bump scale (features per unit), as the CLI's `--bump`.
const MAX_BUMP_SCALE: f64 = 1e4;

/// The keys of the scene dict.
const KEYS: [&str; 16] = [
    "width",
    "height",
    "spp",
    "weights",
    "albedo",
    "lights",
    "floor",
    "shadows",
    "env",
    "env_samples",
    "mesh",
    "texture",
    "bump",
    "sampler",
    "aa",
    "env_sun",
];

/// A scene and its render options, with whether the weights and albedo were given (a material
/// or a metal sets them otherwise).
pub(crate) struct Scene {
    pub(crate) spec: SceneSpec,
    pub(crate) opts: Options,
    weights_given: bool,
    albedo_given: bool,
}

impl Scene {
    /// This scene with the weights KD, KS (a measured reference renders with 0, 1: it is the
    /// whole BRDF).
    pub(crate) fn with_weights(&self, kd: f32, ks: f32) -> Scene {
        let mut spec = self.spec.clone();
        (spec.kd, spec.ks) = (kd, ks);
        Scene {
            spec,
            opts: self.opts,
            weights_given: true,
            albedo_given: self.albedo_given,
        }
    }
}

fn get<'py>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    d.get_item(key)?
        .ok_or_else(|| PyTypeError::new_err(format!("scene: no '{key}'")))
}

/// `n` numbers of argument `name`, each from 0 to 1e3.
fn weights(obj: &Bound<'_, PyAny>, name: &str, n: usize) -> PyResult<Vec<f32>> {
    let v = seq(obj, name, n + 1, |x| weight_arg(x, name))?;
    if v.len() != n {
        return Err(value_error(format!(
            "{name} {}: expected {n} numbers from 0 to {}",
            shown(obj),
            crate::MAX_WEIGHT
        )));
    }
    Ok(v)
}

fn path(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<PathBuf>> {
    if obj.is_none() {
        return Ok(None);
    }
    obj.extract::<PathBuf>().map(Some).map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected a path or a string, got {}",
            obj.get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string())
        ))
    })
}

fn flag(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<bool> {
    obj.extract::<bool>()
        .map_err(|e| crate::args::named(obj.py(), e, name))
}

/// The scene of a dict with the keys [`KEYS`] (the Python layer makes it): `width`, `height`,
/// `spp`, `env_samples` integers; `weights` (KD, KS) and `albedo` (R, G, B) sequences or
/// None (the defaults); `lights` a sequence of the CLI's `--light` specs; `floor`, `shadows`
/// booleans; `env` None or text; `mesh`, `texture` None or a path (`face`, `skin`: the
/// built-ins); `bump` None or (SCALE, DEPTH); `sampler` (`sobol`, `independent`) and `aa`
/// (`adaptive`, `grid`) and `env_sun` (`apart`, `with-map`) absent or None for the defaults. Checked as the CLI checks its
/// options.
pub(crate) fn scene_arg(d: &Bound<'_, PyDict>) -> PyResult<Scene> {
    for k in d.keys() {
        let k: String = k.extract()?;
        if !KEYS.contains(&k.as_str()) {
            return Err(PyTypeError::new_err(format!("scene: unknown key '{k}'")));
        }
    }
    let (width, height) = (
        u32_arg(&get(d, "width")?, "width")?,
        u32_arg(&get(d, "height")?, "height")?,
    );
    let spp = u32_arg(&get(d, "spp")?, "spp")?;
    let env_samples = u32_arg(&get(d, "env_samples")?, "env_samples")?;
    let mut spec = SceneSpec::new();
    let w = get(d, "weights")?;
    let weights_given = !w.is_none();
    if weights_given {
        let v = weights(&w, "weights", 2)?;
        (spec.kd, spec.ks) = (v[0], v[1]);
    }
    let a = get(d, "albedo")?;
    let albedo_given = !a.is_none();
    if albedo_given {
        let v = weights(&a, "albedo", 3)?;
        spec.albedo = glam::Vec3::new(v[0], v[1], v[2]);
    }
    spec.floor = flag(&get(d, "floor")?, "floor")?;
    spec.shadows = flag(&get(d, "shadows")?, "shadows")?;
    let env = get(d, "env")?;
    spec.env = if env.is_none() {
        None
    } else {
        Some(
            env.extract::<String>()
                .map_err(|e| crate::args::named(env.py(), e, "env"))?,
        )
    };
    if !(1..=fastbrdf_render::env::MAX_ENV_SAMPLES).contains(&env_samples) {
        return Err(value_error(format!(
            "env_samples {env_samples}: must be 1 to {}",
            fastbrdf_render::env::MAX_ENV_SAMPLES
        )));
    }
    spec.env_samples = env_samples;
    spec.mesh = path(&get(d, "mesh")?, "mesh")?;
    spec.texture = path(&get(d, "texture")?, "texture")?;
    spec.lights = seq(&get(d, "lights")?, "lights", MAX_ITEMS, |l| {
        l.extract::<String>()
    })?
    .iter()
    .map(|l| Light::parse(l))
    .collect::<Result<_, _>>()
    .map_err(value_error)?;
    let b = get(d, "bump")?;
    if !b.is_none() {
        let v = seq(&b, "bump", 3, |x| crate::args::float_arg(x, "bump"))?;
        let max_depth = crate::MAX_WEIGHT;
        if v.len() != 2
            || !(v[0] > 0.0 && v[0] <= MAX_BUMP_SCALE)
            || !(v[1] >= 0.0 && v[1] <= max_depth)
        {
            return Err(value_error(format!(
                "bump {}: expected (SCALE, DEPTH): the scale positive (at most {MAX_BUMP_SCALE}), the depth from 0 to {max_depth}",
                shown(&b)
            )));
        }
        spec.bump = Some(Bump {
            scale: v[0] as f32,
            depth: v[1] as f32,
        });
    }
    let choice = |key: &str, options: &[&str]| -> PyResult<Option<String>> {
        let v = match d.get_item(key)? {
            Some(v) if !v.is_none() => v,
            _ => return Ok(None),
        };
        let t: String = v
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("{key}: expected a string")))?;
        if !options.contains(&t.as_str()) {
            return Err(value_error(format!(
                "{key} '{}': expected {}",
                fastbrdf_io::shorten(&t, 64),
                options.join(" or ")
            )));
        }
        Ok(Some(t))
    };
    let sampler = match choice("sampler", &["sobol", "independent"])?.as_deref() {
        Some("independent") => fastbrdf_render::render::Sampler::Independent,
        _ => fastbrdf_render::render::Sampler::Sobol,
    };
    let aa = match choice("aa", &["adaptive", "grid"])?.as_deref() {
        Some("grid") => fastbrdf_render::render::Antialias::Grid,
        _ => fastbrdf_render::render::Antialias::Adaptive,
    };
    spec.env_sun = match choice("env_sun", &["apart", "with-map"])?.as_deref() {
        Some("with-map") => fastbrdf_render::setup::SunDraw::WithMap,
        _ => fastbrdf_render::setup::SunDraw::Apart,
    };
    fastbrdf_render::film::check_size(width, height).map_err(value_error)?;
    if !(1..=16).contains(&spp) {
        return Err(value_error(format!(
            "spp {spp}: must be 1 to 16 (N x N samples per pixel)"
        )));
    }
    Ok(Scene {
        spec,
        opts: Options {
            width,
            height,
            spp,
            shading: Shading::Batch,
            sampler,
            aa,
        },
        weights_given,
        albedo_given,
    })
}

/// The material and the metal named (the CLI's `--material`, `--metal`).
pub(crate) struct Colour {
    pub(crate) material: Option<&'static Material>,
    pub(crate) metal: Option<&'static Metal>,
}

impl Colour {
    /// Looks the names up: an unknown one is a `ValueError` naming the argument.
    pub(crate) fn new(material: Option<&str>, metal: Option<&str>) -> PyResult<Self> {
        Ok(Self {
            material: material
                .map(|n| {
                    fastbrdf_analysis::materials::find(n)
                        .map_err(|e| value_error(format!("material: {e}")))
                })
                .transpose()?,
            metal: metal
                .map(|n| fastbrdf::colour::metal(n).map_err(|e| value_error(format!("metal: {e}"))))
                .transpose()?,
        })
    }

    /// What they change in the scene of model `id` (the library's `scene_colour`, as the
    /// CLI's): the fit's diffuse colour and weight 1, a metal's weights 0, 1, unless given.
    pub(crate) fn apply(&self, sc: &mut Scene, id: &str) {
        model_spec::scene_colour(
            &mut sc.spec,
            id,
            self.material,
            self.metal.is_some(),
            sc.albedo_given,
            sc.weights_given,
        );
    }
}
