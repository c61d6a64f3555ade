//! Parameter specifications (name, range or choices, default) and their validation.
//! The same names are used by the library, the CLI (`--param NAME=VALUE`) and, later, WGSL.

use crate::error::{Error, Result};
use crate::kind::Kind;
use serde::Serialize;
use std::collections::BTreeMap;

/// What values a parameter takes. JSON (`fastbrdf models --json`): `{"type": "number", min,
/// max, default, requires (when not empty)}` or `{"type": "choice", options, default}`, and
/// for a choice whose default follows another ([`Follow`]) `"default_follows": {"param",
/// "defaults": {value of param: default}}`.
#[derive(Clone, Copy, Debug)]
pub enum ParamKind {
    /// A real number in `[min, max]`. `default: None` means "optional" (see the doc line).
    /// `requires`: choice parameters that must hold one of the listed values when this one is
    /// given (`cook-torrance`'s `alpha_x`, `alpha_y` need a distribution and a shadowing term
    /// with an anisotropic form): `Params::resolve` refuses the rest naming them, and
    /// `accuracy`'s configuration lists give it only where they hold ([`ParamSpec::allowed`]).
    /// The required parameters come before this one in the model's list.
    Number {
        min: f64,
        max: f64,
        default: Option<f64>,
        requires: Requires,
    },
    /// One of a set of names.
    Choice {
        options: Options,
        default: &'static str,
    },
}

/// Choice parameters and the values one of which each must hold (see [`ParamKind::Number`]).
pub type Requires = &'static [(&'static str, &'static [&'static str])];

/// The names a choice parameter takes.
#[derive(Clone, Copy, Debug)]
pub enum Options {
    /// A fixed list.
    List(&'static [&'static str]),
    /// Any model of a kind, by id without `prefix` (`cook-torrance`'s `f`: `fresnel-`): the
    /// registry replaces it by the list of its ids of that kind (`registry::all`), so that a
    /// new model is a choice without a second list to keep; with `follow`, by
    /// [`Options::Follows`] (the default depends on another choice).
    Models {
        kind: Kind,
        prefix: &'static str,
        follow: Option<Follow>,
    },
    /// A fixed list whose options other than the parameter's default need other choice
    /// parameters at given values (`cook-torrance`'s `ms` needs `d = ggx` and
    /// `g = smith-ggx-correlated`; a part's choice reached through its composite, such as
    /// `schlick-ggx`'s `remap` in `cook-torrance`, needs `g = schlick-ggx`):
    /// `Params::resolve` refuses the rest with an error naming them, and `accuracy`'s
    /// configuration lists leave them out. The required parameters come before this one in
    /// the model's list.
    Gated {
        list: &'static [&'static str],
        requires: Requires,
    },
    /// A fixed list whose default, when the parameter is not given, follows another choice
    /// parameter ([`Follow`]: `cook-torrance`'s `g` is the Smith term of the distribution
    /// `d` names). What the registry makes of `Models` with a `follow`.
    Follows {
        list: &'static [&'static str],
        follow: Follow,
    },
}

/// A default that depends on another choice parameter: where `param` holds one of the first
/// names of `defaults`, the default is the paired name, else the parameter's own `default`.
/// `param` comes before the parameter in the model's list. Given values always win.
#[derive(Clone, Copy, Debug)]
pub struct Follow {
    pub param: &'static str,
    pub defaults: &'static [(&'static str, &'static str)],
}

impl Follow {
    /// The default beside `other` (the value of `param`), `None` where `defaults` has no pair.
    pub fn default_for(&self, other: &str) -> Option<&'static str> {
        self.defaults
            .iter()
            .find(|(k, _)| *k == other)
            .map(|(_, v)| *v)
    }
}

impl Options {
    /// The names (empty for an unresolved `Models`: only the registry's copies are resolved).
    pub fn names(&self) -> &'static [&'static str] {
        match *self {
            Options::List(l)
            | Options::Gated { list: l, .. }
            | Options::Follows { list: l, .. } => l,
            Options::Models { .. } => &[],
        }
    }
    /// The rule that moves the default with another choice, if any.
    pub fn follow(&self) -> Option<Follow> {
        match *self {
            Options::Follows { follow, .. } => Some(follow),
            Options::Models { follow, .. } => follow,
            _ => None,
        }
    }
    /// Whether option `name` (of a parameter whose default is `default`) is allowed beside the
    /// other choices `other(param)` (see [`Options::Gated`]).
    pub fn allows(
        &self,
        name: &str,
        default: &str,
        other: impl Fn(&str) -> Option<String>,
    ) -> bool {
        match *self {
            Options::Gated { requires, .. } if name != default => requires
                .iter()
                .all(|(p, vals)| other(p).is_some_and(|v| vals.contains(&v.as_str()))),
            _ => true,
        }
    }
}

