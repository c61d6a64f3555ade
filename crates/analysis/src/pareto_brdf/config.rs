//! The configurations compared: a Cook-Torrance spec without `alpha` each, the default list
//! and `--all` (every distribution x shadowing term x Fresnel term, counted from the registry).

use fastbrdf::params::Value;
use fastbrdf::{Given, Kind, ModelSpec, registry};

/// One Cook-Torrance configuration: a `cook-torrance` spec without `alpha` (`d`, `g`, `f`,
/// and any of `f0`, `f90`, `eta`, `k`, `denominator`), grey; `alpha` is the sweep's
/// ([`Config::at`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub spec: ModelSpec,
}

impl Config {
    pub(super) fn new(d: &str, g: &str, f: &str) -> Self {
        let choice = |v: &str| Given::Choice(v.into());
        let mut given = vec![("d", choice(d)), ("g", choice(g)), ("f", choice(f))];
        if f == "dielectric" {
            given.push(("eta", Given::Num(1.5)));
        }
        let spec = ModelSpec::new("cook-torrance", &given)
            .unwrap_or_else(|e| panic!("a registered cook-torrance configuration: {e}"));
        Self { spec }
    }

    fn with(self, name: &str, value: Given) -> Self {
        let spec = self
            .spec
            .with(name, value)
            .unwrap_or_else(|e| panic!("a registered cook-torrance configuration: {e}"));
        Self { spec }
    }

    /// A configuration from a spec: `cook-torrance`, grey, without `alpha` (it is the
    /// sweep's).
    pub fn from_spec(spec: &ModelSpec) -> fastbrdf::Result<Self> {
        let bad = |param: &str, value: String, expected: &str| fastbrdf::Error::InvalidParam {
            model: spec.id().into(),
            param: param.into(),
            value,
            expected: expected.into(),
        };
        if spec.id() != "cook-torrance" {
            return Err(fastbrdf::Error::WrongKind {
                model: spec.id().into(),
                expected: "cook-torrance (a configuration is its d, g, f and their values)".into(),
                found: spec.kind().name().into(),
            });
        }
        if let Some(a) = spec.get("alpha") {
            return Err(bad(
                "alpha",
                a.to_string(),
                "no alpha in a configuration: --alpha sets it",
            ));
        }
        spec.plan()?;
        Ok(Self { spec: spec.clone() })
    }

    /// `d=ggx,g=smith-ggx-correlated,f=dielectric,eta=1.5`: Cook-Torrance parameters, parsed
    /// and checked as a spec (`alpha` is refused: it is the sweep's).
    pub fn parse(text: &str) -> fastbrdf::Result<Self> {
        let mut params = Vec::new();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (k, v) = item
                .split_once('=')
                .ok_or_else(|| fastbrdf::Error::InvalidParam {
                    model: "cook-torrance".into(),
                    param: fastbrdf_io::shorten(item, 40),
                    value: String::new(),
                    expected: "NAME=VALUE".into(),
                })?;
            if k.trim() == "alpha" {
                return Err(fastbrdf::Error::InvalidParam {
                    model: "cook-torrance".into(),
                    param: "alpha".into(),
                    value: fastbrdf_io::shorten(v, 40),
                    expected: "no alpha in a configuration: --alpha sets it".into(),
                });
            }
            params.push((k.trim(), v.trim()));
        }
        Self::from_spec(&ModelSpec::parse("cook-torrance", &params)?)
    }

    /// A parameter's value as text, given or cook-torrance's default for it (empty for a
    /// number without a default).
    pub fn get(&self, name: &str) -> String {
        if let Some(v) = self.spec.get(name) {
            return v.to_string();
        }
        match self.spec.channels()[0].get(name) {
            Some(Value::Num(x)) => crate::range::num(*x),
            Some(Value::Text(t)) => t.clone(),
            None => String::new(),
        }
    }

    /// `d / g / f`, then any other parameter given as `name=value`.
    pub fn label(&self) -> String {
        let mut s = format!("{} / {} / {}", self.get("d"), self.get("g"), self.get("f"));
        for (k, v) in self.spec.pairs() {
            if !matches!(k.as_str(), "d" | "g" | "f") {
                s.push_str(&format!(" {k}={v}"));
            }
        }
        s
    }

    /// The configuration at roughness `alpha`.
    pub fn at(&self, alpha: f64) -> fastbrdf::Result<ModelSpec> {
        self.spec.with("alpha", Given::Num(alpha))
    }
}

