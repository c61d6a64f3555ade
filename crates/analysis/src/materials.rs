//! The 86 MERL materials' published fits (Ngan, Matusik and Durand, "Experimental Analysis of
//! BRDF Models", EGSR 2005): Blinn-Phong `n`, Cook-Torrance's Beckmann slope `m` and `f0`,
//! Ward's `alpha`, each with RGB albedos. Embedded (`data/ngan2005_fits.csv`, source in
//! `data/README.md`) and parsed once at first use.
//!
//! A material supplies a model's parameters by the parameter's name and the model's kind:
//! - `n` (every lobe, `phong`, `blinn-phong`): the Blinn-Phong exponent;
//! - `alpha` of Ward (`ward`, `ward-*`): Ward's alpha; `alpha` of everything else that takes
//!   it (distributions, shadowing, `cook-torrance`): the Beckmann slope m (Beckmann's m is
//!   alpha);
//! - `f0` (`cook-torrance`, `fresnel-schlick`): Cook-Torrance's normal-incidence reflectance.
//!
//! [`over`] measures every documented approximation against its reference at each material's
//! own parameter (the `errors` command's measures), and says where a material lies outside a
//! model's documented domain instead of dropping it.

use crate::errors::{self, ErrorRow};
use fastbrdf::params::ParamKind;
use fastbrdf::{Given, ModelSpec, Result, Zone};
use rayon::prelude::*;
use std::sync::OnceLock;

/// The embedded table (`data/ngan2005_fits.csv`).
pub const CSV: &str = include_str!("../data/ngan2005_fits.csv");

/// Where the figures come from, for outputs.
pub const SOURCE: &str = "Ngan, Matusik and Durand, \"Experimental Analysis of BRDF Models\", EGSR 2005 (MERL materials; transcribed from bsdfbenchmark/bbm fits/ngan_{blinnphong,cooktorrance,ward}.fit)";

/// One model's fit: its RGB diffuse and specular albedos (the paper's conventions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedos {
    pub kd: [f64; 3],
    pub ks: [f64; 3],
}

/// One MERL material's published fits.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Blinn-Phong exponent.
    pub blinn_phong_n: f64,
    pub blinn_phong: Albedos,
    /// Cook-Torrance's Beckmann slope m (= alpha).
    pub cook_torrance_m: f64,
    /// Cook-Torrance's normal-incidence reflectance.
    pub cook_torrance_f0: f64,
    pub cook_torrance: Albedos,
    /// Ward's alpha.
    pub ward_alpha: f64,
    pub ward: Albedos,
}

/// Which fitted figure supplies a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    BlinnPhongN,
    CookTorranceM,
    CookTorranceF0,
    WardAlpha,
}

impl Source {
    /// The CSV column's name.
    pub fn column(self) -> &'static str {
        match self {
            Source::BlinnPhongN => "blinn_phong_n",
            Source::CookTorranceM => "cook_torrance_m",
            Source::CookTorranceF0 => "cook_torrance_f0",
            Source::WardAlpha => "ward_alpha",
        }
    }

    /// The material's figure.
    pub fn value(self, m: &Material) -> f64 {
        match self {
            Source::BlinnPhongN => m.blinn_phong_n,
            Source::CookTorranceM => m.cook_torrance_m,
            Source::CookTorranceF0 => m.cook_torrance_f0,
            Source::WardAlpha => m.ward_alpha,
        }
    }
}

/// Whether `id` is one of the Ward BRDFs (their `alpha` is Ward's, not Beckmann's).
fn is_ward(id: &str) -> bool {
    id == "ward" || id.starts_with("ward-")
}

/// The figure that supplies parameter `param` of model `id`, if any.
pub fn source(id: &str, param: &str) -> Option<Source> {
    match param {
        "n" => Some(Source::BlinnPhongN),
        "alpha" if is_ward(id) => Some(Source::WardAlpha),
        "alpha" => Some(Source::CookTorranceM),
        "f0" => Some(Source::CookTorranceF0),
        _ => None,
    }
}