impl Serialize for ParamKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        match *self {
            ParamKind::Number {
                min,
                max,
                default,
                requires,
            } => {
                m.serialize_entry("type", "number")?;
                m.serialize_entry("min", &min)?;
                m.serialize_entry("max", &max)?;
                m.serialize_entry("default", &default)?;
                if !requires.is_empty() {
                    m.serialize_entry("requires", requires)?;
                }
            }
            ParamKind::Choice { options, default } => {
                m.serialize_entry("type", "choice")?;
                m.serialize_entry("options", &options)?;
                m.serialize_entry("default", default)?;
                if let Some(f) = options.follow() {
                    let defaults: BTreeMap<&str, &str> = f.defaults.iter().copied().collect();
                    m.serialize_entry(
                        "default_follows",
                        &json_shape::Follows {
                            param: f.param,
                            defaults,
                        },
                    )?;
                }
            }
        }
        m.end()
    }
}

/// The shape of `default_follows` in JSON.
mod json_shape {
    use serde::Serialize;
    use std::collections::BTreeMap;
    #[derive(Serialize)]
    pub struct Follows<'a> {
        pub param: &'a str,
        pub defaults: BTreeMap<&'a str, &'a str>,
    }
}

impl Serialize for Options {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.names().serialize(s)
    }
}

/// One parameter of a model.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ParamSpec {
    pub name: &'static str,
    #[serde(flatten)]
    pub kind: ParamKind,
    pub doc: &'static str,
}

impl ParamSpec {
    /// The default as text (`-` when optional).
    pub fn default_text(&self) -> String {
        match self.kind {
            ParamKind::Number {
                default: Some(d), ..
            } => fmt_num(d),
            ParamKind::Number { default: None, .. } => "-".into(),
            ParamKind::Choice { default, .. } => default.into(),
        }
    }
    /// `(min, max)` of a numeric parameter (panics for a choice: a programming error).
    pub const fn range(&self) -> (f64, f64) {
        match self.kind {
            ParamKind::Number { min, max, .. } => (min, max),
            ParamKind::Choice { .. } => panic!("range() of a choice parameter"),
        }
    }
    /// Whether this parameter may be given beside the choices `other(param)`: a numeric
    /// parameter's `requires` hold (always true for a choice; gated choices are checked per
    /// option by [`Options::allows`]).
    pub fn allowed(&self, other: impl Fn(&str) -> Option<String>) -> bool {
        match self.kind {
            ParamKind::Number { requires, .. } => requires
                .iter()
                .all(|(p, vals)| other(p).is_some_and(|v| vals.contains(&v.as_str()))),
            ParamKind::Choice { .. } => true,
        }
    }
    /// The range or the choices as text.
    pub fn range_text(&self) -> String {
        match self.kind {
            ParamKind::Number { min, max, .. } => format!("[{}, {}]", fmt_num(min), fmt_num(max)),
            ParamKind::Choice { options, .. } => options.names().join("|"),
        }
    }
}

fn fmt_num(x: f64) -> String {
    format!("{x}")
}

/// The largest specular exponent (issue 14: published Blinn-Phong fits of the MERL materials
/// reach 1.2e5; 40 of 86 are above 1000).
pub const N_MAX: f64 = 100000.0;
/// The smallest microfacet slope (issue 14: Beckmann fits of the MERL materials reach 0.005).
pub const ALPHA_MIN: f64 = 0.005;

/// The specular exponent of every lobe.
pub const N: ParamSpec = ParamSpec {
    name: "n",
    kind: ParamKind::Number {
        min: 1.0,
        max: N_MAX,
        default: Some(20.0),
        requires: &[],
    },
    doc: "specular exponent",
};

/// The microfacet slope parameter of distributions, shadowing and Ward.
pub const ALPHA: ParamSpec = ParamSpec {
    name: "alpha",
    kind: ParamKind::Number {
        min: ALPHA_MIN,
        max: 1.0,
        default: Some(0.3),
        requires: &[],
    },
    doc: "RMS microfacet slope m",
};

/// The slope along x of an anisotropic microfacet surface (`ward`; `cook-torrance` gates its
/// copy: [`ParamKind::Number`]'s `requires`). Optional: given with [`ALPHA_Y`], it replaces
/// `alpha` ([`slope_params`]).
pub const ALPHA_X: ParamSpec = ParamSpec {
    name: "alpha_x",
    kind: ParamKind::Number {
        min: ALPHA_MIN,
        max: 1.0,
        default: None,
        requires: &[],
    },
    doc: "anisotropic slope along x (with alpha_y; replaces alpha)",
};
/// The slope along y (see [`ALPHA_X`]).
pub const ALPHA_Y: ParamSpec = ParamSpec {
    name: "alpha_y",
    kind: ParamKind::Number {
        min: ALPHA_MIN,
        max: 1.0,
        default: None,
        requires: &[],
    },
    doc: "anisotropic slope along y (with alpha_x; replaces alpha)",
};

