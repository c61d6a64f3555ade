//! `fastbrdf demo`: the main job on built-in defaults. Writes a folder with sphere grids of
//! every lobe, the seeds' comparisons with difference maps and metrics (on spheres, and on the
//! embedded face with a procedural skin under the built-in sky), the analysis plots,
//! the reproduction table, a glTF scene built into the binary (`scene.glb`: the face and
//! spheres of gltf-pbr materials, from the library's glTF writer), and `index.html` that shows
//! it all.

use super::common::pictures::{Entry, Scores, check_compare, compare_models, render_model};
use crate::CliError;
use fastbrdf::{Given, ModelSpec};
use fastbrdf_analysis::reproduce;
use fastbrdf_io::OutputSet;
use fastbrdf_render::bump::Bump;
use fastbrdf_render::compare::{Cell, grid};
use fastbrdf_render::film::png_bytes;
use fastbrdf_render::render::{Options, Shading};
use fastbrdf_render::setup::{self, SceneSpec};
use glam::Vec3;
use std::fmt::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf demo\n  fastbrdf demo --out my-demo --mesh head.obj\n  fastbrdf demo --size 256"
)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "fastbrdf-out")]
    out: PathBuf,
    /// A mesh (OBJ) for the face comparisons instead of the built-in face (MediaPipe's
    /// canonical face; `face` names it, `./face` a file of that name). The skin texture is
    /// mapped by the mesh's texture coordinates.
    #[arg(long)]
    mesh: Option<PathBuf>,
    /// Side of each comparison picture in pixels (sphere grid cells are half of it).
    #[arg(long, default_value_t = 384)]
    size: u32,
}

/// Environment samples per primary sample in the face renders, 2 x 2 primary samples per
/// pixel: 16 per pixel (the demo stays fast; each is three rays with their shadow rays).
const FACE_ENV_SAMPLES: u32 = 4;

/// The built-in glTF scene's file in the output folder.
const SCENE_FILE: &str = "scene.glb";

struct Section {
    title: String,
    caption: String,
    image: String,
    metrics: Vec<Scores>,
}

/// Model `id` with typed values, as shading evaluates it (the demo's fixed configurations).
fn shaded(id: &str, given: &[(&str, Given)]) -> Result<ModelSpec, CliError> {
    Ok(ModelSpec::new(id, given)?.shaded()?)
}

/// A comparison entry: model `id` at one value of its parameter `name`.
fn at(id: &str, name: &str, x: f64) -> Result<Entry, CliError> {
    Ok(Entry::new(id, shaded(id, &[(name, Given::Num(x))])?))
}

fn save(set: &mut OutputSet, name: &str, rgb: &[u8], w: u32, h: u32) -> Result<String, CliError> {
    set.write(name, &png_bytes(rgb, w, h)?)?;
    Ok(name.into())
}

