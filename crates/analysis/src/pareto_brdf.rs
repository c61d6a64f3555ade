//! `fastbrdf pareto --brdf`: full specular BRDFs (`cook-torrance` with a distribution, a
//! shadowing term and a Fresnel term), exact and approximate, each with its measured SIMD cost
//! and its error against one exact reference configuration, in BRDF space and in image space,
//! and the Pareto front on (cost, error).
//!
//! - Cost: nanoseconds per evaluation of the batch kernel (`fastbrdf::batch::Kernel`) on 4096
//!   direction pairs, as `fastbrdf bench` measures ([`speed::time`], [`speed::Inputs`]): the
//!   fastest of repeated rounds, one core, measured in this run for every configuration and
//!   the reference, so `cost_ratio` compares numbers taken minutes apart on the same machine
//!   (one run; ratios move by about 10% between runs on a shared machine). Measured once per
//!   configuration at the first alpha (the kernels have no alpha-dependent branches).
//! - BRDF space: `g = f cos_i cos_o` (the BRDF with both cosine factors: what a light and a
//!   viewer see) on a product grid over pairs of hemisphere directions, midpoints uniform in
//!   `theta_i`, `theta_o` (weight `sin theta d theta`) and `phi_o - phi_i` uniform over
//!   `[0, 2 pi)` with an even count (every mirror pair `theta_o = theta_i`, `phi = pi` is a
//!   node, so the specular peak is sampled), evaluated in f64 by the scalar models (the model
//!   error, not the f32 rounding):
//!   - `max_rel_peak = max |g - g_ref| / max g_ref` over the grid;
//!   - `rms_rel = sqrt(integral (g - g_ref)^2) / sqrt(integral g_ref^2)` over pairs with the
//!     solid-angle measure `d omega_i d omega_o` (a relative L2 error; 0.05 is 5%);
//!   - `rms_abs = sqrt(integral (g - g_ref)^2 / (2 pi)^2)`, the same in absolute units.
//! - Image space: mean FLIP (NVIDIA's metric, `fastbrdf_render::compare::metrics`, 8-bit sRGB,
//!   67 pixels per degree) of a render of the built-in sphere, and of a mesh when given (the
//!   face), against the reference's render: `size` x `size` pixels, 1 sample per pixel,
//!   `kd = 0.5`, `ks = 1` (the Cook-Torrance term as it is: its Fresnel makes it weak at normal
//!   incidence and strong at grazing), the default key light.
//! - The front: the rows no other row of the same alpha dominates on (ns per evaluation,
//!   the chosen error, `rms_rel` by default).
//!
//! Roughness: `cook-torrance` has one `alpha`, passed to its D and its Smith terms, so Beckmann
//! and GGX configurations are compared at `alpha_beckmann = alpha_ggx` (the two
//! distributions' common convention: the same `alpha` gives lobes of similar width near the
//! peak; GGX's tail is longer).

use crate::speed;
use fastbrdf::batch::Kernel;
use fastbrdf::params::Value;
use fastbrdf::{Given, Kind, Model, ModelSpec, registry};
use fastbrdf_render::compare;
use fastbrdf_render::render::{self, Shading};
use fastbrdf_render::scene::Specular;
use fastbrdf_render::setup::{self, SceneSpec};
use rayon::prelude::*;
use serde::Serialize;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// One Cook-Torrance configuration: a `cook-torrance` spec without `alpha` (`d`, `g`, `f`,
/// and any of `f0`, `f90`, `eta`, `k`, `denominator`), grey; `alpha` is the sweep's
/// ([`Config::at`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub spec: ModelSpec,
}