/// The names of the parameters that hold the slopes along x and y of an anisotropic model
/// (`ward`, `cook-torrance`): `alpha_x`, `alpha_y` when both are given, else `alpha` twice;
/// one without the other is an error naming the missing one. Shared by the scalar models, the
/// batch kernels and the GPU twins (all build from the plan this chooses).
pub fn slope_params(p: &Params) -> Result<(&'static str, &'static str)> {
    let missing = |param: &str| Error::MissingParam {
        model: p.model().into(),
        param: param.into(),
    };
    match (p.opt_num("alpha_x"), p.opt_num("alpha_y")) {
        (Some(_), Some(_)) => Ok(("alpha_x", "alpha_y")),
        (None, None) => Ok(("alpha", "alpha")),
        (Some(_), None) => Err(missing("alpha_y")),
        (None, Some(_)) => Err(missing("alpha_x")),
    }
}

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Num(f64),
    Text(String),
}

/// Validated parameters of one model: every spec'd parameter that has a value or a default.
#[derive(Clone, Debug)]
pub struct Params {
    model: &'static str,
    values: BTreeMap<&'static str, Value>,
}

impl Params {
    /// Validates `given` (name, value-as-text pairs) against `specs` and fills in defaults.
    /// Errors name the parameter, the value and what was expected.
    pub fn resolve(
        model: &'static str,
        specs: &[ParamSpec],
        given: &[(&str, &str)],
    ) -> Result<Self> {
        let mut values = BTreeMap::new();
        for (name, text) in given {
            let spec = spec_of(model, specs, name)?;
            if values.contains_key(spec.name) {
                return Err(Error::InvalidParam {
                    model: model.into(),
                    param: spec.name.into(),
                    value: (*text).into(),
                    expected: "a single value (it was given twice)".into(),
                });
            }
            values.insert(spec.name, parse(model, spec, text)?);
        }
        for spec in specs {
            if values.contains_key(spec.name) {
                continue;
            }
            match spec.kind {
                ParamKind::Number {
                    default: Some(d), ..
                } => {
                    values.insert(spec.name, Value::Num(d));
                }
                ParamKind::Choice { default, options } => {
                    // A default that follows another choice (cook-torrance's g follows d),
                    // which comes earlier in the list and so is already filled in.
                    let follows = options.follow().and_then(|f| match values.get(f.param) {
                        Some(Value::Text(t)) => f.default_for(t),
                        _ => None,
                    });
                    values.insert(spec.name, Value::Text(follows.unwrap_or(default).into()));
                }
                ParamKind::Number { default: None, .. } => {}
            }
        }
        let p = Self { model, values };
        let choice = |n: &str| match p.values.get(n) {
            Some(Value::Text(t)) => Some(t.clone()),
            _ => None,
        };
        // A parameter that needs other choices (a gated choice's non-default value, an
        // optional number such as cook-torrance's alpha_x): refused naming what it needs and
        // what was given.
        let refuse = |spec: &ParamSpec, value: String, need: Vec<String>, names: Vec<&str>| {
            let given: Vec<String> = names
                .iter()
                .map(|n| format!("{n} = {}", p.choice(n)))
                .collect();
            let unless = match spec.kind {
                ParamKind::Choice { default, .. } => default.to_string(),
                ParamKind::Number { .. } => "no value".to_string(),
            };
            Err(Error::InvalidParam {
                model: model.into(),
                param: spec.name.into(),
                value,
                expected: format!(
                    "{unless} unless {} (given {})",
                    need.join(" and "),
                    given.join(", ")
                ),
            })
        };
        // A gated choice's need: "d = ggx" for one value, "g in {a, b}" for several.
        let need = |n: &str, vals: &[&str]| match vals {
            [v] => format!("{n} = {v}"),
            _ => format!("{n} in {{{}}}", vals.join(", ")),
        };
        for spec in specs {
            match spec.kind {
                ParamKind::Number { requires, .. }
                    if p.values.contains_key(spec.name) && !spec.allowed(choice) =>
                {
                    return refuse(
                        spec,
                        p.num(spec.name).to_string(),
                        requires
                            .iter()
                            .map(|(n, vals)| format!("{n} in {{{}}}", vals.join(", ")))
                            .collect(),
                        requires.iter().map(|(n, _)| *n).collect(),
                    );
                }
                ParamKind::Choice {
                    options: options @ Options::Gated { requires, .. },
                    default,
                } if !options.allows(p.choice(spec.name), default, choice) => {
                    return refuse(
                        spec,
                        p.choice(spec.name).into(),
                        requires.iter().map(|(n, vals)| need(n, vals)).collect(),
                        requires.iter().map(|(n, _)| *n).collect(),
                    );
                }
                _ => {}
            }
        }
        Ok(p)
    }