/// The default reference: GGX, the height-correlated Smith-GGX term and the exact dielectric
/// Fresnel at eta = 1.5 (f0 = 0.04, what `schlick` and `schlick-sg` take by default).
pub fn default_reference() -> Config {
    Config::new("ggx", "smith-ggx-correlated", "dielectric")
}

/// The Fresnel terms `--all` leaves out: `none` (no Fresnel term: not a configuration anyone
/// shades with) and `conductor` (a metal's complex index; the reference is a dielectric).
pub const ALL_LEAVES_OUT: [&str; 2] = ["none", "conductor"];

/// The Fresnel terms of `--all`: every one cook-torrance's `f` takes (the registry's Fresnel
/// terms) but [`ALL_LEAVES_OUT`], in registry order.
pub fn all_fresnel() -> Vec<&'static str> {
    registry::ids_of(Kind::Fresnel)
        .into_iter()
        .filter_map(|id| id.strip_prefix("fresnel-"))
        .filter(|f| !ALL_LEAVES_OUT.contains(f))
        .collect()
}

/// How many configurations `--all` takes: distributions x shadowing terms x [`all_fresnel`]
/// (counted from the registry without building them: what `pareto --brdf --help` states).
pub fn all_count() -> usize {
    registry::ids_of(Kind::Distribution).len()
        * registry::ids_of(Kind::Shadowing).len()
        * all_fresnel().len()
}

/// The configurations of `--all`: every distribution x every shadowing term x every
/// [`all_fresnel`] term (`eta = 1.5` with the exact dielectric), denominator 4.
pub fn all_configurations() -> Vec<Config> {
    let fs = all_fresnel();
    let mut v = Vec::new();
    for d in registry::ids_of(Kind::Distribution) {
        for g in registry::ids_of(Kind::Shadowing) {
            for f in &fs {
                v.push(Config::new(d, g, f));
            }
        }
    }
    v
}