impl Config {
    fn new(d: &str, g: &str, f: &str) -> Self {
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

/// The BRDF-space quadrature: `theta` midpoints per hemisphere angle, `phi` (even) azimuths.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Grid {
    pub theta: usize,
    pub phi: usize,
}

impl Grid {
    /// The default: 48 x 48 x 96 pairs (221184).
    pub const DEFAULT: Grid = Grid { theta: 48, phi: 96 };
    /// `--quick`: 16 x 16 x 32 pairs.
    pub const QUICK: Grid = Grid { theta: 16, phi: 32 };
}

/// `g = f cos_i cos_o` of `config` at `alpha` on the grid (f64, scalar model), in the order
/// theta_i, theta_o, phi; and the solid-angle weight of each node (`sin theta_i sin theta_o
/// d theta^2 d phi`, times `2 pi` for `phi_i`; they sum to about `(2 pi)^2`).
fn cosine_weighted(config: &Config, alpha: f64, grid: Grid) -> fastbrdf::Result<Vec<f64>> {
    let spec = config.at(alpha)?;
    // Built once to report a bad configuration; each row builds its own (Send-free models).
    spec.model::<f64>()?;
    let (nt, np) = (grid.theta, grid.phi.max(2) & !1);
    let dt = std::f64::consts::FRAC_PI_2 / nt as f64;
    let rows: Vec<Vec<f64>> = (0..nt)
        .into_par_iter()
        .map(|i| {
            let Ok(Model::Brdf(b)) = spec.model::<f64>() else {
                unreachable!("checked above")
            };
            let ti = (i as f64 + 0.5) * dt;
            let wi = [ti.sin(), 0.0, ti.cos()];
            let mut row = Vec::with_capacity(nt * np);
            for j in 0..nt {
                let to = (j as f64 + 0.5) * dt;
                let (so, co) = to.sin_cos();
                for k in 0..np {
                    let p = std::f64::consts::TAU * k as f64 / np as f64;
                    let wo = [so * p.cos(), so * p.sin(), co];
                    row.push(b.eval(wi, wo) * wi[2] * co);
                }
            }
            row
        })
        .collect();
    Ok(rows.concat())
}

fn weights(grid: Grid) -> Vec<f64> {
    let (nt, np) = (grid.theta, grid.phi.max(2) & !1);
    let dt = std::f64::consts::FRAC_PI_2 / nt as f64;
    let dp = std::f64::consts::TAU / np as f64;
    let mut w = Vec::with_capacity(nt * nt * np);
    for i in 0..nt {
        let si = ((i as f64 + 0.5) * dt).sin();
        for j in 0..nt {
            let sj = ((j as f64 + 0.5) * dt).sin();
            let x = si * sj * dt * dt * dp * std::f64::consts::TAU;
            w.extend(std::iter::repeat_n(x, np));
        }
    }
    w
}

/// BRDF-space errors of one configuration against the reference's values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BrdfError {
    pub max_rel_peak: f64,
    /// Where the maximum is: `theta_i`, `theta_o` and `phi_o - phi_i` in degrees.
    pub max_at_deg: [f64; 3],
    pub rms_rel: f64,
    pub rms_abs: f64,
}

/// The reference's `g = f cos_i cos_o` and the quadrature weights on a grid, computed once
/// per alpha.
pub struct Reference {
    pub grid: Grid,
    pub alpha: f64,
    values: Vec<f64>,
    weights: Vec<f64>,
    peak: f64,
    norm2: f64,
}

impl Reference {
    pub fn new(config: &Config, alpha: f64, grid: Grid) -> fastbrdf::Result<Self> {
        let values = cosine_weighted(config, alpha, grid)?;
        let weights = weights(grid);
        let peak = values.iter().copied().fold(0.0, f64::max);
        let norm2 = values.iter().zip(&weights).map(|(v, w)| w * v * v).sum();
        Ok(Self {
            grid,
            alpha,
            values,
            weights,
            peak,
            norm2,
        })
    }