fn parse(csv: &str) -> std::result::Result<Vec<Material>, String> {
    let mut lines = csv.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines.next().ok_or("empty table")?.split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| format!("no column {name}"))
    };
    let name_col = col("material")?;
    let mut out = vec![];
    for (i, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != header.len() {
            return Err(format!("row {}: {} fields", i + 2, fields.len()));
        }
        let num = |name: &str| -> std::result::Result<f64, String> {
            let x: f64 = fields[col(name)?]
                .trim()
                .parse()
                .map_err(|_| format!("row {}: {name} is not a number", i + 2))?;
            if x.is_finite() && x >= 0.0 {
                Ok(x)
            } else {
                Err(format!("row {}: {name} = {x}", i + 2))
            }
        };
        let rgb = |prefix: &str| -> std::result::Result<[f64; 3], String> {
            Ok([
                num(&format!("{prefix}_r"))?,
                num(&format!("{prefix}_g"))?,
                num(&format!("{prefix}_b"))?,
            ])
        };
        let albedos = |model: &str| -> std::result::Result<Albedos, String> {
            Ok(Albedos {
                kd: rgb(&format!("{model}_kd"))?,
                ks: rgb(&format!("{model}_ks"))?,
            })
        };
        out.push(Material {
            name: fields[name_col].trim().to_string(),
            blinn_phong_n: num("blinn_phong_n")?,
            blinn_phong: albedos("blinn_phong")?,
            cook_torrance_m: num("cook_torrance_m")?,
            cook_torrance_f0: num("cook_torrance_f0")?,
            cook_torrance: albedos("cook_torrance")?,
            ward_alpha: num("ward_alpha")?,
            ward: albedos("ward")?,
        });
    }
    Ok(out)
}

/// Every material, in the table's (alphabetical) order.
///
/// # Panics
/// When the embedded table does not parse (a test keeps it parsing).
pub fn all() -> &'static [Material] {
    static TABLE: OnceLock<Vec<Material>> = OnceLock::new();
    TABLE.get_or_init(|| parse(CSV).expect("the embedded ngan2005_fits.csv parses"))
}

/// Edit distance between two names (for suggestions).
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur.push(sub.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The `k` material names closest to `name` (names containing it first, then by edit
/// distance).
pub fn closest(name: &str, k: usize) -> Vec<&'static str> {
    let lower = name.to_ascii_lowercase();
    let mut scored: Vec<(usize, &'static str)> = all()
        .iter()
        .map(|m| {
            let d = if !lower.is_empty() && m.name.contains(&lower) {
                0
            } else {
                distance(&lower, &m.name)
            };
            (d, m.name.as_str())
        })
        .collect();
    scored.sort();
    scored.into_iter().take(k).map(|(_, n)| n).collect()
}

/// The material called `name`, or a message naming the closest materials.
pub fn find(name: &str) -> std::result::Result<&'static Material, String> {
    all().iter().find(|m| m.name == name).ok_or_else(|| {
        format!(
            "unknown material '{}'; closest: {} (run `fastbrdf materials` for all 86)",
            fastbrdf_io::shorten(name, 40),
            closest(name, 3).join(", ")
        )
    })
}

/// The documented range `[min, max]` of numeric parameter `param` of model `id` (a split-sum
/// term's `alpha` is an input with `params::ALPHA`'s range).
pub fn domain(id: &str, param: &str) -> Option<(f64, f64)> {
    fastbrdf::registry::find(id).ok()?.info.sweep_range(param)
}

/// Whether `x` lies in the documented range of `param` of model `id`.
pub fn inside(id: &str, param: &str, x: f64) -> bool {
    domain(id, param).is_some_and(|(lo, hi)| x >= lo && x <= hi)
}

/// A parameter a material supplies to a model.
#[derive(Clone, Debug, PartialEq)]
pub struct Supplied {
    pub param: &'static str,
    pub value: f64,
    pub source: Source,
}

/// The numeric parameters `material` supplies to `spec`'s model (given or not: see
/// [`apply`]), in the model's parameter order.
pub fn supplied(material: &Material, spec: &ModelSpec) -> Vec<Supplied> {
    spec.info()
        .params
        .iter()
        .filter(|p| matches!(p.kind, ParamKind::Number { .. }))
        .filter_map(|p| {
            source(spec.id(), p.name).map(|s| Supplied {
                param: p.name,
                value: s.value(material),
                source: s,
            })
        })
        .collect()
}

/// The fit whose albedos go with model `id`: Ward's for the Ward BRDFs, Blinn-Phong's for
/// models that take `n`, Cook-Torrance's for the others that take `alpha` (None otherwise).
pub fn fit_for<'a>(material: &'a Material, id: &str) -> Option<&'a Albedos> {
    let e = fastbrdf::registry::find(id).ok()?;
    let takes = |p: &str| e.info.params.iter().any(|s| s.name == p);
    if takes("n") {
        Some(&material.blinn_phong)
    } else if takes("alpha") && is_ward(e.info.id) {
        Some(&material.ward)
    } else if takes("alpha") {
        Some(&material.cook_torrance)
    } else {
        None
    }
}

