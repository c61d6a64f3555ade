//! The model options, declared once: `--param NAME=VALUE`, `--material NAME` and `--metal
//! NAME`, flattened into every command that takes a model (each command takes the groups it
//! needs; a command may reword a help text with `mut_arg`, never redeclare the option). As
//! ripgrep parses its flags once into one validated config, the text is parsed here once into
//! a validated [`ModelSpec`] ([`ModelArgs::spec`]); the commands pass the spec inward and
//! never read parameter text again. The explorer's query string is the other text boundary:
//! it builds its specs with [`spec`] too.
//!
//! A leaf module: it imports no command.

use crate::CliError;
use fastbrdf::colour::{self, Metal};
use fastbrdf::kind::Shading;
use fastbrdf::{Kind, ModelSpec};
use fastbrdf_analysis::materials::{self, Material};
use fastbrdf_io::shorten;

/// The most characters of a given value quoted in a message.
const QUOTE: usize = 40;

/// `--param NAME=VALUE`, repeatable.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct ParamArgs {
    /// A parameter, NAME=VALUE; repeat for several.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
}

/// `--material NAME`: a MERL material's published fit supplies parameters.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct MaterialArg {
    /// A MERL material (see `fastbrdf materials`) whose published fit supplies the model's n,
    /// alpha and f0 (Ngan et al. 2005); --param values win.
    #[arg(long, value_name = "NAME")]
    pub material: Option<String>,
}

/// `--metal NAME`: a named metal colours the model.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct MetalArg {
    /// A named metal (see `fastbrdf metals`): f = conductor, eta and k per R, G, B channel;
    /// --param values win.
    #[arg(long, value_name = "NAME")]
    pub metal: Option<String>,
}

/// The whole group: `--param`, `--material`, `--metal`.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct ModelArgs {
    #[command(flatten)]
    pub param: ParamArgs,
    #[command(flatten)]
    pub material: MaterialArg,
    #[command(flatten)]
    pub metal: MetalArg,
}

/// What the model is used for: that decides whether it is shaded before a metal colours it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// As it is (eval, sample, albedo, shader export, analysis).
    AsIs,
    /// Shaded (render, compare, demo, the explorer, BRDF Explorer export): a lobe as
    /// blinn-phong, a distribution as cook-torrance ([`ModelSpec::shaded`]); `--param` values
    /// the model itself does not take go to the BRDF it is shaded as.
    Shaded,
}

/// The parameters of the shading BRDF a distribution may also be given in a comparison (where
/// each model takes the `--param` values it can use; see [`ModelArgs::specs`]).
const SHADED_DISTRIBUTION: [&str; 6] = ["g", "f", "f0", "eta", "k", "denominator"];

/// `NAME=VALUE` texts as pairs, split once (names and values trimmed).
pub fn pairs(texts: &[String]) -> Result<Vec<(String, String)>, CliError> {
    texts
        .iter()
        .map(|p| {
            p.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .ok_or_else(|| {
                    CliError::input(format!(
                        "--param '{}': expected NAME=VALUE",
                        shorten(p, QUOTE)
                    ))
                })
        })
        .collect()
}

impl ParamArgs {
    /// The `--param` values as pairs.
    pub fn pairs(&self) -> Result<Vec<(String, String)>, CliError> {
        pairs(&self.params)
    }

    /// The validated spec of model `id` with these values.
    pub fn spec(&self, id: &str, use_: Use) -> Result<ModelSpec, CliError> {
        spec(id, &self.pairs()?, None, None, use_)
    }
}

impl MaterialArg {
    /// The material named, if any (an unknown name is exit code 2 with the closest names).
    pub fn get(&self) -> Result<Option<&'static Material>, CliError> {
        self.material
            .as_deref()
            .map(|n| materials::find(n).map_err(CliError::input))
            .transpose()
    }
}

impl MetalArg {
    /// The metal named, if any (an unknown name is exit code 2 listing the metals).
    pub fn get(&self) -> Result<Option<&'static Metal>, CliError> {
        Ok(self.metal.as_deref().map(colour::metal).transpose()?)
    }
}

