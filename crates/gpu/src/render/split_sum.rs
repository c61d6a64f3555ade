//! The split-sum shortcut (Karis 2013) under environment light, the engines' way of shading a
//! GGX surface with an environment map without sampling it, as a GPU shading mode to compare
//! with the sampled picture ([`render_split_sum`]):
//!
//! - diffuse: `base E(n) / pi`, the irradiance at the normal from a prefiltered map;
//! - specular: `ks L_pre(r, alpha) (f0 scale(n.v, alpha) + bias(n.v, alpha))`, `r` the mirror
//!   direction, `L_pre` the map prefiltered by the GGX lobe with `n = v = r` (Karis's
//!   assumption), and `scale`, `bias` the split-sum terms of an environment model's WGSL twin
//!   (`env-brdf`, the reference by quadrature, or `env-brdf-approx`, Karis's mobile fit, or
//!   its tuned constants), spliced into the module as `rd_dfg`.
//!
//! No shadow rays (engines have none for the environment either), no passes: one draw. The
//! difference from the sampled render of the same GGX model (`cook-torrance d=ggx
//! g=smith-ggx-correlated f=schlick`) is the shortcut's error: its split of the integral, its
//! `n = v` lobe, the prefiltered maps' resolution and, with an approximate model, its DFG
//! fit's (`tests/render_env.rs` measures it).
//!
//! # The prefiltered maps ([`Prefiltered`])
//!
//! Computed on the CPU, `1 + GGX_LEVELS` latitude-longitude maps of [`PRE_WIDTH`] x
//! [`PRE_HEIGHT`] texels stacked top to bottom in one `Rgba32Float` texture (group 3,
//! binding 3): level 0 the irradiance over pi, `sum L(l) max(n.l, 0) dw / pi`; level 1 + k
//! the GGX-prefiltered radiance of `alpha_k = (k / (GGX_LEVELS - 1))^2` (k = 0: the map
//! itself, box-filtered to the level's size), `sum L(l) D(h) max(r.l, 0) dw / sum D(h)
//! max(r.l, 0) dw` with `h = normalize(r + l)`, both as sums over the map's texels filtered to
//! (or, for a smaller map, repeated at) [`SOURCE_WIDTH`] x `SOURCE_WIDTH / 2` (solid-angle
//! weighted). The shader reads them
//! bilinearly (texel centres; wrapping in longitude), linearly between the two levels around
//! `sqrt(alpha)`.

use crate::context::GpuError;
use crate::spec::Instance;
use fastbrdf::ModelSpec;
use fastbrdf::model::Kind;
use fastbrdf_render::env::{EnvMap, uv_to_dir};
use fastbrdf_render::film::Film;
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::Scene;
use glam::Vec3;
use std::f32::consts::PI;

/// Each prefiltered level's size.
pub const PRE_WIDTH: u32 = 64;
pub const PRE_HEIGHT: u32 = 32;
/// The GGX levels (roughness `sqrt(alpha)` 0, 0.2, ..., 1).
pub const GGX_LEVELS: u32 = 6;
/// The width of the map the sums run over (a larger map is box-filtered to it).
pub const SOURCE_WIDTH: u32 = 128;

/// The prefiltered maps of an environment (see the module's header), as plain data: what the
/// native renderer uploads, and a browser likewise (group 3, binding 3).
#[derive(Clone, Debug, PartialEq)]
pub struct Prefiltered {
    /// One level's size ([`PRE_WIDTH`] x [`PRE_HEIGHT`]).
    pub width: u32,
    pub height: u32,
    /// Levels: 1 (irradiance / pi) + [`GGX_LEVELS`].
    pub levels: u32,
    /// `width x (height x levels)` texels, RGBA f32 (A = 1), level after level.
    pub texels_rgba32f: Vec<f32>,
}

