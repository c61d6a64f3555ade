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
//!
//! Files: [`config`] (the configurations, the default list and `--all`), [`brdf_space`] (the
//! grid and the BRDF-space errors), [`images`] (the renders and their FLIP); this file holds
//! the cost, the rows, the front and the run.

mod brdf_space;
mod config;
mod images;

pub use brdf_space::{BrdfError, Grid, Reference};
pub use config::{
    ALL_LEAVES_OUT, Config, all_configurations, all_count, all_fresnel, configurations,
    default_reference,
};
pub use images::Images;

use crate::speed;
use fastbrdf::batch::Kernel;
use fastbrdf::{Kind, ModelSpec};
use serde::Serialize;
use std::time::Duration;

/// Seconds per evaluation of `config`'s batch kernel at `alpha` on 4096 direction pairs (as
/// `fastbrdf bench`), and whether the kernel is fully SIMD (an exact Beckmann Smith term calls
/// libm's `erfc` per lane).
pub fn cost(
    config: &Config,
    alpha: f64,
    inputs: &speed::Inputs,
    budget: Duration,
) -> fastbrdf::Result<(f64, bool)> {
    let k = Kernel::new(&config.at(alpha)?)?;
    let n = inputs.dirs[0].len();
    let input = inputs.input(Kind::Brdf, n);
    let mut out = vec![0.0f32; n];
    let t = speed::time(|| k.eval(input, &mut out).expect("sizes match"), budget);
    Ok((t / n as f64, k.simd()))
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

impl Grid {
    /// `THETAxPHI` (`48x96`): theta midpoints (2 to 512) and even azimuth counts (2 to 1024).
    /// The message starts with the text (the caller names the argument before it).
    pub fn parse(text: &str) -> Result<Grid, String> {
        let bad = || {
            format!(
                "{}: expected THETAxPHI, theta 2 to 512, phi even, 2 to 1024",
                fastbrdf_io::shorten(text, 40)
            )
        };
        let (t, p) = text.split_once('x').ok_or_else(bad)?;
        let (theta, phi): (usize, usize) = (
            t.trim().parse().map_err(|_| bad())?,
            p.trim().parse().map_err(|_| bad())?,
        );
        if !(2..=512).contains(&theta) || !(2..=1024).contains(&phi) || phi % 2 != 0 {
            return Err(bad());
        }
        Ok(Grid { theta, phi })
    }
}

/// `fastbrdf pareto --brdf --json`'s object: `{reference, reference_label, alphas, grid, size,
/// spp, mesh, front_on, rows}` (the CLI and the Python package print this one value). `size`
/// is the render side used (0: no renders), `mesh` the mesh file as given.
pub fn json(o: &Options, rows: &[Row], size: u32, mesh: Option<&str>) -> serde_json::Value {
    serde_json::json!({
        "reference": params_pairs_json(&o.reference.spec),
        "reference_label": o.reference.label(),
        "alphas": o.alphas,
        "grid": o.grid,
        "size": size,
        "spp": 1,
        "mesh": mesh,
        "front_on": o.front_on.name(),
        "rows": rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