/// `spec` with the figures `material` supplies to its model added where no value is given
/// (given values win: [`ModelSpec::with_defaults`]). A supplied value outside the model's
/// documented domain is an error that says so (give the parameter to override it).
pub fn apply(material: &Material, spec: &ModelSpec) -> std::result::Result<ModelSpec, String> {
    let id = spec.id();
    let mut defaults = vec![];
    for s in supplied(material, spec) {
        if spec.get(s.param).is_some() {
            continue;
        }
        if !inside(id, s.param, s.value) {
            let (lo, hi) = domain(id, s.param).unwrap_or((f64::NAN, f64::NAN));
            return Err(format!(
                "material '{}': its {} = {} is outside {id}'s documented domain {} in [{lo}, {hi}] \
                 (give {} explicitly to override it, or choose another material)",
                material.name,
                s.source.column(),
                s.value,
                s.param,
                s.param
            ));
        }
        defaults.push((s.param, Given::Num(s.value)));
    }
    spec.with_defaults(&defaults)
        .map_err(|e| format!("material '{}': {e}", material.name))
}

/// The model families a material's figures fall inside the documented domains of:
/// `blinn-phong` (n), `cook-torrance` (alpha = m, f0), `ward` (alpha).
pub fn families(m: &Material) -> Vec<&'static str> {
    let mut out = vec![];
    if inside("blinn-phong", "n", m.blinn_phong_n) {
        out.push("blinn-phong");
    }
    if inside("cook-torrance", "alpha", m.cook_torrance_m)
        && inside("cook-torrance", "f0", m.cook_torrance_f0)
    {
        out.push("cook-torrance");
    }
    if inside("ward", "alpha", m.ward_alpha) {
        out.push("ward");
    }
    out
}

/// An approximation and the reference its documented bounds are measured against.
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    pub model: &'static str,
    pub reference: &'static str,
    /// The swept parameter (`n` or `alpha`).
    pub param: &'static str,
}

/// Every model with a documented error bound, against the reference of its first bound.
pub fn approximations() -> Vec<Pair> {
    fastbrdf::registry::all()
        .iter()
        .filter_map(|e| {
            e.info.bounds.first().map(|b| Pair {
                model: e.info.id,
                reference: b.reference,
                param: b.param.0,
            })
        })
        .collect()
}

/// One material's errors for one approximation: `None` when the material's parameter lies
/// outside the model's or the reference's documented domain.
#[derive(Clone, Debug)]
pub struct OverRow {
    pub material: &'static str,
    pub pair: Pair,
    pub source: Source,
    pub value: f64,
    pub errors: Option<ErrorRow>,
}