/// The `alpha` of GGX level `k` (0 to `GGX_LEVELS - 1`).
pub fn level_alpha(k: u32) -> f32 {
    let r = k as f32 / (GGX_LEVELS - 1) as f32;
    r * r
}

/// `texels` (w x h, row-major) filtered to tw x th: each target texel the solid-angle weighted
/// mean of the source texels whose centres fall in it; where none does (a smaller source),
/// the source texel at its centre.
fn resample(texels: &[Vec3], (w, h): (u32, u32), (tw, th): (u32, u32)) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; (tw * th) as usize];
    let mut weight = vec![0.0f32; (tw * th) as usize];
    for r in 0..h {
        let st = (PI * (r as f32 + 0.5) / h as f32).sin();
        let tr = ((r as f32 + 0.5) / h as f32 * th as f32) as u32;
        for c in 0..w {
            let tc = ((c as f32 + 0.5) / w as f32 * tw as f32) as u32;
            let i = (tr.min(th - 1) * tw + tc.min(tw - 1)) as usize;
            sum[i] += texels[(r * w + c) as usize] * st;
            weight[i] += st;
        }
    }
    (0..(tw * th) as usize)
        .map(|i| {
            if weight[i] > 0.0 {
                sum[i] / weight[i]
            } else {
                let (c, r) = (i as u32 % tw, i as u32 / tw);
                let sc = ((c as f32 + 0.5) / tw as f32 * w as f32) as u32;
                let sr = ((r as f32 + 0.5) / th as f32 * h as f32) as u32;
                texels[(sr.min(h - 1) * w + sc.min(w - 1)) as usize]
            }
        })
        .collect()
}

/// The unit directions at the texel centres of a w x h map, and their solid angles.
fn centres(w: u32, h: u32) -> Vec<(Vec3, f32)> {
    let dw = (2.0 * PI / w as f32) * (PI / h as f32);
    (0..w * h)
        .map(|i| {
            let (c, r) = (i % w, i / w);
            let (d, st) = uv_to_dir((c as f32 + 0.5) / w as f32, (r as f32 + 0.5) / h as f32);
            (d, dw * st)
        })
        .collect()
}

impl Prefiltered {
    /// The prefiltered maps of `map`.
    pub fn new(map: &EnvMap) -> Self {
        let texels: Vec<Vec3> = map.texels().map(|(t, _)| t).collect();
        let (w, h) = (map.width, map.height);
        // A smaller map is read at the finer grid too (its texels repeated), so that the
        // sums over directions are as fine as for a large one.
        let src_size = (SOURCE_WIDTH, SOURCE_WIDTH / 2);
        let src = resample(&texels, (w, h), src_size);
        let src_dirs = centres(src_size.0, src_size.1);
        let out_dirs = centres(PRE_WIDTH, PRE_HEIGHT);
        let mut levels: Vec<Vec<Vec3>> = Vec::with_capacity(1 + GGX_LEVELS as usize);
        // Irradiance / pi.
        levels.push(
            out_dirs
                .iter()
                .map(|&(n, _)| {
                    let mut e = Vec3::ZERO;
                    for (&(l, dw), &le) in src_dirs.iter().zip(&src) {
                        let c = n.dot(l);
                        if c > 0.0 {
                            e += le * (c * dw);
                        }
                    }
                    e / PI
                })
                .collect(),
        );
        // The map itself, then GGX lobes.
        levels.push(resample(&texels, (w, h), (PRE_WIDTH, PRE_HEIGHT)));
        for k in 1..GGX_LEVELS {
            let a2 = level_alpha(k) * level_alpha(k);
            levels.push(
                out_dirs
                    .iter()
                    .map(|&(r, _)| {
                        let (mut sum, mut norm) = (Vec3::ZERO, 0.0f32);
                        for (&(l, dw), &le) in src_dirs.iter().zip(&src) {
                            let c = r.dot(l);
                            if c <= 0.0 {
                                continue;
                            }
                            let hn = (r + l).normalize().dot(r);
                            let q = hn * hn * (a2 - 1.0) + 1.0;
                            let wgt = a2 / (PI * q * q) * c * dw;
                            sum += le * wgt;
                            norm += wgt;
                        }
                        if norm > 0.0 { sum / norm } else { Vec3::ZERO }
                    })
                    .collect(),
            );
        }
        let texels_rgba32f = levels
            .iter()
            .flatten()
            .flat_map(|t| [t.x, t.y, t.z, 1.0])
            .collect();
        Self {
            width: PRE_WIDTH,
            height: PRE_HEIGHT,
            levels: 1 + GGX_LEVELS,
            texels_rgba32f,
        }
    }
}

