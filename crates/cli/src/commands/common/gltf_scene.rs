//! `--scene FILE` of `render` and `compare`: a glTF scene read once (its warnings on stderr),
//! rendered with its materials as `gltf-pbr` (the `--param` values and an approximation set's
//! choices given to every material), and a comparison of approximation sets against the
//! materials as written, with difference maps, scores and each set's time per pixel.

use super::pictures::Scores;
use super::progress::bar;
use crate::CliError;
use fastbrdf_render::compare::{self, Cell};
use fastbrdf_render::env::EnvMap;
use fastbrdf_render::film::Film;
use fastbrdf_render::gltf::{self, GltfScene};
use fastbrdf_render::render::{Options, render};
use fastbrdf_render::setup::SceneSpec;
use std::path::Path;
use std::sync::Arc;

/// A scene and its environment map, read once.
pub struct Loaded {
    pub scene: GltfScene,
    pub env: Option<Arc<EnvMap>>,
}

/// Reads the scene (its warnings printed to stderr, `warning: FILE: ...`) and the
/// environment map of `spec`.
pub fn load(path: &Path, spec: &SceneSpec) -> Result<Loaded, CliError> {
    let scene = gltf::load(path)?;
    for w in &scene.warnings {
        eprintln!("warning: {}: {w}", scene.file);
    }
    let env = spec
        .env
        .as_deref()
        .map(EnvMap::from_spec)
        .transpose()?
        .map(|m| Arc::new(spec.env_sun.apply(m)));
    Ok(Loaded { scene, env })
}

/// Renders the scene with `overrides` given to every material; returns the film and the
/// seconds the render took: with `timed`, the least of renders repeated until
/// [`TIMING_SECONDS`] have passed (at most [`TIMING_RENDERS`]), so that a small picture's time
/// is not one thread start-up's noise.
pub fn render_scene(
    l: &Loaded,
    spec: &SceneSpec,
    opts: &Options,
    overrides: &[(String, String)],
    what: &'static str,
    timed: bool,
) -> Result<(Film, f64), CliError> {
    let specs = l.scene.specs(overrides)?;
    let scene = l.scene.scene(spec, l.env.clone(), &specs)?;
    let pb = bar(1, what);
    let start = std::time::Instant::now();
    let mut best = f64::INFINITY;
    let mut film = None;
    for _ in 0..if timed { TIMING_RENDERS } else { 1 } {
        let t = std::time::Instant::now();
        let f = render(&scene, opts, &|d, t| {
            pb.set_length(t as u64);
            pb.set_position(d as u64);
        })?;
        best = best.min(t.elapsed().as_secs_f64());
        film.get_or_insert(f);
        if start.elapsed().as_secs_f64() > TIMING_SECONDS {
            break;
        }
    }
    pb.finish_and_clear();
    let film = film.expect("rendered once");
    film.check_finite()
        .map_err(|e| CliError::input(format!("--scene {}: {e}", l.scene.file)))?;
    Ok((film, best))
}

/// A timed render is repeated until this many seconds have passed...
pub const TIMING_SECONDS: f64 = 0.25;
/// ... or it was rendered this many times.
pub const TIMING_RENDERS: usize = 5;

/// `NAME=VALUE,NAME=VALUE` (an approximation set): pairs; a piece without `=` continues the
/// previous value (`base_color=1,0.5,0` is one pair).
pub fn parse_set(s: &str) -> Result<Vec<(String, String)>, CliError> {
    let mut out: Vec<(String, String)> = Vec::new();
    for piece in s.split(',') {
        match piece.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => {
                out.push((k.trim().into(), v.trim().into()));
            }
            None if !out.is_empty() => {
                let last = out.last_mut().expect("not empty");
                last.1 = format!("{},{}", last.1, piece.trim());
            }
            _ => {
                return Err(CliError::input(format!(
                    "--set '{}': expected NAME=VALUE[,NAME=VALUE...], e.g. g=smith-ggx-correlated-fast,f=schlick-sg",
                    fastbrdf_io::shorten(s, 60)
                )));
            }
        }
    }
    Ok(out)
}

/// One approximation set's result.
pub struct SetResult {
    pub label: String,
    pub scores: Scores,
    pub ns_per_pixel: f64,
    /// Shading alone: nanoseconds per BRDF evaluation ([`shading_cost`]).
    pub ns_per_eval: f64,
}

/// Direction pairs of [`shading_cost`].
pub const COST_PAIRS: usize = 1 << 14;

