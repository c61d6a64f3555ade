//! What is fitted: the model, its fixed parameters, the free ones (each mapped from an
//! unbounded variable onto its documented range) and the held ones.

use super::{Data, HELD};
use fastbrdf::measured;
use fastbrdf::params::ParamKind;
use fastbrdf::params::Value;
use fastbrdf::{Brdf, Given, Kind, Model, ModelSpec};

/// A fitted (or searched) numeric parameter and its documented range.
#[derive(Clone, Debug)]
pub struct Free {
    pub name: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    /// The default, where the first start begins.
    pub default: f64,
}

impl Free {
    pub(super) fn value(&self, u: f64) -> f64 {
        let t = (0.5 - 0.5 * u.cos()).clamp(0.0, 1.0);
        let v = if self.log {
            (self.lo.ln() + t * (self.hi.ln() - self.lo.ln())).exp()
        } else {
            self.lo + t * (self.hi - self.lo)
        };
        v.clamp(self.lo, self.hi)
    }

    pub(super) fn u_of_t(t: f64) -> f64 {
        (1.0 - 2.0 * t.clamp(0.0, 1.0)).acos()
    }

    pub(super) fn t_of(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

/// What is fitted: a registry BRDF with its fixed parameters (the spec's given values:
/// choices and values given by the user) and its free numeric parameters.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The model and the values fixed (given); a grey BRDF.
    pub spec: ModelSpec,
    pub free: Vec<Free>,
    /// Parameters of [`HELD`] the model reads that a search left at their default (name,
    /// value): not fitted, and not in `fixed`.
    pub held: Vec<(&'static str, f64)>,
}

impl Problem {
    /// `spec`'s model (a BRDF) with its given values fixed; with `search`, every other
    /// numeric parameter that has a default and whose required choices hold is free, except
    /// those of [`HELD`] (left at their default), otherwise none is (defaults are used).
    /// Errors: a non-BRDF kind, a coloured spec (the albedos carry the colour).
    pub fn new(spec: &ModelSpec, search: bool) -> Result<Self, String> {
        Self::with_free(spec, search, &[])
    }

    /// [`Problem::new`], with the [`HELD`] parameters named in `also` fitted too. Errors also:
    /// a name in `also` that is not one of the model's numeric parameters, or that `spec`
    /// gives.
    pub fn with_free(spec: &ModelSpec, search: bool, also: &[String]) -> Result<Self, String> {
        let e = spec.entry();
        let id = spec.id();
        for name in also {
            let short = fastbrdf_io::shorten(name, 40);
            match e.info.params.iter().find(|p| p.name == name) {
                Some(p) if matches!(p.kind, ParamKind::Number { .. }) => {}
                Some(_) => return Err(format!("{short} is a choice, not a number to fit")),
                None => return Err(format!("{} has no parameter '{short}'", e.info.id)),
            }
            if spec.get(name).is_some() {
                return Err(format!(
                    "{short} is both fixed (--param) and asked to be fitted"
                ));
            }
        }
        if e.info.kind != Kind::Brdf {
            return Err(format!(
                "{id} is a {} model; fitting measured data needs a BRDF (see `fastbrdf models --kind brdf`)",
                format!("{:?}", e.info.kind).to_lowercase()
            ));
        }
        // The choices in force (given or default), for `requires`.
        let resolved = spec.params().map_err(|e| e.to_string())?;
        let choice = |name: &str| match resolved.get(name) {
            Some(Value::Text(t)) => Some(t.clone()),
            _ => None,
        };
        let mut free = Vec::new();
        let mut held = Vec::new();
        if search {
            for p in e.info.params {
                if spec.get(p.name).is_some() {
                    continue;
                }
                let ParamKind::Number {
                    min,
                    max,
                    default: Some(default),
                    ..
                } = p.kind
                else {
                    continue;
                };
                if !(p.allowed(choice) && max > min) {
                    continue;
                }
                // Probed below like the others; moved to `held` if the model reads it.
                held.push(
                    HELD.iter().any(|(n, _)| *n == p.name) && !also.iter().any(|a| a == p.name),
                );
                free.push(Free {
                    name: p.name,
                    lo: min,
                    hi: max,
                    log: min > 0.0 && max / min > 20.0,
                    default,
                });
            }
        }
        let mut problem = Self {
            spec: spec.clone(),
            free,
            held: Vec::new(),
        };
        let defaults: Vec<f64> = problem.free.iter().map(|f| f.default).collect();
        let base = problem.model(&defaults).map_err(|e| e.to_string())?;
        // A parameter the chosen configuration does not read (cook-torrance's eta and k beside
        // f = schlick) would be a flat direction of the search: it stays at its default. It is
        // found by probing: moved to two other points of its range, the model is unchanged at
        // every probe direction.
        let probes: Vec<([f64; 3], [f64; 3])> = (0..24)
            .map(|i| {
                let th = 0.05 + 0.06 * i as f64;
                let td = 0.1 + 0.055 * ((i * 7) % 24) as f64;
                measured::from_half_diff(th.min(1.3), td.min(1.35), 0.3 + 0.12 * i as f64)
            })
            .collect();
        let mut used = Vec::new();
        for (i, f) in problem.free.iter().enumerate() {
            let mut reads = false;
            for t in [0.3, 0.8] {
                let mut v = defaults.clone();
                v[i] = f.value(Free::u_of_t(t));
                let Ok(m) = problem.model(&v) else {
                    reads = true;
                    break;
                };
                reads |= probes
                    .iter()
                    .any(|&(wi, wo)| m.eval(wi, wo) != base.eval(wi, wo));
            }
            used.push(reads);
        }
        let all = std::mem::take(&mut problem.free);
        for ((f, used), held) in all.into_iter().zip(used).zip(held) {
            match (used, held) {
                (false, _) => {}
                (true, true) => problem.held.push((f.name, f.default)),
                (true, false) => problem.free.push(f),
            }
        }
        // A name in `also` that did not change what is fitted is refused: a silent no-op would
        // let the user believe it was fitted (or that the model reads it).
        for name in also {
            let short = fastbrdf_io::shorten(name, 40);
            let Some(p) = e.info.params.iter().find(|p| p.name == name) else {
                continue;
            };
            let ParamKind::Number {
                min,
                max,
                default,
                requires,
            } = p.kind
            else {
                continue;
            };
            let why = if !search {
                format!("nothing is fitted without a search, so {short} is not either")
            } else if !p.allowed(choice) {
                let need: Vec<String> = requires
                    .iter()
                    .map(|(c, vals)| format!("{c} = {}", vals.join(" or ")))
                    .collect();
                format!(
                    "{short} is not read with these choices (it needs {}); nothing to fit",
                    need.join(" and ")
                )
            } else if default.is_none() || max <= min {
                format!("{short} has no default and range to search from; give it with --param")
            } else if !problem.free.iter().any(|f| f.name == name.as_str()) {
                let with: Vec<String> = problem
                    .spec
                    .pairs()
                    .iter()
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect();
                format!(
                    "{} {} does not read {short} (moving it changes nothing); nothing to fit",
                    e.info.id,
                    if with.is_empty() {
                        "with its default choices".to_string()
                    } else {
                        format!("with {}", with.join(" "))
                    }
                )
            } else if !HELD.iter().any(|(n, _)| n == name) {
                let held: Vec<&str> = HELD.iter().map(|(n, _)| *n).collect();
                format!(
                    "{short} is fitted already; --free only adds the parameters held at their default ({})",
                    held.join(", ")
                )
            } else {
                continue;
            };
            return Err(format!("--free {short}: {why}"));
        }
        Ok(problem)
    }

    /// The model's registry id.
    pub fn id(&self) -> &'static str {
        self.spec.id()
    }

    /// The model at `values` (one per free parameter): the fixed values, then the free ones.
    pub fn params(&self, values: &[f64]) -> fastbrdf::Result<ModelSpec> {
        let mut given: Vec<(&str, Given)> = self.spec.given().to_vec();
        given.extend(
            self.free
                .iter()
                .zip(values)
                .map(|(f, &v)| (f.name, Given::Num(v))),
        );
        ModelSpec::new(self.id(), &given)
    }

    /// The specular model at `values` (one per free parameter).
    pub fn model(&self, values: &[f64]) -> fastbrdf::Result<Box<dyn Brdf<f64>>> {
        match self.params(values)?.model::<f64>()? {
            Model::Brdf(b) => Ok(b),
            _ => unreachable!("checked to be a BRDF"),
        }
    }

    /// The specular values at every sample, or `None` when one is not finite.
    pub(super) fn spec(&self, data: &Data, values: &[f64]) -> Option<Vec<f64>> {
        let b = self.model(values).ok()?;
        let s: Vec<f64> = data
            .wi
            .iter()
            .zip(&data.wo)
            .map(|(&wi, &wo)| b.eval(wi, wo))
            .collect();
        s.iter().all(|x| x.is_finite()).then_some(s)
    }
}
