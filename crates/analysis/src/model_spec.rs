//! The one place a model's parameter text, a MERL material and a named metal become a
//! validated [`ModelSpec`], for a use as it is or shaded (render, compare): the CLI's
//! `--param`/`--material`/`--metal` and Python's `Model(..., material=, metal=)` and
//! `render(...)` both call [`spec`], so that both build the same model from the same words.
//! Errors are [`SpecError`], whose messages name no flag: the caller adds its own prefix
//! (`--material NAME: ` on the command line, `material 'NAME': ` in Python).

use crate::materials::{self, Material};
use fastbrdf::colour::Metal;
use fastbrdf::kind::Shading;
use fastbrdf::{Kind, ModelSpec};
use fastbrdf_io::shorten;
use fastbrdf_render::setup::SceneSpec;
use std::fmt;

/// The most characters of a given value quoted in a message.
const QUOTE: usize = 40;

/// What the model is used for: that decides whether it is shaded before a metal colours it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// As it is (eval, sample, albedo, shader export, analysis).
    AsIs,
    /// Shaded (render, compare, demo, the explorer, BRDF Explorer export): a lobe as
    /// blinn-phong, a distribution as cook-torrance ([`ModelSpec::shaded`]); values the model
    /// itself does not take go to the BRDF it is shaded as.
    Shaded,
}

/// Why a spec could not be built.
#[derive(Debug)]
pub enum SpecError {
    /// The registry's refusal (an unknown model or parameter, a bad value, a metal's values).
    Model(fastbrdf::Error),
    /// The renderer's refusal of a term that cannot be shaded.
    Render(fastbrdf_render::RenderError),
    /// The material supplies none of the model's parameters (`material` is its name).
    NoFittedParams { material: String, model: String },
    /// A figure of the material outside the model's domain (the message names the material).
    MaterialValue(String),
    /// The model has no conductor Fresnel term to colour with metal `metal`.
    NoConductor { metal: String, model: String },
    /// A value no model of a comparison takes ([`specs`]).
    Unused { param: String },
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SpecError::Model(e) => write!(f, "{e}"),
            SpecError::Render(e) => write!(f, "{e}"),
            SpecError::NoFittedParams { model, .. } => write!(
                f,
                "model '{model}' takes none of the fitted parameters (n, alpha, f0)"
            ),
            SpecError::MaterialValue(m) => f.write_str(m),
            SpecError::NoConductor { model, .. } => write!(
                f,
                "model '{model}' has no conductor Fresnel term (parameters eta, k): \
                 metals colour cook-torrance, the distributions (shaded as cook-torrance) and \
                 fresnel-conductor"
            ),
            SpecError::Unused { .. } => f.write_str("none of the models takes it"),
        }
    }
}

impl std::error::Error for SpecError {}

impl From<fastbrdf::Error> for SpecError {
    fn from(e: fastbrdf::Error) -> Self {
        SpecError::Model(e)
    }
}

impl From<fastbrdf_render::RenderError> for SpecError {
    fn from(e: fastbrdf_render::RenderError) -> Self {
        SpecError::Render(e)
    }
}

/// `given` validated against model `id` (with [`Use::Shaded`], the values the model does not
/// take against the BRDF it is shaded as), the material's figures ([`with_material`]) and the
/// metal's ([`with_metal`], after shading) added where no value was given. Every error names
/// the model, the parameter and the value.
pub fn spec(
    id: &str,
    given: &[(String, String)],
    material: Option<&Material>,
    metal: Option<&Metal>,
    use_: Use,
) -> Result<ModelSpec, SpecError> {
    let e = fastbrdf::registry::find(id)?;
    let via = use_ == Use::Shaded && matches!(e.info.kind.shading(), Shading::Via { .. });
    // The model's own values first, so that a message names the model chosen (not the BRDF a
    // lobe or a distribution is shaded as).
    let (own, rest): (Vec<_>, Vec<_>) = given
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .partition(|(k, _)| !via || e.info.params.iter().any(|p| p.name == *k));
    let mut spec = ModelSpec::parse(id, &own)?;
    if let Some(m) = material {
        spec = with_material(m, &spec)?;
    }
    if use_ == Use::Shaded {
        // The renderer's policy and its message for a term that cannot be shaded.
        spec = fastbrdf_render::scene::shading_brdf(&spec)?;
        // A value neither the model nor the BRDF it is shaded as takes: name the model chosen.
        if let Some((k, _)) = rest.iter().find(|(k, _)| !spec.takes(k)) {
            return Err(fastbrdf::Error::UnknownParam {
                model: e.info.id.into(),
                param: shorten(k, QUOTE),
            }
            .into());
        }
        if !rest.is_empty() {
            let mut all = spec.pairs();
            all.extend(rest.iter().map(|(k, v)| (k.to_string(), v.to_string())));
            let all: Vec<(&str, &str)> =
                all.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
            spec = ModelSpec::parse(spec.id(), &all)?;
        }
    }
    if let Some(m) = metal {
        spec = with_metal(m, &spec, id)?;
    }
    Ok(spec)
}

/// `spec` with the figures material `m` supplies to its model where no value was given. A
/// model that takes none of them, or a figure outside the model's documented domain, is an
/// error.
pub fn with_material(m: &Material, spec: &ModelSpec) -> Result<ModelSpec, SpecError> {
    if materials::supplied(m, spec).is_empty() {
        return Err(SpecError::NoFittedParams {
            material: m.name.to_string(),
            model: spec.id().to_string(),
        });
    }
    materials::apply(m, spec).map_err(SpecError::MaterialValue)
}