/// The cost of shading alone, steadier than a small render's time: nanoseconds per BRDF
/// evaluation (all channels of a coloured material), averaged over the scene's materials,
/// each evaluated by its batch kernels (one thread) on [`COST_PAIRS`] fixed direction pairs
/// of the upper hemisphere, the least of 3 runs.
pub fn shading_cost(l: &Loaded, overrides: &[(String, String)]) -> Result<f64, CliError> {
    let n = COST_PAIRS;
    let mut cols: [Vec<f32>; 6] = Default::default();
    for k in 0..n {
        // A low-discrepancy spread of both directions (golden-ratio sequences).
        let (u, v) = ((k as f32 * 0.618_034).fract(), (k as f32 + 0.5) / n as f32);
        let (w, x) = (
            (k as f32 * 0.754_878).fract(),
            (k as f32 * 0.569_840).fract(),
        );
        for (base, (a, b)) in [(0, (u, v)), (3, (w, x))] {
            let (s, c) = (2.0 * std::f32::consts::PI * a).sin_cos();
            let z = 0.05 + 0.95 * b;
            let r = (1.0 - z * z).sqrt();
            cols[base].push(r * c);
            cols[base + 1].push(r * s);
            cols[base + 2].push(z);
        }
    }
    let input = [
        &cols[0][..],
        &cols[1],
        &cols[2],
        &cols[3],
        &cols[4],
        &cols[5],
    ];
    let mut out = vec![0.0f32; n];
    let specs = l.scene.specs(overrides)?;
    let mut total = 0.0;
    for spec in &specs {
        let sp = fastbrdf_render::scene::Specular::new(spec)?;
        let mut best = f64::INFINITY;
        for _ in 0..3 {
            let t = std::time::Instant::now();
            for ch in &sp.channels {
                ch.kernel
                    .eval(fastbrdf::batch::Input::Dirs(input), &mut out)
                    .map_err(fastbrdf_render::RenderError::from)?;
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        std::hint::black_box(&out);
        total += best * 1e9 / n as f64;
    }
    Ok(total / specs.len().max(1) as f64)
}

/// A comparison's grid picture (8-bit sRGB, `width` x `height`), the reference's time per
/// pixel and each set's result.
pub struct Comparison {
    pub rgb: Vec<u8>,
    pub width: u32,
    pub height: u32,
    pub reference_ns_per_pixel: f64,
    pub reference_ns_per_eval: f64,
    pub sets: Vec<SetResult>,
}

/// The comparison: the reference (the materials as written, with `common`) and each set
/// (`common` then the set's pairs).
pub fn compare_sets(
    l: &Loaded,
    spec: &SceneSpec,
    opts: &Options,
    exposure: f32,
    common: &[(String, String)],
    sets: &[(String, Vec<(String, String)>)],
) -> Result<Comparison, CliError> {
    let (w, h) = (opts.width, opts.height);
    let pixels = f64::from(w) * f64::from(h);
    // Every set's materials are checked before anything is rendered.
    let all: Vec<Vec<(String, String)>> = sets
        .iter()
        .map(|(_, p)| common.iter().chain(p).cloned().collect())
        .collect();
    for o in &all {
        l.scene.specs(o)?;
    }
    let (rf, rsecs) = render_scene(l, spec, opts, common, "reference", true)?;
    let r = rf.to_srgb8(exposure);
    let mut results = Vec::new();
    let mut tests = Vec::new();
    for ((label, _), o) in sets.iter().zip(&all) {
        let (f, secs) = render_scene(l, spec, opts, o, "set", true)?;
        let t = f.to_srgb8(exposure);
        results.push(SetResult {
            label: label.clone(),
            scores: Scores {
                srgb: compare::metrics(label, &r, &t, w, h),
                linear: compare::linear_metrics(&rf, &f, exposure),
            },
            ns_per_pixel: secs * 1e9 / pixels,
            ns_per_eval: shading_cost(l, o)?,
        });
        tests.push(t);
    }
    let diffs: Vec<Vec<f32>> = tests.iter().map(|t| compare::difference(&r, t)).collect();
    let scale = diffs
        .iter()
        .flatten()
        .copied()
        .fold(0.0f32, f32::max)
        .max(1.0 / 255.0);
    let mut top = vec![Cell {
        label: "reference: the scene's materials".into(),
        rgb: r,
    }];
    let mut bottom = vec![Cell {
        label: "difference to the reference:".into(),
        rgb: vec![255; (w * h * 3) as usize],
    }];
    for ((res, t), d) in results.iter().zip(tests).zip(&diffs) {
        top.push(Cell {
            label: res.label.clone(),
            rgb: t,
        });
        let m = &res.scores.srgb;
        let psnr = if m.psnr.is_finite() {
            format!("{:.1} dB", m.psnr)
        } else {
            "inf dB".into()
        };
        bottom.push(Cell {
            label: format!("PSNR {psnr}, FLIP {:.3}", m.flip),
            rgb: compare::heat_map(d, scale),
        });
    }
    let (rgb, gw, gh) = compare::grid(&[top, bottom], w, h, Some(scale))?;
    Ok(Comparison {
        rgb,
        width: gw,
        height: gh,
        reference_ns_per_pixel: rsecs * 1e9 / pixels,
        reference_ns_per_eval: shading_cost(l, common)?,
        sets: results,
    })
}
