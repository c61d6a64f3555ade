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
use fastbrdf::ModelSpec;
use fastbrdf::colour::{self, Metal};
use fastbrdf_analysis::materials::{self, Material};
use fastbrdf_analysis::model_spec::{self, SpecError};
use fastbrdf_io::{shorten, shorten_middle};

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

/// The one spelling of a model outside the registry, wherever a command takes a model id:
/// `file:PATH`, a BRDF Explorer `.brdf` file or a shader function in `.wgsl` or `.glsl`
/// (issue 31; the format: the book's user-shaders page). It is evaluated on the GPU (Mesa's
/// lavapipe without one), with the `--param` values checked against the ranges the file
/// declares.
pub const USER_PREFIX: &str = "file:";

/// Whether `id` names a user's model ([`USER_PREFIX`]).
pub fn is_user(id: &str) -> bool {
    id.starts_with(USER_PREFIX)
}

/// The user's model `id` (`file:PATH`) with the `--param` values `given`, compiled on the GPU;
/// `None` when `id` is a registry id. A bad file, a compile error (the compiler's message
/// with the file, line and column) or a bad value is exit 2, a GPU failure exit 1.
pub fn user(
    id: &str,
    given: &[(String, String)],
) -> Result<Option<std::sync::Arc<dyn fastbrdf::user::UserBrdf>>, CliError> {
    let Some(path) = id.strip_prefix(USER_PREFIX) else {
        return Ok(None);
    };
    if path.is_empty() {
        return Err(CliError::input(
            "--model file:: no path after 'file:' (e.g. --model file:my.brdf)",
        ));
    }
    match fastbrdf_gpu::user::load(std::path::Path::new(path), given) {
        Ok(b) => Ok(Some(std::sync::Arc::new(b))),
        Err(e) => Err(CliError {
            code: match e.kind {
                fastbrdf_gpu::user::UserErrorKind::Input => crate::EXIT_INPUT,
                fastbrdf_gpu::user::UserErrorKind::Gpu => crate::EXIT_CHECK_FAILED,
            },
            message: e.message,
        }),
    }
}

impl ModelArgs {
    /// [`user`] with these `--param` values; a user's model takes no `--material` or
    /// `--metal` (exit 2).
    pub fn user(
        &self,
        id: &str,
    ) -> Result<Option<std::sync::Arc<dyn fastbrdf::user::UserBrdf>>, CliError> {
        if is_user(id) {
            if let Some(m) = &self.material.material {
                return Err(CliError::input(format!(
                    "--material {}: a user's model ({}) takes its values from --param only",
                    shorten(m, QUOTE),
                    shorten_middle(id, QUOTE)
                )));
            }
            if let Some(m) = &self.metal.metal {
                return Err(CliError::input(format!(
                    "--metal {}: a user's model ({}) takes its values from --param only",
                    shorten(m, QUOTE),
                    shorten_middle(id, QUOTE)
                )));
            }
        }
        user(id, &self.param.pairs()?)
    }
}

/// One model of a comparison: a registry spec or a user's model.
pub enum Chosen {
    Spec(ModelSpec),
    User(std::sync::Arc<dyn fastbrdf::user::UserBrdf>),
}

