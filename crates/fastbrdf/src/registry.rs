//! The registry: every model id with its self-description and its plan builder, and the only
//! place where a model id is looked up. Adding a model means one `ENTRY` in its family file
//! and one line in [`REGISTRY`]; the id lists (`ids_of`), the parameter choices that name
//! "any model of kind X" and the registry-wide tests derive from it.

use crate::brdf::{cook_torrance, gltf_pbr, lambert, phong, ward};
use crate::entry::Entry;
use crate::error::{Error, Result};
use crate::lobes::{cubic, flog, gauss, pow, power, rational, schlick, sg, tuned};
use crate::microfacet::{
    beckmann, beckmann_pow, env_brdf, env_rational, env_table, fresnel, ggx, kelemen_neumann,
    shadowing, sheen_albedo, smith_ggx,
};
use crate::model::{Kind, Lobe};
use crate::params::{self, Options, ParamKind, ParamSpec, Params, Value};
use crate::plan::{Models, Plan};
use crate::real::Real;
use std::sync::OnceLock;

/// Every model, in display order.
pub static REGISTRY: &[Entry] = &[
    // Lobes (reference: pow).
    pow::ENTRY,
    schlick::ENTRY,
    schlick::ENTRY_MODIFIED,
    gauss::ENTRY,
    flog::ENTRY,
    flog::ENTRY_NORMALIZED,
    flog::ENTRY_CLAMPED,
    cubic::ENTRY,
    cubic::ENTRY3,
    rational::ENTRY,
    rational::ENTRY_CUBIC_RATIONAL,
    power::ENTRY4,
    power::ENTRY8,
    power::ENTRY16,
    sg::ENTRY,
    sg::ENTRY_UE4,
    tuned::ENTRY_POWER4,
    tuned::ENTRY_POWER8,
    tuned::ENTRY_POWER16,
    tuned::ENTRY_SG,
    tuned::ENTRY_CUBIC_RATIONAL,
    // Microfacet distributions (reference: beckmann / beckmann-ct).
    beckmann::ENTRY,
    beckmann::ENTRY_CT,
    beckmann_pow::ENTRY,
    beckmann_pow::ENTRY4,
    beckmann_pow::ENTRY8,
    beckmann_pow::ENTRY16,
    ggx::ENTRY,
    // Shadowing-masking.
    shadowing::ENTRY_VCAVITY,
    shadowing::ENTRY_SMITH,
    shadowing::ENTRY_RATIONAL,
    shadowing::ENTRY_BECKMANN_CORRELATED,
    smith_ggx::ENTRY_SMITH_GGX,
    smith_ggx::ENTRY_CORRELATED,
    smith_ggx::ENTRY_FAST,
    smith_ggx::ENTRY_FAST_TUNED,
    smith_ggx::ENTRY_JOINT,
    smith_ggx::ENTRY_SCHLICK,
    kelemen_neumann::ENTRY_KELEMEN,
    kelemen_neumann::ENTRY_NEUMANN,
    // Fresnel.
    fresnel::ENTRY_NONE,
    fresnel::ENTRY_SCHLICK,
    fresnel::ENTRY_SCHLICK_SG,
    fresnel::ENTRY_SCHLICK_SG_TUNED,
    fresnel::ENTRY_DIELECTRIC,
    fresnel::ENTRY_CONDUCTOR,
    env_brdf::ENTRY_DFG,
    env_brdf::ENTRY_APPROX,
    env_brdf::ENTRY_APPROX_TUNED,
    env_rational::ENTRY_MATERIALX,
    env_rational::ENTRY_MATERIALX_TUNED,
    env_table::ENTRY,
    sheen_albedo::ENTRY_EXACT,
    sheen_albedo::ENTRY_TABLE,
    sheen_albedo::ENTRY_KHRONOS,
    sheen_albedo::ENTRY_TUNED,
    // Full BRDFs.
    cook_torrance::ENTRY,
    ward::ENTRY,
    ward::ENTRY_POW,
    ward::ENTRY_POWER16,
    lambert::ENTRY,
    phong::ENTRY,
    phong::ENTRY_BLINN,
    gltf_pbr::ENTRY,
];