impl ModelArgs {
    /// The validated spec of model `id`: `--param` values, then the material's figures and
    /// (after shading, for [`Use::Shaded`]) the metal's, given values winning.
    pub fn spec(&self, id: &str, use_: Use) -> Result<ModelSpec, CliError> {
        spec(
            id,
            &self.param.pairs()?,
            self.material.get()?,
            self.metal.get()?,
            use_,
        )
    }

    /// One spec per model of a comparison: each model takes the `--param` values it can use
    /// (see [`takes`]); a value no model takes is an error.
    pub fn specs(&self, ids: &[&str], use_: Use) -> Result<Vec<ModelSpec>, CliError> {
        let all = self.param.pairs()?;
        let (material, metal) = (self.material.get()?, self.metal.get()?);
        for (k, _) in &all {
            let mut used = false;
            for id in ids {
                used |= takes(id, k)?;
            }
            if !used {
                return Err(CliError::input(format!(
                    "--param {k}: none of the models takes it"
                )));
            }
        }
        ids.iter()
            .map(|id| spec(id, &own_pairs(id, &all)?, material, metal, use_))
            .collect()
    }
}

/// Whether model `id` takes parameter `name` in a comparison: its own parameters, and for a
/// distribution the shading Cook-Torrance's `g`, `f`, `f0`, `eta`, `k` and `denominator`.
pub fn takes(id: &str, name: &str) -> Result<bool, CliError> {
    let e = fastbrdf::registry::find(id)?;
    Ok(e.info.params.iter().any(|p| p.name == name)
        || (e.info.kind == Kind::Distribution && SHADED_DISTRIBUTION.contains(&name)))
}

/// The pairs of `all` that model `id` takes (see [`takes`]).
pub fn own_pairs(id: &str, all: &[(String, String)]) -> Result<Vec<(String, String)>, CliError> {
    let mut out = Vec::new();
    for (k, v) in all {
        if takes(id, k)? {
            out.push((k.clone(), v.clone()));
        }
    }
    Ok(out)
}