/// `spec` coloured by metal `m` (`f = conductor`, `eta`, `k` per channel, given values
/// winning); a model without the conductor term's `eta` and `k` is an error naming `asked`,
/// the model the user gave.
pub fn with_metal(m: &Metal, spec: &ModelSpec, asked: &str) -> Result<ModelSpec, SpecError> {
    if !(spec.takes("eta") && spec.takes("k")) {
        return Err(SpecError::NoConductor {
            metal: m.id.to_string(),
            model: shorten(asked, QUOTE),
        });
    }
    Ok(spec.with_metal(m)?)
}

/// The parameters of the shading BRDF a distribution may also be given in a comparison (where
/// each model takes the values it can use; see [`specs`]).
const SHADED_DISTRIBUTION: [&str; 6] = ["g", "f", "f0", "eta", "k", "denominator"];

/// Whether model `id` takes parameter `name` in a comparison: its own parameters, and for a
/// distribution the shading Cook-Torrance's `g`, `f`, `f0`, `eta`, `k` and `denominator`.
pub fn takes(id: &str, name: &str) -> Result<bool, fastbrdf::Error> {
    let e = fastbrdf::registry::find(id)?;
    Ok(e.info.params.iter().any(|p| p.name == name)
        || (e.info.kind == Kind::Distribution && SHADED_DISTRIBUTION.contains(&name)))
}

/// The pairs of `all` that model `id` takes (see [`takes`]).
pub fn own_pairs(
    id: &str,
    all: &[(String, String)],
) -> Result<Vec<(String, String)>, fastbrdf::Error> {
    let mut out = Vec::new();
    for (k, v) in all {
        if takes(id, k)? {
            out.push((k.clone(), v.clone()));
        }
    }
    Ok(out)
}

/// One spec per model of a comparison: each model takes the values of `all` it can use (see
/// [`takes`]); a value no model takes is [`SpecError::Unused`].
pub fn specs(
    ids: &[&str],
    all: &[(String, String)],
    material: Option<&Material>,
    metal: Option<&Metal>,
    use_: Use,
) -> Result<Vec<ModelSpec>, SpecError> {
    for (k, _) in all {
        let mut used = false;
        for id in ids {
            used |= takes(id, k)?;
        }
        if !used {
            return Err(SpecError::Unused { param: k.clone() });
        }
    }
    ids.iter()
        .map(|id| spec(id, &own_pairs(id, all)?, material, metal, use_))
        .collect()
}

/// The values of `spec` as given to model `id` (the user's values, a material's and a
/// metal's), less those that shading `id` added (a lobe's `lobe` and `norm`, a distribution's
/// `d`): for labels and the explorer's answers, which name the model chosen.
pub fn asked_pairs(id: &str, spec: &ModelSpec) -> Vec<(String, String)> {
    let added: Vec<&str> = match fastbrdf::registry::find(id).map(|e| e.info.kind.shading()) {
        Ok(Shading::Via { param, extra, .. }) if spec.id() != id => std::iter::once(param)
            .chain(extra.iter().map(|(k, _)| *k))
            .collect(),
        _ => vec![],
    };
    spec.given()
        .iter()
        .filter(|(k, _)| !added.contains(k))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// `id k=v ...`: model `id` and the values `spec` was given, less those shading `id` adds
/// (a lobe's `lobe` and `norm`, a distribution's `d`): a comparison's label.
pub fn label(id: &str, spec: &ModelSpec) -> String {
    let mut s = id.to_string();
    for (k, v) in asked_pairs(id, spec) {
        s.push_str(&format!(" {k}={v}"));
    }
    s
}

/// What a material and a metal change in the scene of model `id` (render, compare): with a
/// material, the diffuse colour from the fit that goes with the model (its kd: the fits'
/// Lambert term is kd / pi, as the renderer's) unless the albedo was given, and the diffuse
/// weight 1 unless the weights were given (the specular weight is left alone: it is one
/// number here, the fit's ks is RGB, and lobes shade unnormalised); with a metal, the weights
/// KD,KS 0,1 unless given (a metal has no diffuse term; the specular colour is the metal's).
pub fn scene_colour(
    scene: &mut SceneSpec,
    id: &str,
    material: Option<&Material>,
    metal: bool,
    albedo_given: bool,
    weights_given: bool,
) {
    if let Some(fit) = material.and_then(|m| materials::fit_for(m, id)) {
        if !albedo_given {
            let [r, g, b] = fit.kd.map(|x| x as f32);
            (scene.albedo.x, scene.albedo.y, scene.albedo.z) = (r, g, b);
        }
        if !weights_given {
            scene.kd = 1.0;
        }
    }
    if metal && !weights_given {
        (scene.kd, scene.ks) = (0.0, 1.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf::Given;

    #[test]
    fn messages_name_no_flag() {
        let gold = fastbrdf::colour::metal("gold").unwrap();
        let e = spec("flog", &[], None, Some(gold), Use::Shaded).unwrap_err();
        assert!(
            e.to_string().starts_with("model 'flog' has no conductor"),
            "{e}"
        );
        let lambert = materials::find("gold-metallic-paint").unwrap();
        let e = spec("lambert", &[], Some(lambert), None, Use::AsIs).unwrap_err();
        assert!(
            e.to_string().starts_with("model 'lambert' takes none"),
            "{e}"
        );
    }

    #[test]
    fn shaded_metal_colours_the_brdf() {
        let gold = fastbrdf::colour::metal("gold").unwrap();
        let s = spec("ggx", &[], None, Some(gold), Use::Shaded).unwrap();
        assert_eq!(s.id(), "cook-torrance");
        assert_eq!(s.get("f"), Some(&Given::Choice("conductor".into())));
        assert!(s.is_coloured());
    }
}