    /// The errors of `config` against this reference (module documentation).
    pub fn error(&self, config: &Config) -> fastbrdf::Result<BrdfError> {
        let v = cosine_weighted(config, self.alpha, self.grid)?;
        let (mut max, mut at, mut sq) = (0.0f64, 0usize, 0.0f64);
        for (i, ((a, b), w)) in v.iter().zip(&self.values).zip(&self.weights).enumerate() {
            let d = a - b;
            if d.abs() > max {
                (max, at) = (d.abs(), i);
            }
            sq += w * d * d;
        }
        let (nt, np) = (self.grid.theta, self.grid.phi.max(2) & !1);
        let theta = |k: usize| (k as f64 + 0.5) * 90.0 / nt as f64;
        let max_at_deg = [
            theta(at / (nt * np)),
            theta(at / np % nt),
            (at % np) as f64 * 360.0 / np as f64,
        ];
        let total: f64 = self.weights.iter().sum();
        Ok(BrdfError {
            max_rel_peak: max / self.peak,
            max_at_deg,
            rms_rel: (sq / self.norm2).sqrt(),
            rms_abs: (sq / total).sqrt(),
        })
    }
}

/// Seconds per evaluation of `config`'s batch kernel at `alpha` on 4096 direction pairs (as
/// `fastbrdf bench`), and whether the kernel is fully SIMD (an exact Beckmann Smith term calls
/// libm's `erfc` per lane).
pub fn cost(
    config: &Config,
    alpha: f64,
    inputs: &speed::Inputs,
    budget: Duration,
) -> fastbrdf::Result<(f64, bool)> {
    let k = Kernel::from_spec(&config.at(alpha)?)?;
    let n = inputs.dirs[0].len();
    let input = inputs.input(Kind::Brdf, n);
    let mut out = vec![0.0f32; n];
    let t = speed::time(|| k.eval(input, &mut out).expect("sizes match"), budget);
    Ok((t / n as f64, k.simd()))
}

/// The renders compared in image space: the sphere, and a mesh when given.
pub struct Images {
    pub size: u32,
    sphere: (SceneSpec, setup::Loaded),
    mesh: Option<(SceneSpec, setup::Loaded)>,
}

impl Images {
    /// Loads the mesh (if any) once.
    pub fn new(size: u32, mesh: Option<PathBuf>) -> fastbrdf_render::Result<Self> {
        let spec = |mesh: Option<PathBuf>| SceneSpec {
            mesh,
            kd: 0.5,
            ks: 1.0,
            // Shadows (issue 15) only mask the same pixels in every configuration's picture;
            // off, the FLIP figures stay those of README's table (BRDF error alone).
            shadows: false,
            ..SceneSpec::new()
        };
        let sphere = spec(None);
        let sphere_loaded = setup::load(&sphere)?;
        let mesh = match mesh {
            Some(p) => {
                let s = spec(Some(p));
                let l = setup::load(&s)?;
                Some((s, l))
            }
            None => None,
        };
        Ok(Self {
            size,
            sphere: (sphere, sphere_loaded),
            mesh,
        })
    }

    /// The sRGB 8-bit renders of `config` at `alpha`: the sphere, then the mesh if any.
    pub fn render(&self, config: &Config, alpha: f64) -> fastbrdf_render::Result<Vec<Vec<u8>>> {
        let specular = Arc::new(Specular::new(&config.at(alpha)?)?);
        let opts = render::Options {
            width: self.size,
            height: self.size,
            spp: 1,
            shading: Shading::Batch,
        };
        let mut out = Vec::new();
        for (spec, loaded) in std::iter::once(&self.sphere).chain(self.mesh.as_ref()) {
            let scene = setup::scene(spec, loaded, specular.clone());
            let film = render::render(&scene, &opts, &|_, _| {})?;
            film.check_finite()?;
            out.push(film.to_srgb8(1.0));
        }
        Ok(out)
    }

    /// Mean FLIP of each render against the reference's.
    pub fn flip(&self, reference: &[Vec<u8>], test: &[Vec<u8>]) -> Vec<f64> {
        reference
            .iter()
            .zip(test)
            .map(|(r, t)| compare::metrics("", r, t, self.size, self.size).flip)
            .collect()
    }
}