/// Every pair's errors at every material's own parameter (rayon over materials and pairs;
/// `progress` is called once per measurement). Rows in material order, pairs in the given order.
pub fn over(pairs: &[Pair], zone: Zone, progress: &(dyn Fn() + Sync)) -> Result<Vec<OverRow>> {
    let mut jobs = vec![];
    for m in all() {
        for p in pairs {
            let source = source(p.model, p.param).ok_or_else(|| fastbrdf::Error::Domain {
                input: p.model.into(),
                reason: format!("no material figure supplies parameter {}", p.param),
            })?;
            jobs.push((m, p.clone(), source));
        }
    }
    jobs.par_iter()
        .map(|(m, p, source)| {
            let value = source.value(m);
            let spec = errors::Spec {
                model: p.model.into(),
                reference: p.reference.into(),
                param: p.param.into(),
                zone,
            };
            let errors = if inside(p.model, p.param, value) && inside(p.reference, p.param, value) {
                Some(errors::at(&spec, value)?)
            } else {
                None
            };
            progress();
            Ok(OverRow {
                material: m.name.as_str(),
                pair: p.clone(),
                source: *source,
                value,
                errors,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn median(mut v: Vec<f64>) -> f64 {
        v.sort_by(f64::total_cmp);
        (v[v.len() / 2 - 1] + v[v.len() / 2]) / 2.0
    }

    #[test]
    fn all_86_rows_parse_and_the_readme_figures_hold() {
        let t = all();
        assert_eq!(t.len(), 86);
        let n: Vec<f64> = t.iter().map(|m| m.blinn_phong_n).collect();
        let m: Vec<f64> = t.iter().map(|m| m.cook_torrance_m).collect();
        let w: Vec<f64> = t.iter().map(|m| m.ward_alpha).collect();
        let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        // n from 1.45 to 121,000, median 230, 40 of 86 above 1000.
        assert_eq!((min(&n), max(&n)), (1.45, 121_000.0));
        assert!(
            (median(n.clone()) - 230.0).abs() < 1.0,
            "{}",
            median(n.clone())
        );
        assert_eq!(n.iter().filter(|x| **x > 1000.0).count(), 40);
        // m from 0.005 to 0.94, median 0.072.
        assert!((min(&m) - 0.005).abs() < 0.0005 && (max(&m) - 0.94).abs() < 0.005);
        assert!((median(m) - 0.072).abs() < 0.0005);
        // Ward alpha from 0.006 to 0.5.
        assert!((min(&w) - 0.006).abs() < 0.0005 && max(&w) == 0.5);
        // f0 a reflectance; albedos finite and non-negative (checked by the parser).
        assert!(
            t.iter()
                .all(|m| m.cook_torrance_f0 > 0.0 && m.cook_torrance_f0 < 1.0)
        );
        let mut names: Vec<&str> = t.iter().map(|m| m.name.as_str()).collect();
        names.dedup();
        assert_eq!(names.len(), 86, "names are unique and sorted");
    }

    fn spec(id: &str, given: &[(&str, &str)]) -> ModelSpec {
        ModelSpec::parse(id, given).unwrap()
    }

    #[test]
    fn a_material_supplies_parameters_by_kind_and_name() {
        let m = find("gold-paint").unwrap();
        let pairs = |id: &str, given: &[(&str, &str)]| apply(m, &spec(id, given)).unwrap().pairs();
        let one = |k: &str, v: &str| vec![(k.to_string(), v.to_string())];
        assert_eq!(pairs("pow", &[]), one("n", "36.8"));
        assert_eq!(pairs("ward-pow", &[]), one("alpha", "0.234"));
        assert_eq!(pairs("beckmann", &[]), one("alpha", "0.214"));
        assert_eq!(
            pairs("cook-torrance", &[("f0", "0.5")]),
            [
                ("f0".to_string(), "0.5".to_string()),
                ("alpha".to_string(), "0.214".to_string())
            ]
        );
        // Given values win; the figures a model takes are supplied whether given or not.
        assert_eq!(pairs("pow", &[("n", "7")]), one("n", "7"));
        let s = supplied(m, &spec("cook-torrance", &[]));
        let names: Vec<&str> = s.iter().map(|s| s.param).collect();
        assert!(
            names.contains(&"alpha") && names.contains(&"f0"),
            "{names:?}"
        );
        assert!(supplied(m, &spec("lambert", &[])).is_empty());
        // n = 121,000 stays outside even a widened [1, 1e5].
        let violet = find("specular-violet-phenolic").unwrap();
        let e = apply(violet, &spec("pow", &[])).unwrap_err();
        assert!(e.contains("outside pow's documented domain n"), "{e}");
        assert!(apply(violet, &spec("pow", &[("n", "1000")])).is_ok());
        assert!(find("gold-pant").unwrap_err().contains("gold-paint"));
        assert_eq!(fit_for(m, "flog"), Some(&m.blinn_phong));
        assert_eq!(fit_for(m, "ward-power16"), Some(&m.ward));
        assert_eq!(fit_for(m, "beckmann-pow"), Some(&m.cook_torrance));
        assert_eq!(fit_for(m, "lambert"), None);
    }
}