/// The one place a model's parameter text becomes a [`ModelSpec`] (the CLI's options and the
/// explorer's query): `given` validated against model `id` (with [`Use::Shaded`], the values
/// the model does not take against the BRDF it is shaded as), the material's figures
/// ([`with_material`]) and the metal's ([`with_metal`], after shading) added where no value
/// was given. Every error is exit code 2 and names the model, the parameter and the value.
pub fn spec(
    id: &str,
    given: &[(String, String)],
    material: Option<&Material>,
    metal: Option<&Metal>,
    use_: Use,
) -> Result<ModelSpec, CliError> {
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
/// model that takes none of them, or a figure outside the model's documented domain, is exit
/// code 2.
pub fn with_material(m: &Material, spec: &ModelSpec) -> Result<ModelSpec, CliError> {
    let id = spec.id();
    if materials::supplied(m, spec).is_empty() {
        return Err(CliError::input(format!(
            "--material {}: model '{id}' takes none of the fitted parameters (n, alpha, f0)",
            m.name
        )));
    }
    materials::apply(m, spec).map_err(CliError::input)
}

/// `spec` coloured by metal `m` (`f = conductor`, `eta`, `k` per channel, given values
/// winning); a model without the conductor term's `eta` and `k` is exit code 2 naming `asked`,
/// the model the user gave.
pub fn with_metal(m: &Metal, spec: &ModelSpec, asked: &str) -> Result<ModelSpec, CliError> {
    if !(spec.takes("eta") && spec.takes("k")) {
        return Err(CliError::input(format!(
            "--metal {}: model '{}' has no conductor Fresnel term (parameters eta, k): \
             metals colour cook-torrance, the distributions (shaded as cook-torrance) and \
             fresnel-conductor",
            m.id,
            shorten(asked, QUOTE)
        )));
    }
    Ok(spec.with_metal(m)?)
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

/// Model `id` itself, from `spec` (a spec of `id`, or of the BRDF `id` is shaded as): the
/// values given that `id` takes, typed (no text is parsed again).
pub fn unshaded(id: &str, spec: &ModelSpec) -> Result<ModelSpec, CliError> {
    if spec.id() == id {
        return Ok(spec.clone());
    }
    let e = fastbrdf::registry::find(id)?;
    let own: Vec<(&str, fastbrdf::Given)> = spec
        .given()
        .iter()
        .filter(|(k, _)| e.info.params.iter().any(|p| p.name == *k))
        .map(|(k, v)| (*k, v.clone()))
        .collect();
    Ok(ModelSpec::new(id, &own)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf::Given;

    fn given(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    #[test]
    fn text_splits_once_and_bad_text_is_exit_2() {
        assert_eq!(
            pairs(&[" n = 20 ".into()]).unwrap(),
            vec![("n".into(), "20".into())]
        );
        let e = pairs(&["n".into()]).unwrap_err();
        assert_eq!(e.code, crate::EXIT_INPUT);
        assert!(e.message.contains("--param 'n': expected NAME=VALUE"));
    }

    /// A shaded distribution: its own values checked against it, the others against
    /// cook-torrance; labels and the explorer name the distribution with the values given.
    #[test]
    fn shading_routes_values_and_keeps_the_models_name() {
        let all = given(&[("alpha", "0.3"), ("g", "smith")]);
        let s = spec("ggx", &all, None, None, Use::Shaded).unwrap();
        assert_eq!(s.id(), "cook-torrance");
        assert_eq!(s.get("d"), Some(&Given::Choice("ggx".into())));
        assert_eq!(s.get("g"), Some(&Given::Choice("smith".into())));
        assert_eq!(
            asked_pairs("ggx", &s),
            given(&[("alpha", "0.3"), ("g", "smith")])
        );
        let own = unshaded("ggx", &s).unwrap();
        assert_eq!(
            own,
            ModelSpec::new("ggx", &[("alpha", Given::Num(0.3))]).unwrap()
        );
        // As it is, a distribution takes no g.
        assert!(spec("ggx", &all, None, None, Use::AsIs).is_err());
        // A value out of the distribution's range names the distribution.
        let e = spec("ggx", &given(&[("alpha", "7")]), None, None, Use::Shaded).unwrap_err();
        assert!(e.message.contains("ggx"), "{}", e.message);
    }

    #[test]
    fn metals_follow_shading_and_given_values_win() {
        let gold = colour::metal("gold").unwrap();
        let s = spec(
            "ggx",
            &given(&[("eta", "1.5")]),
            None,
            Some(gold),
            Use::Shaded,
        )
        .unwrap();
        assert!(s.is_coloured());
        assert_eq!(s.get("eta"), Some(&Given::Num(1.5)));
        assert_eq!(s.get("f"), Some(&Given::Choice("conductor".into())));
        let e = spec("ggx", &[], None, Some(gold), Use::AsIs).unwrap_err();
        assert!(
            e.message.contains("--metal gold: model 'ggx'"),
            "{}",
            e.message
        );
        let e = spec("flog", &[], None, Some(gold), Use::Shaded).unwrap_err();
        assert!(e.message.contains("model 'flog'"), "{}", e.message);
    }

    #[test]
    fn materials_supply_figures_where_none_is_given() {
        let m = materials::find("gold-paint").unwrap();
        let s = spec("flog", &[], Some(m), None, Use::AsIs).unwrap();
        assert!(matches!(s.get("n"), Some(Given::Num(_))));
        let mine = spec("flog", &given(&[("n", "20")]), Some(m), None, Use::AsIs).unwrap();
        assert_eq!(mine.get("n"), Some(&Given::Num(20.0)));
    }

    #[test]
    fn a_comparison_gives_each_model_what_it_takes() {
        let all = given(&[("n", "50"), ("f", "schlick")]);
        assert_eq!(own_pairs("flog", &all).unwrap(), given(&[("n", "50")]));
        assert_eq!(own_pairs("ggx", &all).unwrap(), given(&[("f", "schlick")]));
        assert!(takes("ggx", "denominator").unwrap() && !takes("flog", "f").unwrap());
    }
}