/// Which error the front is taken on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrontOn {
    Max,
    Rms,
    FlipSphere,
}

impl FrontOn {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "max" => Some(Self::Max),
            "rms" => Some(Self::Rms),
            "flip" => Some(Self::FlipSphere),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Self::Max => "max_rel_peak",
            Self::Rms => "rms_rel",
            Self::FlipSphere => "flip_sphere",
        }
    }
    fn of(self, r: &Row) -> f64 {
        match self {
            Self::Max => r.max_rel_peak,
            Self::Rms => r.rms_rel,
            Self::FlipSphere => r.flip_sphere.unwrap_or(f64::NAN),
        }
    }
}

/// A spec's given values as `[[NAME, VALUE], ...]`, in the order given, each value a JSON
/// number where it is one (`["eta", 1.5]`), else the choice's name: machine outputs carry
/// numbers (issue 27).
pub fn params_pairs_json(spec: &ModelSpec) -> serde_json::Value {
    pairs_json(&spec.pairs())
}

fn pairs_json(pairs: &[(String, String)]) -> serde_json::Value {
    pairs
        .iter()
        .map(|(k, v)| serde_json::json!([k, crate::text_json(v)]))
        .collect()
}

fn ser_pairs<S: serde::Serializer>(p: &[(String, String)], s: S) -> Result<S::Ok, S::Error> {
    pairs_json(p).serialize(s)
}

/// One configuration at one alpha.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub label: String,
    pub d: String,
    pub g: String,
    pub f: String,
    pub denominator: String,
    /// Every parameter given (besides alpha), name and value (JSON: `[NAME, VALUE]` pairs, a
    /// value a number where it is one).
    #[serde(serialize_with = "ser_pairs")]
    pub params: Vec<(String, String)>,
    pub alpha: f64,
    /// The reference configuration itself.
    pub reference: bool,
    /// Whether the whole kernel is SIMD (false: an exact Beckmann Smith term, libm erfc per lane).
    pub simd: bool,
    /// Nanoseconds per evaluation, batch kernel, 4096 direction pairs, one core.
    pub ns_per_eval: f64,
    /// `ns_per_eval` over the reference's, measured in the same run.
    pub cost_ratio: f64,
    pub max_rel_peak: f64,
    /// Where the maximum is: `theta_i`, `theta_o` and `phi_o - phi_i` in degrees.
    pub max_at_deg: [f64; 3],
    pub rms_rel: f64,
    pub rms_abs: f64,
    /// Mean FLIP of the sphere render against the reference's.
    pub flip_sphere: Option<f64>,
    /// Mean FLIP of the mesh (face) render, when a mesh was given.
    pub flip_mesh: Option<f64>,
    /// On the Pareto front of its alpha.
    pub pareto: bool,
}

/// What to compute.
pub struct Options {
    pub reference: Config,
    pub configs: Vec<Config>,
    pub alphas: Vec<f64>,
    pub grid: Grid,
    /// The time budget of each cost measurement.
    pub budget: Duration,
    /// Image-space comparison (none: no FLIP columns).
    pub images: Option<Images>,
    pub front_on: FrontOn,
    /// Costs saved by an earlier run (`--costs`: label, ns per evaluation, SIMD) instead of
    /// measuring; every configuration must have one.
    pub saved_costs: Option<Vec<(String, f64, bool)>>,
}

/// The costs of a saved `pareto --brdf --json` output (`rows[].label`, `ns_per_eval`, `simd`;
/// the first row of each label).
pub fn saved_costs(json: &serde_json::Value) -> Result<Vec<(String, f64, bool)>, String> {
    let rows = json["rows"]
        .as_array()
        .ok_or("no \"rows\" array: not a `pareto --brdf --json` output")?;
    rows.iter()
        .map(|r| {
            match (
                r["label"].as_str(),
                r["ns_per_eval"].as_f64(),
                r["simd"].as_bool(),
            ) {
                (Some(l), Some(ns), Some(simd)) => Ok((l.to_string(), ns * 1e-9, simd)),
                _ => Err("a row lacks label, ns_per_eval or simd".to_string()),
            }
        })
        .collect()
}