/// The split-sum mode of one render: the environment model giving `scale` and `bias`, and the
/// scene's GGX roughness and f0.
#[derive(Clone, Debug)]
pub struct SplitSum {
    /// An environment model (`Kind::Env`: `env-brdf`, `env-brdf-approx`, ...).
    pub dfg: ModelSpec,
    pub alpha: f32,
    pub f0: f32,
}

/// `rd_dfg` where no split-sum is drawn (the sampled mode's module).
pub const DFG_STUB: &str =
    "fn rd_dfg(cos_v: f32, alpha: f32) -> vec2<f32> {\n    return vec2<f32>(0.0);\n}\n";

impl SplitSum {
    /// The split-sum of `scene` with the environment model `dfg`: its `alpha` and `f0` are
    /// those of the specular models of its objects with a specular term, which must all be
    /// the same GGX microfacet model with Schlick's Fresnel (`cook-torrance d=ggx f=schlick`,
    /// the BRDF the split-sum terms integrate).
    pub fn for_scene(scene: &Scene, dfg: &ModelSpec) -> Result<Self, GpuError> {
        if dfg.info().kind != Kind::Env {
            return Err(GpuError::Input(format!(
                "'{}' is not a split-sum model (env-brdf, env-brdf-approx, env-brdf-approx-tuned)",
                dfg.id()
            )));
        }
        let mut found: Option<(f32, f32)> = None;
        for o in scene.objects.iter().filter(|o| o.material.ks > 0.0) {
            let spec = &o.material.specular;
            let bad = || {
                GpuError::Input(format!(
                    "the split-sum shortcut needs cook-torrance with d=ggx and f=schlick (the BRDF \
                     its terms integrate); the scene's specular model is '{}'",
                    spec.id
                ))
            };
            let brdf = spec.brdf.as_ref().ok_or_else(bad)?;
            let p = brdf.params().map_err(|_| bad())?;
            if brdf.id() != "cook-torrance" || p.choice("d") != "ggx" || p.choice("f") != "schlick"
            {
                return Err(bad());
            }
            let af = (p.num("alpha") as f32, p.num("f0") as f32);
            if found.is_some_and(|f| f != af) {
                return Err(GpuError::Input(
                    "the split-sum shortcut takes one alpha and f0 for the scene: its objects differ"
                        .into(),
                ));
            }
            found = Some(af);
        }
        let (alpha, f0) = found.unwrap_or((1.0, 0.0));
        Ok(Self {
            dfg: dfg.clone(),
            alpha,
            f0,
        })
    }

    /// The WGSL of `rd_dfg` for a module whose other code is `module` ([`dfg_glue`]).
    pub fn glue(&self, module: &str) -> Result<String, GpuError> {
        dfg_glue(&self.dfg, module)
    }
}