pub fn run(a: &Args) -> Result<(), CliError> {
    if !(64..=2048).contains(&a.size) {
        return Err(CliError::input(format!(
            "--size {}: must be 64 to 2048",
            a.size
        )));
    }
    let t0 = std::time::Instant::now();
    let dir = &a.out;
    check_compare(
        &Options {
            width: a.size,
            height: a.size,
            spp: 3,
            shading: Shading::Batch,
            sampler: fastbrdf_render::render::Sampler::default(),
            aa: fastbrdf_render::render::Antialias::default(),
        },
        4,
    )?;
    // Every input is checked before anything is written: the sizes, then the mesh (read once
    // here and shared by the face comparisons).
    let mut skin = SceneSpec::new();
    skin.albedo = Vec3::new(0.78, 0.52, 0.42);
    skin.bump = Some(Bump {
        scale: 40.0,
        depth: 0.6,
    });
    skin.kd = 0.6;
    skin.ks = 1.0;
    // The face: the embedded MediaPipe face (or the user's mesh) with the procedural skin
    // albedo, a light micro-relief, under the built-in sky (no other light).
    let mut face = SceneSpec::new();
    face.mesh = Some(
        a.mesh
            .clone()
            .unwrap_or_else(|| PathBuf::from(setup::BUILTIN_MESH)),
    );
    face.texture = Some(PathBuf::from(setup::BUILTIN_TEXTURE));
    face.albedo = Vec3::ONE;
    face.bump = Some(Bump {
        scale: 3.0,
        depth: 0.3,
    });
    face.kd = 1.0;
    face.ks = 1.0;
    face.env = Some("sky".into());
    face.env_samples = FACE_ENV_SAMPLES;
    for note in setup::builtin_notes(&face) {
        eprintln!("{note}");
    }
    let face_loaded = setup::load(&face)?;
    let plain = setup::load(&SceneSpec::new())?;
    // All-or-nothing: files are staged and moved into place only at the end.
    let mut set = OutputSet::new(dir)?;
    let mut sections = Vec::new();
    // 1. Every lobe on a sphere, at n = 20 and n = 200.
    let cell = a.size / 2;
    let opts = Options {
        width: cell,
        height: cell,
        spp: 2,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    let spec = SceneSpec::new();
    let loaded = &plain;
    for n in [20.0, 200.0] {
        let mut rows: Vec<Vec<Cell>> = vec![];
        for chunk in fastbrdf::registry::ids_of(fastbrdf::Kind::Lobe).chunks(4) {
            let mut row = vec![];
            for id in chunk {
                let model = shaded(id, &[("n", Given::Num(n))])?;
                let film = render_model(&spec, loaded, &opts, id, &model)?;
                row.push(Cell {
                    label: (*id).into(),
                    rgb: film.to_srgb8(1.0),
                });
            }
            rows.push(row);
        }
        let (rgb, w, h) = grid(&rows, cell, cell, None)?;
        let image = save(&mut set, &format!("lobes-n{n}.png"), &rgb, w, h)?;
        sections.push(Section {
            title: format!("Every lobe at n = {n}"),
            caption: format!("Each lobe as the specular term (lobe of n.h, kd 0.6, ks 0.4, one directional light), n = {n}. pow is the reference; the normalised flog is brighter by design (coef(n)), its clamped GLSL twin saturates."),
            image,
            metrics: vec![],
        });
    }
    // 2. The seeds' comparisons.
    let opts = Options {
        width: a.size,
        height: a.size,
        spp: 3,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    // The face renders sample the environment per primary sample: 2 x 2 of them per pixel.
    let face_opts = Options { spp: 2, ..opts };
    let mut cmp = |title: &str,
                   caption: &str,
                   file: &str,
                   spec: &SceneSpec,
                   reference: Entry,
                   models: Vec<Entry>|
     -> Result<(), CliError> {
        let (loaded, opts) = if spec.mesh.is_some() {
            (&face_loaded, &face_opts)
        } else {
            (&plain, &opts)
        };
        let (rgb, w, h, metrics) = compare_models(spec, loaded, opts, 1.0, &reference, &models)?;
        let image = save(&mut set, file, &rgb, w, h)?;
        sections.push(Section {
            title: title.into(),
            caption: caption.into(),
            image,
            metrics,
        });
        Ok(())
    };
    let n = 50.0;
    cmp(
        "Seed 001: normalised and original flog, and Schlick",
        "Against cos^n at n = 50. flog-normalized multiplies flog by the seed's coef(n) (energy conserving, so brighter than the unnormalised lobes); flog-normalized-clamped is the seed's GLSL, which clamps to 1 and loses the peak.",
        "seed001-flog.png",
        &SceneSpec::new(),
        at("pow", "n", n)?,
        vec![
            at("flog", "n", n)?,
            at("flog-normalized", "n", n)?,
            at("flog-normalized-clamped", "n", n)?,
            at("schlick", "n", n)?,
        ],
    )?;
    cmp(
        "Seed 003: cubic and rational stand-ins for cos^n",
        "Against cos^n at n = 100: the seed's cubic (epicentre), rational (fall-off) and the piecewise cubic-rational.",
        "seed003-cubic-rational.png",
        &SceneSpec::new(),
        at("pow", "n", 100.0)?,
        vec![
            at("cubic-rational", "n", 100.0)?,
            at("cubic", "n", 100.0)?,
            at("rational", "n", 100.0)?,
        ],
    )?;
    cmp(
        "Beyond the seeds: minimax-tuned coefficients at the same cost",
        "Against cos^n at n = 40: the power-16 form with its textbook slope n/16 and with the minimax-tuned slope (same operations, half the maximum error), and UE4's exp2 approximation against the tuned exp2 rate (same single exp2).",
        "tuned-vs-untuned.png",
        &SceneSpec::new(),
        at("pow", "n", 40.0)?,
        vec![
            at("power16", "n", 40.0)?,
            at("power16-tuned", "n", 40.0)?,
            at("ue4-phong-approx", "n", 40.0)?,
            at("sg-tuned", "n", 40.0)?,
        ],
    )?;
    let object = "a sphere";
    let ct = |d: &str, label: &str| -> Result<Entry, CliError> {
        let choice = |c: &str| Given::Choice(c.into());
        let mut e = Entry::new(
            "cook-torrance",
            shaded(
                "cook-torrance",
                &[
                    ("alpha", Given::Num(0.35)),
                    ("d", choice(d)),
                    ("g", choice("v-cavity")),
                    ("f", choice("schlick")),
                    ("f0", Given::Num(0.028)),
                    ("denominator", choice("seed-000")),
                ],
            )?,
        );
        e.label = format!("{label} (d={d})");
        Ok(e)
    };
    cmp(
        "Seed 000: Cook-Torrance on skin, exact D against its one-function forms",
        &format!(
            "Seed 000's Cook-Torrance (V-cavity G, Schlick F with f0 = 0.028, denominator (V.N)(L.N)), m = 0.35, on {object} with a procedural micro-relief standing in for skin. Reference: the exp-based D; compared: D16 (g = 16) and the one-pow D."
        ),
        "seed000-cook-torrance-skin.png",
        &skin,
        ct("beckmann-ct", "exp D")?,
        vec![
            ct("beckmann-power16", "D16")?,
            ct("beckmann-pow", "one-pow D")?,
        ],
    )?;
    cmp(
        "Seed 000: Ward on skin, exp against its one-function forms",
        &format!(
            "Isotropic Ward, m = 0.35, on {object} with the same micro-relief. Reference: exp(-tan^2 / m^2); compared: the g = 16 form and the one-pow form."
        ),
        "seed000-ward-skin.png",
        &skin,
        at("ward", "alpha", 0.35)?,
        vec![
            at("ward-power16", "alpha", 0.35)?,
            at("ward-pow", "alpha", 0.35)?,
        ],
    )?;
    // The same comparisons on the face under the sky.
    let user_mesh = a
        .mesh
        .as_deref()
        .filter(|m| !setup::is_builtin(m, setup::BUILTIN_MESH));
    let (face_name, face_file) = match user_mesh {
        Some(m) => (format!("the given mesh {}", m.display()), "mesh"),
        None => ("MediaPipe's canonical face".to_string(), "face"),
    };
    let sky = format!(
        "under the built-in sky (environment light: {} samples per pixel, each a map, a cosine and a BRDF sample combined by MIS, with shadow rays), with the built-in procedural skin albedo (pores, colour and redness variation) and a light micro-relief",
        4 * FACE_ENV_SAMPLES
    );
    cmp(
        "Seed 000 on a face: Cook-Torrance under environment light",
        &format!(
            "The Cook-Torrance comparison above on {face_name} {sky}. Reference: the exp-based Beckmann D; compared: D16 (g = 16) and the one-pow D. The noise in the difference maps is partly the Monte Carlo noise of the two renders (each model samples its own lobe)."
        ),
        &format!("seed000-cook-torrance-{face_file}.png"),
        &face,
        ct("beckmann-ct", "exp D")?,
        vec![
            ct("beckmann-power16", "D16")?,
            ct("beckmann-pow", "one-pow D")?,
        ],
    )?;
    cmp(
        "Seed 000 on a face: Ward under environment light",
        &format!(
            "The Ward comparison above (m = 0.35) on {face_name} {sky}; specular weight ks 0.2 (1 on the sphere) so that the sheen reads as skin. Reference: exp(-tan^2 / m^2); compared: the g = 16 form and the one-pow form."
        ),
        &format!("seed000-ward-{face_file}.png"),
        &SceneSpec {
            ks: 0.2,
            ..face.clone()
        },
        at("ward", "alpha", 0.35)?,
        vec![
            at("ward-power16", "alpha", 0.35)?,
            at("ward-pow", "alpha", 0.35)?,
        ],
    )?;
    // 3. The built-in glTF scene (the face and five spheres of gltf-pbr materials), written
    // by the library's glTF writer (the same bytes every run), read back by the glTF reader
    // and rendered under the sky: its materials as written against two sets of shortcuts.
    let glb = fastbrdf_render::gltf_write::demo_scene();
    set.write(SCENE_FILE, &glb)?;
    sections.push(scene_section(&mut set, &glb, &face_opts)?);
    // 4. Plots and the reproduction table.
    super::common::figures::stage_seed_figures(&mut set, "plots")?;
    let report = reproduce::run(&[], &|| {})?;
    let md = reproduce::markdown(&report);
    set.write("REPRODUCTION.md", md.as_bytes())?;
    let html = index_html(&sections, &report, t0.elapsed().as_secs_f64());
    set.write("index.html", html.as_bytes())?;
    for f in set.commit()? {
        eprintln!("wrote {}", f.display());
    }
    eprintln!(
        "wrote {} ({:.1} s): open it in a browser",
        dir.join("index.html").display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The approximation sets the demo scene is compared with (as `compare --scene --set`):
/// label, pairs given to every material.
const SCENE_SETS: [(&str, &str); 2] = [
    (
        "fast G, SG Fresnel",
        "g=smith-ggx-correlated-fast,f=schlick-sg",
    ),
    (
        "Neubelt sheen, no sheen albedo",
        "sheen_v=neubelt,sheen_albedo=none",
    ),
];

/// Renders the built-in scene, read back from its `.glb` bytes by the glTF reader and seen by
/// its camera, under the built-in sky (which replaces the file's lights), with its materials
/// as written and with each of [`SCENE_SETS`]; stages the comparison picture.
fn scene_section(set: &mut OutputSet, glb: &[u8], opts: &Options) -> Result<Section, CliError> {
    use super::common::gltf_scene::{Loaded, compare_sets, parse_set};
    let scene = fastbrdf_render::gltf::from_bytes(SCENE_FILE, glb, std::path::Path::new("."))?;
    for w in &scene.warnings {
        eprintln!("warning: {SCENE_FILE}: {w}");
    }
    let mut spec = SceneSpec::new();
    spec.env = Some("sky".into());
    spec.env_samples = FACE_ENV_SAMPLES;
    let env = fastbrdf_render::env::EnvMap::from_spec("sky")?;
    let loaded = Loaded {
        scene,
        env: Some(std::sync::Arc::new(env)),
    };
    let sets = SCENE_SETS
        .iter()
        .map(|(label, pairs)| Ok(((*label).to_string(), parse_set(pairs)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    let c = compare_sets(&loaded, &spec, opts, 1.0, &[], &sets)?;
    let image = save(set, "gltf-scene.png", &c.rgb, c.width, c.height)?;
    let times: Vec<String> = c
        .sets
        .iter()
        .zip(SCENE_SETS)
        .map(|(r, (label, pairs))| format!("{label} ({pairs}) {:.0} ns", r.ns_per_pixel))
        .collect();
    Ok(Section {
        title: "A glTF scene: gltf-pbr materials against shortcut sets".into(),
        caption: format!(
            "The built-in scene {SCENE_FILE} (see below), read back by the glTF reader and seen by its camera, under the built-in sky ({} samples per pixel, as the face): every material is the gltf-pbr model. Reference: the materials as written (height-correlated Smith G, Schlick Fresnel, Charlie sheen with its albedo scaling); compared: each set of shortcuts given to every material. Time per pixel (the least of up to {} renders): reference {:.0} ns; {}.",
            4 * FACE_ENV_SAMPLES,
            super::common::gltf_scene::TIMING_RENDERS,
            c.reference_ns_per_pixel,
            times.join("; ")
        ),
        image,
        metrics: c.sets.into_iter().map(|r| r.scores).collect(),
    })
}

/// The glTF scene's section: the file and a table of its materials' factors.
fn scene_html() -> String {
    let mut h = format!(
        "<h2>A glTF scene</h2>\n<p><a href=\"{SCENE_FILE}\"><code>{SCENE_FILE}</code></a>: MediaPipe's canonical face over five spheres, a camera, a directional key light and a point fill light, written by the glTF writer (<code>fastbrdf_render::gltf_write</code>). Open it in any glTF viewer; it passes the Khronos glTF-Validator (<code>node tools/gltf_validate.mjs {SCENE_FILE}</code>). Its materials (linear factors):</p>\n<table><tr><th>material</th><th>base colour</th><th>metallic</th><th>roughness</th><th>extensions</th></tr>\n"
    );
    for row in fastbrdf_render::gltf_write::material_rows() {
        h.push_str("<tr>");
        for cell in row {
            let _ = write!(h, "<td>{}</td>", esc(&cell));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    h
}

fn index_html(sections: &[Section], report: &reproduce::Report, secs: f64) -> String {
    let mut h = String::from(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>fastbrdf demo</title>\n<style>body{font-family:sans-serif;max-width:1400px;margin:auto;padding:1em}\
img{max-width:100%;border:1px solid #ccc}table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:3px 8px;font-size:14px}\
th{background:#eee}.agrees{color:#060}.differs{color:#a00}figure{margin:1em 0 2em 0}</style></head><body>\n<h1>fastbrdf demo</h1>\n",
    );
    let _ = writeln!(
        h,
        "<p>Generated by <code>fastbrdf demo</code> in {secs:.1} s. Every picture and number below was computed by this run.</p>"
    );
    let _ = writeln!(h, "<h2>Renders</h2>");
    for s in sections {
        let _ = writeln!(
            h,
            "<figure><h3>{}</h3><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption>",
            esc(&s.title),
            esc(&s.image),
            esc(&s.title),
            esc(&s.caption)
        );
        if !s.metrics.is_empty() {
            let _ = writeln!(
                h,
                "<table><caption>RMSE, PSNR, FLIP: on the clipped 8-bit sRGB pictures; linear: on the HDR film, PSNR against the reference's peak {:.3}; FLIP after the Reinhard tone map x/(1+x)</caption><tr><th>model</th><th>RMSE</th><th>PSNR (dB)</th><th>FLIP</th><th>RMSE linear</th><th>PSNR linear (dB)</th><th>FLIP Reinhard</th></tr>",
                s.metrics.first().map_or(0.0, |m| m.linear.peak)
            );
            let db = |x: f64| {
                if x.is_finite() {
                    format!("{x:.2}")
                } else {
                    "inf".into()
                }
            };
            for m in &s.metrics {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{:.5}</td><td>{}</td><td>{:.4}</td><td>{:.5}</td><td>{}</td><td>{:.4}</td></tr>",
                    esc(&m.srgb.model),
                    m.srgb.rmse,
                    db(m.srgb.psnr),
                    m.srgb.flip,
                    m.linear.rmse,
                    db(m.linear.psnr),
                    m.linear.flip_reinhard
                );
            }
            let _ = writeln!(h, "</table>");
        }
        let _ = writeln!(h, "</figure>");
    }
    h.push_str(&scene_html());
    let _ = writeln!(h, "<h2>Plots of the seeds' figures</h2>");
    for (file, caption) in [
        (
            "seed001-fig2-lobes-n20.png",
            "Seed 001 Fig. 2: flog, cos^n and Schlick at n = 20",
        ),
        (
            "seed001-fig3-max-rel-epicentre.png",
            "Seed 001 Fig. 3: max relative error in the epicentre against n",
        ),
        (
            "seed001-fig4-max-abs.png",
            "Seed 001 Fig. 4: max absolute error against n",
        ),
        (
            "seed001-fig9-energy-residual.png",
            "Seed 001 Fig. 9: energy residual of the published coef(n)",
        ),
        (
            "seed003-fig1-cubic-epicentre.png",
            "Seed 003 Fig. 1: max absolute error in the epicentre against n",
        ),
        (
            "seed003-fig3-lobes-n20.png",
            "Seed 003 Fig. 3: Schlick, rational and cos^n at n = 20",
        ),
        (
            "seed000-fig1-3-beckmann-forms.png",
            "Seed 000 Fig. 1 and 3: D, D4, D8, D16 at m = 0.3",
        ),
        (
            "seed000-fig2-4-relative-error.png",
            "Seed 000 Fig. 2 and 4: their relative error",
        ),
    ] {
        let _ = writeln!(
            h,
            "<figure><img src=\"plots/{file}\" alt=\"{}\"><figcaption>{}</figcaption></figure>",
            esc(caption),
            esc(caption)
        );
    }
    let _ = writeln!(
        h,
        "<h2>The seeds' claims, reproduced</h2><table><tr><th>claim</th><th>seed</th><th>claimed</th><th>measured</th><th>verdict</th><th>domain</th></tr>"
    );
    for c in &report.claims {
        let _ = writeln!(
            h,
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td class=\"{}\">{}</td><td>{}</td></tr>",
            esc(&c.id),
            c.seed,
            esc(c.claimed_text.as_deref().unwrap_or("-")),
            esc(c.measured_text.as_deref().unwrap_or("-")),
            c.verdict.replace(' ', "-"),
            c.verdict,
            esc(&c.domain)
        );
    }
    h.push_str("</table>\n<p>Speed rows: run <code>fastbrdf bench --json &gt; bench.json</code> and <code>fastbrdf reproduce --speedups bench.json</code>.</p>\n</body></html>\n");
    h
}