/// The steps `run` reports to `progress` (one per configuration and alpha, plus one per
/// configuration's timing).
pub fn steps(o: &Options) -> usize {
    let n = o.configs.len() + 1;
    n + n * o.alphas.len()
}

/// Every row, grouped by alpha (in the order given), cheapest first within each, the front
/// marked per alpha. The reference is always a row (added when the list lacks it).
pub fn run(o: &Options, progress: &dyn Fn()) -> Result<Vec<Row>, String> {
    let mut configs = vec![o.reference.clone()];
    configs.extend(o.configs.iter().filter(|c| **c != o.reference).cloned());
    let alpha0 = o.alphas.first().copied().unwrap_or(0.3);
    let inputs = speed::Inputs::new(4096);
    let mut costs = Vec::with_capacity(configs.len());
    for c in &configs {
        let label = c.label();
        costs.push(match &o.saved_costs {
            Some(saved) => saved
                .iter()
                .find(|(l, _, _)| *l == label)
                .map(|&(_, t, simd)| (t, simd))
                .ok_or_else(|| format!("the saved costs lack '{label}'"))?,
            None => cost(c, alpha0, &inputs, o.budget).map_err(|e| e.to_string())?,
        });
        progress();
    }
    let ref_ns = costs[0].0;
    let mut rows = Vec::new();
    for &alpha in &o.alphas {
        let reference = Reference::new(&o.reference, alpha, o.grid).map_err(|e| e.to_string())?;
        let ref_images = match &o.images {
            Some(im) => Some(im.render(&o.reference, alpha).map_err(|e| e.to_string())?),
            None => None,
        };
        let mut group = Vec::new();
        for (c, &(t, simd)) in configs.iter().zip(&costs) {
            let e = reference.error(c).map_err(|e| e.to_string())?;
            let flips = match (&o.images, &ref_images) {
                (Some(im), Some(r)) => {
                    let t = im.render(c, alpha).map_err(|e| e.to_string())?;
                    im.flip(r, &t)
                }
                _ => vec![],
            };
            group.push(Row {
                label: c.label(),
                d: c.get("d"),
                g: c.get("g"),
                f: c.get("f"),
                denominator: c.get("denominator"),
                params: c.spec.pairs(),
                alpha,
                reference: *c == o.reference,
                simd,
                ns_per_eval: t * 1e9,
                cost_ratio: t / ref_ns,
                max_rel_peak: e.max_rel_peak,
                max_at_deg: e.max_at_deg,
                rms_rel: e.rms_rel,
                rms_abs: e.rms_abs,
                flip_sphere: flips.first().copied(),
                flip_mesh: flips.get(1).copied(),
                pareto: false,
            });
            progress();
        }
        mark_front(&mut group, o.front_on);
        rows.extend(group);
    }
    Ok(rows)
}