/// The WGSL of `rd_dfg(cos_v, alpha) -> vec2<f32>` (scale, bias) for a module whose other
/// code is `module`: the environment model `dfg`'s twin for each term (renamed
/// `rd_dfg_scale`, `rd_dfg_bias`) and the library items they need that `module` lacks (so
/// that no item is declared twice).
pub fn dfg_glue(dfg: &ModelSpec, module: &str) -> Result<String, GpuError> {
    if dfg.info().kind != Kind::Env {
        return Err(GpuError::Input(format!(
            "'{}' is not a split-sum model (env-brdf, env-brdf-approx, env-brdf-approx-tuned)",
            dfg.id()
        )));
    }
    let mut wrappers = String::new();
    for term in ["scale", "bias"] {
        let spec = ModelSpec::parse(dfg.id(), &[("term", term)])
            .map_err(|e| GpuError::Input(e.to_string()))?;
        let inst = Instance::new(&spec)?;
        wrappers.push_str(&inst.wrapper.replace(
            &format!("fn {}(", inst.function),
            &format!("fn rd_dfg_{term}("),
        ));
    }
    let present = crate::library::closure(module);
    let need = crate::library::closure(&wrappers);
    let items = crate::library::texts_of(&need.difference(&present).cloned().collect());
    Ok(format!(
        "{}\n{wrappers}\nfn rd_dfg(cos_v: f32, alpha: f32) -> vec2<f32> {{\n    return vec2<f32>(rd_dfg_scale(cos_v, alpha), rd_dfg_bias(cos_v, alpha));\n}}\n",
        items.join("\n")
    ))
}

/// Renders `scene` under its environment with the split-sum shortcut (see the module's
/// header), `dfg` the environment model giving its terms; direct lights and the background as
/// in [`super::render`]. Errors: those of [`super::render`], a scene without an environment,
/// a `dfg` that is not an environment model, and specular models other than one GGX
/// cook-torrance with Schlick's Fresnel.
pub fn render_split_sum(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    opts: &Options,
    dfg: &ModelSpec,
) -> Result<Film, GpuError> {
    if scene.environment.is_none() {
        return Err(GpuError::Input(
            "the split-sum shortcut needs an environment (--env)".into(),
        ));
    }
    let split = SplitSum::for_scene(scene, dfg)?;
    super::render_scene(device, queue, scene, opts, None, Some(&split), &|_, _| {})
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf_render::env::EnvMap;

    /// A constant map prefilters to itself at every level, and its irradiance over pi is the
    /// constant (the sums are normalised, the solid angles sum to 4 pi).
    #[test]
    fn a_constant_map_prefilters_to_itself() {
        let p = Prefiltered::new(&EnvMap::constant(Vec3::splat(2.0)));
        assert_eq!(p.levels, 1 + GGX_LEVELS);
        assert_eq!(
            p.texels_rgba32f.len(),
            (4 * PRE_WIDTH * PRE_HEIGHT * p.levels) as usize
        );
        for t in p.texels_rgba32f.chunks_exact(4) {
            assert!((t[0] - 2.0).abs() < 0.01, "{t:?}");
        }
        assert_eq!(level_alpha(0), 0.0);
        assert_eq!(level_alpha(GGX_LEVELS - 1), 1.0);
    }

    /// The sky's sun spreads with roughness: the brightest texel of each GGX level falls as
    /// alpha grows, and stays towards the sun.
    #[test]
    fn rougher_levels_spread_the_sun() {
        let p = Prefiltered::new(&EnvMap::sky());
        let n = (PRE_WIDTH * PRE_HEIGHT) as usize;
        let peak = |level: usize| {
            let t = &p.texels_rgba32f[4 * n * level..4 * n * (level + 1)];
            t.chunks_exact(4)
                .enumerate()
                .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
                .map(|(i, t)| (i, t[0]))
                .unwrap()
        };
        let sun = Vec3::from(fastbrdf_render::env::SUN_DIR).normalize();
        let mut last = f32::INFINITY;
        for level in 1..=GGX_LEVELS as usize {
            let (i, v) = peak(level);
            assert!(v < last, "level {level}: peak {v} after {last}");
            last = v;
            let (d, _) = centres(PRE_WIDTH, PRE_HEIGHT)[i];
            assert!(d.dot(sun) > 0.9, "level {level}: peak towards {d}");
        }
    }
}