impl ModelArgs {
    /// [`ModelArgs::specs`] for ids that may name users' models (`file:PATH`): each user's
    /// model takes the `--param` values its file declares, the registry models the rest as
    /// `specs` gives them; a value no model takes is exit 2.
    pub fn chosen(&self, ids: &[&str], use_: Use) -> Result<Vec<Chosen>, CliError> {
        if !ids.iter().any(|id| is_user(id)) {
            return Ok(self
                .specs(ids, use_)?
                .into_iter()
                .map(Chosen::Spec)
                .collect());
        }
        let all = self.param.pairs()?;
        let mut declared: Vec<Vec<String>> = Vec::new();
        for id in ids.iter().filter(|id| is_user(id)) {
            let path = std::path::Path::new(&id[USER_PREFIX.len()..]);
            let shader = fastbrdf_gpu::user::UserShader::load(path)
                .map_err(|e| CliError::input(e.message))?;
            declared.push(shader.params().iter().map(|p| p.name.clone()).collect());
        }
        let registry: Vec<&str> = ids.iter().copied().filter(|id| !is_user(id)).collect();
        let users_take = |k: &str| declared.iter().any(|d| d.iter().any(|n| n == k));
        // The registry models get the values that one of them takes or no user's model does
        // (the latter then fail as unused, naming the value).
        let mut to_registry = Vec::new();
        for (k, v) in &all {
            let mut taken = false;
            for id in &registry {
                taken |= takes(id, k)?;
            }
            if taken || !users_take(k) {
                to_registry.push((k.clone(), v.clone()));
            }
        }
        let (material, metal) = (self.material.get()?, self.metal.get()?);
        let mut specs =
            model_spec::specs(&registry, &to_registry, material, metal, use_)?.into_iter();
        let mut users = declared.iter();
        let mut out = Vec::new();
        for id in ids {
            if is_user(id) {
                let names = users.next().expect("one list per user's model");
                let own: Vec<(String, String)> = all
                    .iter()
                    .filter(|(k, _)| names.contains(k))
                    .cloned()
                    .collect();
                out.push(Chosen::User(user(id, &own)?.expect("a user's id")));
            } else {
                out.push(Chosen::Spec(
                    specs.next().expect("one spec per registry id"),
                ));
            }
        }
        Ok(out)
    }
}

/// What the model is used for: that decides whether it is shaded before a metal colours it
/// (the library's: [`fastbrdf_analysis::model_spec::Use`]).
pub use fastbrdf_analysis::model_spec::Use;

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
        Ok(model_spec::specs(ids, &all, material, metal, use_)?)
    }
}

/// Whether model `id` takes parameter `name` in a comparison: its own parameters, and for a
/// distribution the shading Cook-Torrance's `g`, `f`, `f0`, `eta`, `k` and `denominator`.
pub fn takes(id: &str, name: &str) -> Result<bool, CliError> {
    Ok(model_spec::takes(id, name)?)
}

/// The pairs of `all` that model `id` takes (see [`takes`]).
pub fn own_pairs(id: &str, all: &[(String, String)]) -> Result<Vec<(String, String)>, CliError> {
    Ok(model_spec::own_pairs(id, all)?)
}

/// A library spec error as the CLI's: exit code 2, the material's and the metal's messages
/// prefixed by their flag (`--material NAME: `, `--metal NAME: `).
impl From<SpecError> for CliError {
    fn from(e: SpecError) -> Self {
        match e {
            SpecError::Model(e) => e.into(),
            SpecError::Render(e) => e.into(),
            SpecError::NoFittedParams { ref material, .. } => {
                CliError::input(format!("--material {material}: {e}"))
            }
            SpecError::MaterialValue(m) => CliError::input(m),
            SpecError::NoConductor { ref metal, .. } => {
                CliError::input(format!("--metal {metal}: {e}"))
            }
            SpecError::Unused { ref param } => CliError::input(format!("--param {param}: {e}")),
        }
    }
}

/// The one place a model's parameter text becomes a [`ModelSpec`] (the CLI's options and the
/// explorer's query): the library's [`model_spec::spec`] (Python calls it too): `given`
/// validated against model `id` (with [`Use::Shaded`], the values the model does not take
/// against the BRDF it is shaded as), the material's figures ([`with_material`]) and the
/// metal's ([`with_metal`], after shading) added where no value was given. Every error is
/// exit code 2 and names the model, the parameter and the value.
pub fn spec(
    id: &str,
    given: &[(String, String)],
    material: Option<&Material>,
    metal: Option<&Metal>,
    use_: Use,
) -> Result<ModelSpec, CliError> {
    Ok(model_spec::spec(id, given, material, metal, use_)?)
}

/// `spec` with the figures material `m` supplies to its model where no value was given. A
/// model that takes none of them, or a figure outside the model's documented domain, is exit
/// code 2.
pub fn with_material(m: &Material, spec: &ModelSpec) -> Result<ModelSpec, CliError> {
    Ok(model_spec::with_material(m, spec)?)
}

/// The values of `spec` as given to model `id`, less those that shading `id` added (the
/// library's [`model_spec::asked_pairs`]).
pub use fastbrdf_analysis::model_spec::asked_pairs;

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
