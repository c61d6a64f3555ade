//! The typed model spec: a model id with its parameters parsed and validated once, at the
//! boundary where they arrive (the CLI's `--param`, the explorer's query, Python's keyword
//! arguments), and passed inward as one value. Every library function that needs "a model
//! with its parameters" takes a [`ModelSpec`] (or a [`Plan`] built from one), never text.
//!
//! A spec holds the registry entry, the values given (numbers, numbers per colour channel,
//! choices; in the order given), the resolved parameters (defaults filled in) of each colour
//! channel, and the channels' plans, built once. Metals (`with_metal`), the shading policy
//! (`shaded`) and, in `fastbrdf-analysis`, MERL materials are typed transformations of a
//! spec: they return a new validated spec.
//!
//! ```
//! use fastbrdf::spec::{Given, ModelSpec};
//! let spec = ModelSpec::parse("cook-torrance", &[("alpha", "0.2"), ("eta", "0.2,0.4,1.4")]).unwrap();
//! assert!(spec.is_coloured());
//! assert_eq!(spec.given()[1].1, Given::Rgb([0.2, 0.4, 1.4]));
//! let lobe = ModelSpec::new("flog", &[("n", Given::Num(20.0))]).unwrap();
//! let fastbrdf::Model::Lobe(l) = lobe.model::<f32>().unwrap() else { panic!() };
//! assert!((l.eval(1.0) - 1.0).abs() < 1e-6);
//! ```

use crate::colour::{self, Metal};
use crate::entry::Entry;
use crate::error::{Error, Result};
use crate::kind::Shading;
use crate::model::{Kind, Model, ModelInfo};
use crate::params::{ParamKind, Params, Value};
use crate::plan::Plan;
use crate::real::Real;
use crate::registry;
use std::fmt;

/// A value given for one parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum Given {
    /// One number (every channel).
    Num(f64),
    /// One number per colour channel (R, G, B: 650, 550, 450 nm): the model is coloured.
    Rgb([f64; 3]),
    /// One of a choice parameter's names.
    Choice(String),
}

impl fmt::Display for Given {
    /// Numbers in Rust's shortest round-trip form (they parse back unchanged); `R,G,B` as
    /// `a,b,c`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Given::Num(x) => write!(f, "{x}"),
            Given::Rgb([r, g, b]) => write!(f, "{r},{g},{b}"),
            Given::Choice(c) => f.write_str(c),
        }
    }
}

/// A model with validated parameters: see the module documentation.
#[derive(Clone)]
pub struct ModelSpec {
    entry: &'static Entry,
    given: Vec<(&'static str, Given)>,
    /// One (grey) or three (R, G, B) resolved parameter sets.
    params: Vec<Params>,
    /// The plan of each channel.
    plans: Vec<Plan>,
}

impl fmt::Debug for ModelSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ModelSpec({self})")
    }
}

/// `id name=value ...` (the given values only).
impl fmt::Display for ModelSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())?;
        for (k, v) in &self.given {
            write!(f, " {k}={v}")?;
        }
        Ok(())
    }
}

impl PartialEq for ModelSpec {
    fn eq(&self, other: &Self) -> bool {
        self.id() == other.id() && self.given == other.given
    }
}