/// Every registry entry, with the choices that name "any model of kind X"
/// (`Options::Models`) replaced by the ids of that kind in registry order (by
/// `Options::Follows` where the default follows another choice), and a composite's list
/// completed with every parameter of its possible parts that it does not declare itself
/// ([`part_params`]: `cook-torrance` gains `schlick-ggx`'s `remap`), so that each option of a
/// part is reachable through the composite.
pub fn all() -> &'static [Entry] {
    static RESOLVED: OnceLock<Vec<Entry>> = OnceLock::new();
    RESOLVED.get_or_init(|| {
        REGISTRY
            .iter()
            .map(|e| {
                let mut e = *e;
                if e.info.params.iter().any(|p| {
                    matches!(
                        p.kind,
                        ParamKind::Choice {
                            options: Options::Models { .. },
                            ..
                        }
                    )
                }) {
                    let mut specs: Vec<ParamSpec> =
                        e.info.params.iter().map(resolve_spec).collect();
                    specs.extend(part_params(e.info.params));
                    e.info.params = Box::leak(specs.into_boxed_slice());
                }
                e
            })
            .collect()
    })
}

/// A parameter spec with `Options::Models` resolved to a list (leaked once: the registry
/// lives as long as the program).
fn resolve_spec(spec: &ParamSpec) -> ParamSpec {
    let mut s = *spec;
    if let ParamKind::Choice {
        options:
            Options::Models {
                kind,
                prefix,
                follow,
            },
        default,
    } = spec.kind
    {
        let names: Vec<&'static str> = ids_of(kind)
            .into_iter()
            .map(|id| id.strip_prefix(prefix).unwrap_or(id))
            .collect();
        let list: &'static [&'static str] = Box::leak(names.into_boxed_slice());
        s.kind = ParamKind::Choice {
            options: match follow {
                None => Options::List(list),
                Some(follow) => Options::Follows { list, follow },
            },
            default,
        };
    }
    s
}

/// The parameters of a composite's possible parts that the composite (`specs`, unresolved)
/// does not declare, in registry order, each gated on the choice that selects a part
/// declaring it: a number by its `requires`, a choice by `Options::Gated` (its non-default
/// options need that part; its default is harmless anywhere). The composite hands every value
/// it holds to its parts (`plan::Models::plan`), so these reach the part. A number is optional
/// in the composite (the part's own default applies when it is not given).
fn part_params(specs: &[ParamSpec]) -> Vec<ParamSpec> {
    // (the part's spec, the choice parameter, the options whose model declares it)
    let mut found: Vec<(ParamSpec, &'static str, Vec<&'static str>)> = Vec::new();
    for choice in specs {
        let ParamKind::Choice {
            options: Options::Models { kind, prefix, .. },
            ..
        } = choice.kind
        else {
            continue;
        };
        for part in REGISTRY.iter().filter(|e| e.info.kind == kind) {
            let option = part.info.id.strip_prefix(prefix).unwrap_or(part.info.id);
            for ps in part.info.params {
                if specs.iter().any(|s| s.name == ps.name) {
                    continue;
                }
                match found.iter_mut().find(|(s, _, _)| s.name == ps.name) {
                    // The same name in another part selected by the same choice: one
                    // parameter, needing either part (a name shared across choices keeps
                    // the first; `tests/composites.rs` would then find the second
                    // unreachable).
                    Some((_, c, opts)) if *c == choice.name => opts.push(option),
                    Some(_) => {}
                    None => found.push((*ps, choice.name, vec![option])),
                }
            }
        }
    }
    found
        .into_iter()
        .map(|(ps, choice, opts)| {
            let opts: &'static [&'static str] = Box::leak(opts.into_boxed_slice());
            let requires: params::Requires = Box::leak(vec![(choice, opts)].into_boxed_slice());
            let need = format!("{choice} = {}", opts.join(" or "));
            let doc: &'static str = Box::leak(format!("{} (needs {need})", ps.doc).into());
            let kind = match ps.kind {
                // Optional in the composite (a number with a default would always be
                // present, and so refused beside the other parts): the part takes its own
                // default when it is not given.
                ParamKind::Number { min, max, .. } => ParamKind::Number {
                    min,
                    max,
                    default: None,
                    requires,
                },
                ParamKind::Choice { default, .. } => ParamKind::Choice {
                    options: Options::Gated {
                        list: match resolve_spec(&ps).kind {
                            ParamKind::Choice { options, .. } => options.names(),
                            ParamKind::Number { .. } => &[],
                        },
                        requires,
                    },
                    default,
                },
            };
            ParamSpec { kind, doc, ..ps }
        })
        .collect()
}