/// The configurations of the table. The default list varies one part at a time from the
/// reference and then covers the seeds' Beckmann forms (`all` = false):
/// - the Fresnel terms on exact GGX with the correlated Smith term;
/// - every GGX-style shadowing term (and the V-cavity) with GGX and Schlick;
/// - the cheapest engine form (GGX, `smith-ggx-correlated-fast`, `schlick-sg`);
/// - every Beckmann form (`beckmann`, `beckmann-ct`, `beckmann-pow`, `beckmann-power4/8/16`)
///   with the exact Smith term, its rational approximation and the V-cavity, Schlick's F;
///   `beckmann` with the correlated Smith term and with the exact dielectric;
/// - seed 000 as printed (`beckmann-ct` or `beckmann-power16`, V-cavity, Schlick,
///   denominator `cos_i cos_o`).
///
/// `all`: [`all_configurations`].
pub fn configurations(all: bool) -> Vec<Config> {
    if all {
        return all_configurations();
    }
    let mut v = Vec::new();
    for f in ["dielectric", "schlick", "schlick-sg", "schlick-sg-tuned"] {
        v.push(Config::new("ggx", "smith-ggx-correlated", f));
    }
    for g in [
        "smith-ggx",
        "smith-ggx-correlated-fast",
        "smith-ggx-joint-approx",
        "schlick-ggx",
        "kelemen",
        "neumann",
        "v-cavity",
    ] {
        v.push(Config::new("ggx", g, "schlick"));
    }
    v.push(Config::new(
        "ggx",
        "smith-ggx-correlated-fast",
        "schlick-sg",
    ));
    v.push(Config::new("beckmann", "smith", "dielectric"));
    v.push(Config::new(
        "beckmann",
        "smith-beckmann-correlated",
        "schlick",
    ));
    for d in [
        "beckmann",
        "beckmann-ct",
        "beckmann-pow",
        "beckmann-power4",
        "beckmann-power8",
        "beckmann-power16",
    ] {
        for g in ["smith", "smith-rational", "v-cavity"] {
            v.push(Config::new(d, g, "schlick"));
        }
    }
    for d in ["beckmann-ct", "beckmann-power16"] {
        v.push(
            Config::new(d, "v-cavity", "schlick")
                .with("denominator", Given::Choice("seed-000".into())),
        );
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations_parse_label_and_refuse_alpha() {
        let c = Config::parse("d=ggx, g=smith-ggx-correlated,f=dielectric,eta=1.5").unwrap();
        assert_eq!(c, default_reference());
        assert_eq!(c.label(), "ggx / smith-ggx-correlated / dielectric eta=1.5");
        assert_eq!(
            Config::parse("").unwrap().label(),
            "beckmann / smith / none"
        );
        assert_eq!(Config::parse("f=schlick").unwrap().get("denominator"), "4");
        assert!(Config::parse("alpha=0.2").is_err());
        assert!(Config::parse("d=nope").is_err());
        assert!(Config::parse("ggx").is_err());
        let list = configurations(false);
        assert!(list.contains(&default_reference()));
        assert!(list.iter().any(|c| c.get("denominator") == "seed-000"));
        for c in &list {
            c.at(0.3).unwrap().model::<f32>().unwrap();
        }
        assert_eq!(configurations(true), all_configurations());
    }

    /// `--all`'s count is the registry's, never a number written by hand (issue 28: the help
    /// said 308 after the Charlie parts made it larger): every distribution x every shadowing
    /// term x every Fresnel term cook-torrance's `f` takes but `none` and `conductor`, each
    /// configuration distinct and valid, and [`all_count`] (what the help prints) agrees.
    #[test]
    fn all_takes_every_part_of_the_registry_and_counts_it() {
        let info = &registry::find("cook-torrance").unwrap().info;
        let choices = |name: &str| -> Vec<&'static str> {
            let p = info.params.iter().find(|p| p.name == name).unwrap();
            match p.kind {
                fastbrdf::params::ParamKind::Choice { options, .. } => options.names().to_vec(),
                fastbrdf::params::ParamKind::Number { .. } => panic!("{name} is a choice"),
            }
        };
        let ds = registry::ids_of(Kind::Distribution);
        let gs = registry::ids_of(Kind::Shadowing);
        let fs: Vec<&str> = choices("f")
            .into_iter()
            .filter(|f| !["none", "conductor"].contains(f))
            .collect();
        assert_eq!(
            choices("d"),
            ds,
            "cook-torrance's d takes every distribution"
        );
        assert_eq!(
            choices("g"),
            gs,
            "cook-torrance's g takes every shadowing term"
        );
        for f in ["dielectric", "schlick", "schlick-sg", "schlick-sg-tuned"] {
            assert!(fs.contains(&f), "{f} in {fs:?}");
        }
        let all = all_configurations();
        assert_eq!(all.len(), ds.len() * gs.len() * fs.len());
        assert_eq!(all_count(), all.len());
        eprintln!(
            "--all: {} distributions x {} shadowing terms x {} Fresnel terms = {}",
            ds.len(),
            gs.len(),
            fs.len(),
            all.len()
        );
        let mut labels: Vec<String> = all.iter().map(Config::label).collect();
        labels.sort();
        labels.dedup();
        assert_eq!(labels.len(), all.len(), "configurations are distinct");
        for d in &ds {
            for g in &gs {
                for f in &fs {
                    assert!(
                        all.iter()
                            .any(|c| c.get("d") == *d && c.get("g") == *g && c.get("f") == *f),
                        "{d} {g} {f}"
                    );
                }
            }
        }
        for c in &all {
            c.at(0.3).unwrap().model::<f32>().unwrap();
        }
    }
}