    /// Validates numeric parameters given as numbers (a composite model's parts: Phong's
    /// lobe at its `n`, Cook-Torrance's D at its `alpha`) and fills in defaults.
    pub fn resolve_nums(
        model: &'static str,
        specs: &[ParamSpec],
        given: &[(&str, f64)],
    ) -> Result<Self> {
        let mut p = Self::resolve(model, specs, &[])?;
        for (name, x) in given {
            let spec = spec_of(model, specs, name)?;
            p.values
                .insert(spec.name, Value::Num(check(model, spec, *x)?));
        }
        Ok(p)
    }

    /// Validates values given as [`Value`]s (a composite's values handed to its parts:
    /// `cook-torrance`'s `alpha` and `remap` to `g`) and fills in defaults, as
    /// [`Params::resolve`] (numbers are written in Rust's shortest round-trip form, so they
    /// arrive unchanged; non-finite ones are refused).
    pub fn resolve_values(
        model: &'static str,
        specs: &[ParamSpec],
        given: &[(&str, Value)],
    ) -> Result<Self> {
        let text: Vec<(&str, String)> = given
            .iter()
            .map(|(n, v)| match v {
                Value::Num(x) => (*n, format!("{x}")),
                Value::Text(t) => (*n, t.clone()),
            })
            .collect();
        let pairs: Vec<(&str, &str)> = text.iter().map(|(n, t)| (*n, t.as_str())).collect();
        Self::resolve(model, specs, &pairs)
    }

    /// A resolved value (given, or its default), `None` for an unknown name or an optional
    /// number not given.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.values.get(name)
    }

    /// The model these parameters belong to.
    pub fn model(&self) -> &'static str {
        self.model
    }

    /// A numeric parameter (its default when not given).
    ///
    /// # Panics
    /// When the model has no such numeric parameter with a default: a bug in the model file.
    pub fn num(&self, name: &str) -> f64 {
        self.opt_num(name)
            .unwrap_or_else(|| panic!("{}: no numeric parameter {name}", self.model))
    }

    /// An optional numeric parameter.
    pub fn opt_num(&self, name: &str) -> Option<f64> {
        match self.values.get(name) {
            Some(Value::Num(x)) => Some(*x),
            _ => None,
        }
    }

    /// A choice parameter (its default when not given).
    ///
    /// # Panics
    /// When the model has no such choice parameter: a bug in the model file.
    pub fn choice(&self, name: &str) -> &str {
        match self.values.get(name) {
            Some(Value::Text(s)) => s,
            _ => panic!("{}: no choice parameter {name}", self.model),
        }
    }

    /// Every resolved value, for display.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &Value)> {
        self.values.iter().map(|(k, v)| (*k, v))
    }
}

/// The spec of parameter `name`, or an error naming the model.
fn spec_of<'a>(model: &str, specs: &'a [ParamSpec], name: &str) -> Result<&'a ParamSpec> {
    specs
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| Error::UnknownParam {
            model: model.into(),
            param: name.into(),
        })
}

fn parse(model: &'static str, spec: &ParamSpec, text: &str) -> Result<Value> {
    let invalid = |expected: String| Error::InvalidParam {
        model: model.into(),
        param: spec.name.into(),
        value: text.into(),
        expected,
    };
    match spec.kind {
        ParamKind::Number { min, max, .. } => {
            let x: f64 = text
                .trim()
                .parse()
                .map_err(|_| invalid(format!("a number in [{min}, {max}]")))?;
            if !(x >= min && x <= max) {
                return Err(invalid(format!("a number in [{min}, {max}]")));
            }
            Ok(Value::Num(x))
        }
        ParamKind::Choice { options, .. } => {
            let t = text.trim();
            if options.names().contains(&t) {
                Ok(Value::Text(t.into()))
            } else {
                Err(invalid(format!("one of {}", options.names().join(", "))))
            }
        }
    }
}

/// Checks a typed constructor argument against its spec (for the typed `new` functions,
/// which bypass [`Params::resolve`]).
pub fn check(model: &'static str, spec: &ParamSpec, x: f64) -> Result<f64> {
    parse(model, spec, &format!("{x}"))
        .map(|_| x)
        .and_then(|_| {
            if x.is_finite() {
                Ok(x)
            } else {
                Err(Error::InvalidParam {
                    model: model.into(),
                    param: spec.name.into(),
                    value: format!("{x}"),
                    expected: spec.range_text(),
                })
            }
        })
}