/// Marks the rows no other row dominates on (ns per evaluation, the chosen error): at least as
/// good on both and better on one. Then sorts them cheapest first. Rows with an unknown
/// error are never on the front.
pub fn mark_front(rows: &mut [Row], on: FrontOn) {
    for i in 0..rows.len() {
        let (ci, ei) = (rows[i].ns_per_eval, on.of(&rows[i]));
        rows[i].pareto = ei.is_finite()
            && !rows.iter().enumerate().any(|(j, r)| {
                let (cj, ej) = (r.ns_per_eval, on.of(r));
                j != i && cj <= ci && ej <= ei && (cj < ci || ej < ei)
            });
    }
    rows.sort_by(|a, b| a.ns_per_eval.total_cmp(&b.ns_per_eval));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(d: &str, g: &str, f: &str) -> Config {
        Config::new(d, g, f)
    }

    #[test]
    fn the_reference_has_zero_error_against_itself() {
        let r = Reference::new(&default_reference(), 0.3, Grid::QUICK).unwrap();
        let e = r.error(&default_reference()).unwrap();
        assert_eq!(
            e,
            BrdfError {
                max_rel_peak: 0.0,
                max_at_deg: [90.0 / 32.0, 90.0 / 32.0, 0.0],
                rms_rel: 0.0,
                rms_abs: 0.0
            }
        );
        assert!(r.peak > 0.0 && r.norm2 > 0.0);
        // The weights integrate the pair measure: (2 pi)^2 within the midpoint rule's error.
        let total: f64 = r.weights.iter().sum();
        let want = std::f64::consts::TAU.powi(2);
        assert!((total / want - 1.0).abs() < 2e-3, "{total} vs {want}");
    }

    #[test]
    fn a_finer_power_is_closer_to_the_power_it_approximates() {
        // (1 + x/g)^g tends to exp(x) as g grows: the power forms tend to `beckmann-pow`'s
        // cos^(2/m^2 - 4) (same normalisation, same G and F: only D differs), monotonically.
        let r = Reference::new(&cfg("beckmann-pow", "smith", "schlick"), 0.3, Grid::QUICK).unwrap();
        let e = |d| r.error(&cfg(d, "smith", "schlick")).unwrap();
        let (p4, p8, p16) = (
            e("beckmann-power4"),
            e("beckmann-power8"),
            e("beckmann-power16"),
        );
        assert!(
            p16.rms_rel < p8.rms_rel && p8.rms_rel < p4.rms_rel,
            "{p4:?} {p8:?} {p16:?}"
        );
        assert!(p16.max_rel_peak < p8.max_rel_peak && p8.max_rel_peak < p4.max_rel_peak);
        assert!(p16.rms_rel > 0.0);
        // Not so against the exact Beckmann: cos^(2/m^2) is itself an approximation of
        // exp(-tan^2/m^2), and at alpha = 0.3 the coarser powers' error partly cancels its
        // error (measured: power8 closest, power16 furthest). The pi/4 scale of the seeds'
        // normalisation against the energy-normalised `beckmann` is exact.
        let r = Reference::new(&cfg("beckmann", "smith", "schlick"), 0.3, Grid::QUICK).unwrap();
        let e = |d| r.error(&cfg(d, "smith", "schlick")).unwrap();
        let ct = e("beckmann-ct").rms_rel;
        assert!(
            (ct - (1.0 - std::f64::consts::FRAC_PI_4)).abs() < 1e-9,
            "{ct}"
        );
    }

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

    #[test]
    fn the_front_is_per_error_and_cheapest_first() {
        let row = |label: &str, ns: f64, rms: f64| Row {
            label: label.into(),
            d: String::new(),
            g: String::new(),
            f: String::new(),
            denominator: String::new(),
            params: vec![],
            alpha: 0.3,
            reference: false,
            simd: true,
            ns_per_eval: ns,
            cost_ratio: 1.0,
            max_rel_peak: 1.0 - rms,
            max_at_deg: [0.0; 3],
            rms_rel: rms,
            rms_abs: rms,
            flip_sphere: None,
            flip_mesh: None,
            pareto: false,
        };
        let mut rows = vec![
            row("exact", 10.0, 0.0),
            row("cheap", 1.0, 0.5),
            row("dominated", 5.0, 0.6),
            row("middle", 5.0, 0.1),
        ];
        mark_front(&mut rows, FrontOn::Rms);
        let on: Vec<&str> = rows
            .iter()
            .filter(|r| r.pareto)
            .map(|r| r.label.as_str())
            .collect();
        assert_eq!(on, ["cheap", "middle", "exact"]);
        mark_front(&mut rows, FrontOn::FlipSphere);
        assert!(rows.iter().all(|r| !r.pareto));
    }
}