impl ModelSpec {
    /// Parses parameters given as text (`NAME=VALUE` pairs: the CLI, the explorer): a numeric
    /// value `a,b,c` is one number per colour channel (the model is then coloured). Errors
    /// name the model, the parameter (and the channel), the value and what was expected.
    pub fn parse(id: &str, given: &[(&str, &str)]) -> Result<Self> {
        let entry = registry::find(id)?;
        let pairs: Vec<(String, String)> = given
            .iter()
            .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
            .collect();
        let lists: Vec<Vec<(String, String)>> = match colour::channels(entry.info.id, &pairs)? {
            None => vec![pairs.clone()],
            Some(three) => three.to_vec(),
        };
        let params = lists
            .iter()
            .map(|l| {
                let l: Vec<(&str, &str)> =
                    l.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
                Params::resolve(entry.info.id, entry.info.params, &l)
            })
            .collect::<Result<Vec<_>>>()?;
        // The given values, typed from what validation resolved.
        let given = pairs
            .iter()
            .map(|(name, text)| {
                let spec = entry
                    .info
                    .params
                    .iter()
                    .find(|s| s.name == name)
                    .expect("validated by Params::resolve");
                let value = if params.len() == 3 && text.contains(',') {
                    Given::Rgb(std::array::from_fn(|c| params[c].num(spec.name)))
                } else {
                    match params[0].get(spec.name) {
                        Some(Value::Num(x)) => Given::Num(*x),
                        Some(Value::Text(t)) => Given::Choice(t.clone()),
                        None => unreachable!("a given value is resolved"),
                    }
                };
                (spec.name, value)
            })
            .collect();
        let plans = params
            .iter()
            .map(|p| registry::plan_resolved(entry, p))
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            entry,
            given,
            params,
            plans,
        })
    }

    /// A spec from typed values (Python's numbers and sequences, a metal, a fit). Numbers are
    /// validated as [`ModelSpec::parse`] validates text (non-finite numbers are refused).
    pub fn new(id: &str, given: &[(&str, Given)]) -> Result<Self> {
        let text: Vec<(&str, String)> = given.iter().map(|(k, v)| (*k, v.to_string())).collect();
        let pairs: Vec<(&str, &str)> = text.iter().map(|(k, v)| (*k, v.as_str())).collect();
        Self::parse(id, &pairs)
    }

    /// The model's registry id.
    pub fn id(&self) -> &'static str {
        self.entry.info.id
    }

    /// The registry entry.
    pub fn entry(&self) -> &'static Entry {
        self.entry
    }

    /// The model's self-description (parameters, formula, bounds).
    pub fn info(&self) -> &'static ModelInfo {
        &self.entry.info
    }

    /// The model's kind.
    pub fn kind(&self) -> Kind {
        self.entry.info.kind
    }

    /// The values given, in the order given (defaults not included).
    pub fn given(&self) -> &[(&'static str, Given)] {
        &self.given
    }

    /// The value given for `name`, if any.
    pub fn get(&self, name: &str) -> Option<&Given> {
        self.given.iter().find(|(k, _)| *k == name).map(|(_, v)| v)
    }

    /// The given values as `(name, text)` pairs (`R,G,B` as `a,b,c`): for messages, labels
    /// and machine outputs.
    pub fn pairs(&self) -> Vec<(String, String)> {
        self.given
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    /// Whether the model takes a parameter `name`.
    pub fn takes(&self, name: &str) -> bool {
        self.entry.info.params.iter().any(|s| s.name == name)
    }

    /// Whether a value was given per colour channel (three channel models).
    pub fn is_coloured(&self) -> bool {
        self.params.len() == 3
    }

    /// The resolved parameters (defaults filled in) of each channel: one, or R, G, B.
    pub fn channels(&self) -> &[Params] {
        &self.params
    }

    /// The plan of each channel: one, or R, G, B.
    pub fn plans(&self) -> &[Plan] {
        &self.plans
    }

    /// The grey spec of each channel: itself when grey, else three specs with channel `c`'s
    /// number for every `R,G,B` value.
    pub fn channel_specs(&self) -> Vec<ModelSpec> {
        if !self.is_coloured() {
            return vec![self.clone()];
        }
        (0..3)
            .map(|c| Self {
                entry: self.entry,
                given: self
                    .given
                    .iter()
                    .map(|(k, v)| {
                        let v = match v {
                            Given::Rgb(rgb) => Given::Num(rgb[c]),
                            other => other.clone(),
                        };
                        (*k, v)
                    })
                    // A value the colour rule derived for every channel (`sheen_max`).
                    .chain(colour::derived(self.entry.info.params).filter_map(|name| {
                        let given = self.given.iter().any(|(k, _)| *k == name);
                        match self.params[c].get(name) {
                            Some(Value::Num(x)) if !given => Some((name, Given::Num(*x))),
                            _ => None,
                        }
                    }))
                    .collect(),
                params: vec![self.params[c].clone()],
                plans: vec![self.plans[c]],
            })
            .collect()
    }

    /// The resolved parameters of a grey model; an error naming the coloured parameters for a
    /// coloured one (use [`ModelSpec::channels`]).
    pub fn params(&self) -> Result<&Params> {
        self.grey()?;
        Ok(&self.params[0])
    }

    /// The plan of a grey model (coefficients computed once, in f64); an error for a coloured
    /// one (use [`ModelSpec::plans`]).
    pub fn plan(&self) -> Result<&Plan> {
        self.grey()?;
        Ok(&self.plans[0])
    }

    /// The scalar model of a grey model in precision `T`.
    pub fn model<T: Real>(&self) -> Result<Model<T>> {
        Ok(self.plan()?.model())
    }

    /// A coloured spec where one model is needed: refused naming the first value given per
    /// channel, as text, and its range (the message a grey model's parser gives such text).
    fn grey(&self) -> Result<()> {
        let Some((name, value)) = self.given.iter().find(|(_, v)| matches!(v, Given::Rgb(_)))
        else {
            return Ok(());
        };
        let range = self
            .entry
            .info
            .params
            .iter()
            .find(|s| s.name == *name)
            .map_or_else(String::new, |s| s.range_text());
        Err(Error::InvalidParam {
            model: self.id().into(),
            param: name.to_string(),
            value: value.to_string(),
            expected: format!(
                "a number in {range} (this use takes one model, not one per colour channel R,G,B)"
            ),
        })
    }

    /// The spec with `name` set to `value` (replacing a given value).
    pub fn with(&self, name: &str, value: Given) -> Result<Self> {
        let mut given: Vec<(&str, Given)> = self
            .given
            .iter()
            .filter(|(k, _)| *k != name)
            .map(|(k, v)| (*k, v.clone()))
            .collect();
        given.push((name, value));
        Self::new(self.id(), &given)
    }

    /// The spec with `defaults` added where no value was given (a material's or a metal's
    /// figures: given values win).
    pub fn with_defaults(&self, defaults: &[(&str, Given)]) -> Result<Self> {
        let mut given: Vec<(&str, Given)> =
            self.given.iter().map(|(k, v)| (*k, v.clone())).collect();
        for (k, v) in defaults {
            if self.get(k).is_none() {
                given.push((k, v.clone()));
            }
        }
        Self::new(self.id(), &given)
    }

    /// The BRDF that shading with this model evaluates, by its kind's policy
    /// (`Kind::shading`): BRDFs as they are, a lobe as `blinn-phong` with that lobe and
    /// `norm = none`, a distribution as `cook-torrance` with that `d` (the given values passed
    /// on); shadowing and Fresnel terms are an error. Both renderers and the BRDF Explorer
    /// export shade through it.
    pub fn shaded(&self) -> Result<Self> {
        match self.kind().shading() {
            Shading::AsIs => Ok(self.clone()),
            Shading::Via { brdf, param, extra } => {
                let mut given: Vec<(&str, Given)> =
                    self.given.iter().map(|(k, v)| (*k, v.clone())).collect();
                given.push((param, Given::Choice(self.id().into())));
                given.extend(
                    extra
                        .iter()
                        .map(|(k, v)| (*k, Given::Choice(v.to_string()))),
                );
                Self::new(brdf, &given)
            }
            Shading::Not => Err(Error::WrongKind {
                model: self.id().into(),
                expected: "a lobe, a distribution or a BRDF (something to shade with)".into(),
                found: self.kind().name().into(),
            }),
        }
    }

    /// The spec coloured by metal `m`: `f = conductor` (where the model has a Fresnel choice),
    /// `eta = R,G,B`, `k = R,G,B`, each unless given. A model without the conductor term's
    /// `eta` and `k` is an error naming it (shade a distribution through
    /// [`ModelSpec::shaded`] first).
    pub fn with_metal(&self, m: &Metal) -> Result<Self> {
        if !(self.takes("eta") && self.takes("k")) {
            return Err(Error::InvalidParam {
                model: self.id().into(),
                param: "eta, k".into(),
                value: m.id.into(),
                expected: "a model with the conductor Fresnel term's eta and k (metals colour \
                           cook-torrance, the distributions shaded as cook-torrance, and \
                           fresnel-conductor)"
                    .into(),
            });
        }
        let mut defaults = vec![("eta", Given::Rgb(m.eta)), ("k", Given::Rgb(m.k))];
        if self.takes("f") {
            defaults.insert(0, ("f", Given::Choice("conductor".into())));
        }
        self.with_defaults(&defaults)
    }

    /// Whether a numeric parameter's spec holds `value` (used by typed transformations that
    /// supply figures only where the model's documented range holds them).
    pub fn range_holds(&self, name: &str, value: f64) -> bool {
        self.entry.info.params.iter().any(|s| {
            s.name == name
                && matches!(s.kind, ParamKind::Number { min, max, .. } if value >= min && value <= max)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_typed_values_give_the_same_spec() {
        let a = ModelSpec::parse("cook-torrance", &[("alpha", "0.25"), ("f", "schlick")]).unwrap();
        let b = ModelSpec::new(
            "cook-torrance",
            &[
                ("alpha", Given::Num(0.25)),
                ("f", Given::Choice("schlick".into())),
            ],
        )
        .unwrap();
        assert_eq!(a, b);
        assert_eq!(a.to_string(), "cook-torrance alpha=0.25 f=schlick");
        assert_eq!(a.params().unwrap().num("alpha"), 0.25);
    }

    #[test]
    fn errors_name_model_parameter_and_value() {
        let e = ModelSpec::parse("flog", &[("n", "0")])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("flog") && e.contains('n') && e.contains('0'),
            "{e}"
        );
        let e = ModelSpec::parse("flog", &[("q", "1")]).unwrap_err();
        assert!(matches!(e, Error::UnknownParam { .. }), "{e}");
        let e = ModelSpec::new("flog", &[("n", Given::Num(f64::NAN))]).unwrap_err();
        assert!(matches!(e, Error::InvalidParam { .. }), "{e}");
        let e = ModelSpec::new("flog", &[("n", Given::Num(f64::INFINITY))]).unwrap_err();
        assert!(matches!(e, Error::InvalidParam { .. }), "{e}");
    }

    #[test]
    fn coloured_specs_split_into_grey_channels() {
        let s = ModelSpec::parse("cook-torrance", &[("f0", "0.9,0.6,0.5")]).unwrap();
        assert!(s.is_coloured() && s.plan().is_err() && s.plans().len() == 3);
        let ch = s.channel_specs();
        assert_eq!(ch[1].get("f0"), Some(&Given::Num(0.6)));
        assert!(!ch[2].is_coloured());
        let Err(e) = s.model::<f32>() else { panic!() };
        let msg = e.to_string();
        assert!(
            msg.contains("parameter f0 = 0.9,0.6,0.5 is invalid") && msg.contains("[0, 1]"),
            "{msg}"
        );
    }

    #[test]
    fn shading_and_metals_are_typed_transformations() {
        let d = ModelSpec::parse("ggx", &[("alpha", "0.2")]).unwrap();
        let s = d.shaded().unwrap();
        assert_eq!(s.id(), "cook-torrance");
        assert_eq!(s.get("d"), Some(&Given::Choice("ggx".into())));
        assert!(d.with_metal(colour::metal("gold").unwrap()).is_err());
        let gold = s.with_metal(colour::metal("gold").unwrap()).unwrap();
        assert!(gold.is_coloured());
        assert_eq!(gold.get("f"), Some(&Given::Choice("conductor".into())));
        let mine = s
            .with("eta", Given::Num(1.5))
            .unwrap()
            .with_metal(colour::metal("gold").unwrap())
            .unwrap();
        assert_eq!(mine.get("eta"), Some(&Given::Num(1.5)));
        let lobe = ModelSpec::parse("flog", &[]).unwrap().shaded().unwrap();
        assert_eq!(lobe.id(), "blinn-phong");
        assert!(
            ModelSpec::parse("fresnel-schlick", &[])
                .unwrap()
                .shaded()
                .is_err()
        );
    }
}