/// The ids of every model of `kind`, in registry order.
pub fn ids_of(kind: Kind) -> Vec<&'static str> {
    REGISTRY
        .iter()
        .filter(|e| e.info.kind == kind)
        .map(|e| e.info.id)
        .collect()
}

/// The entry of `id`.
pub fn find(id: &str) -> Result<&'static Entry> {
    all()
        .iter()
        .find(|e| e.info.id == id)
        .ok_or_else(|| Error::UnknownModel(id.into()))
}

/// The registry as the sub-model builder of composite models.
struct Registry;

impl Models for Registry {
    fn plan(&self, id: &str, given: &dyn Fn(&str) -> Option<Value>) -> Result<Plan> {
        let e = find(id)?;
        let given: Vec<(&str, Value)> = e
            .info
            .params
            .iter()
            .filter_map(|s| given(s.name).map(|v| (s.name, v)))
            .collect();
        let p = Params::resolve_values(e.info.id, e.info.params, &given)?;
        e.build_plan(&p, self)
    }
}

/// The plan from already resolved parameters (what [`crate::ModelSpec`] builds each
/// channel's plan with).
pub fn plan_resolved(e: &Entry, p: &Params) -> Result<Plan> {
    e.build_plan(p, &Registry)
}

/// Lobe `id` at exponent `n` in precision `T` (Phong's and Blinn-Phong's `lobe`).
pub fn lobe<T: Real>(id: &str, n: f64) -> Result<Box<dyn Lobe<T>>> {
    Ok(Registry.lobe(id, n)?.model())
}

/// `Int(n) = integral_0^1 lobe(c) c dc` of lobe `id` (`brdf::phong::lobe_integral`).
pub fn lobe_integral(id: &str, n: f64) -> Result<f64> {
    Ok(crate::brdf::phong::lobe_integral(&Registry.lobe(id, n)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Kind;

    /// A composite that declares none of its parts' parameters gains them all, each gated on
    /// the parts that declare it: a number optional (so the composite builds with any part),
    /// refused beside a part without it, accepted beside one with it.
    #[test]
    fn part_params_gate_numbers_and_choices_on_their_part() {
        const G: ParamSpec = ParamSpec {
            name: "g",
            kind: ParamKind::Choice {
                options: Options::Models {
                    kind: Kind::Shadowing,
                    prefix: "",
                    follow: None,
                },
                default: "v-cavity",
            },
            doc: "",
        };
        let raw = [G];
        let mut specs: Vec<ParamSpec> = raw.iter().map(resolve_spec).collect();
        specs.extend(part_params(&raw));
        let names: Vec<&str> = specs.iter().map(|s| s.name).collect();
        assert_eq!(names, ["g", "alpha", "remap"]);
        let ok = |given: &[(&str, &str)]| Params::resolve("test", &specs, given);
        assert!(ok(&[]).is_ok());
        assert!(ok(&[("g", "smith")]).is_ok());
        assert!(ok(&[("g", "smith"), ("alpha", "0.5")]).is_ok());
        let err = ok(&[("g", "v-cavity"), ("alpha", "0.5")])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("alpha") && err.contains("g in {smith"),
            "{err}"
        );
        assert!(ok(&[("g", "schlick-ggx"), ("remap", "ue4")]).is_ok());
        assert!(ok(&[("g", "smith"), ("remap", "ue4")]).is_err());
    }
}
