//! `/api/render`: the pictures, difference maps and RMSE/PSNR/FLIP of `fastbrdf compare`,
//! under the server's render slots and per-client generations.

use super::query::{
    Chosen, MAX_SIZE, MAX_SPP, Query, Reference, Response, base64, chosen, parse_u32,
};
use crate::CliError;
use crate::commands::view::state::{State, client_gone};
use fastbrdf_render::compare;
use fastbrdf_render::film::png_bytes;
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Light, Specular};
use fastbrdf_render::setup;
use serde_json::{Value, json};
use std::sync::Arc;
use std::time::Instant;

/// `GET /api/render?models=A,B&ref=R&size=N&spp=S&mesh=sphere|mesh&light=X,Y,Z&client=C&gen=G`:
/// the pictures (PNG, base64), difference maps against the reference, and RMSE/PSNR/FLIP as
/// `fastbrdf compare`. Renders wait for one of the server's render slots; a request whose
/// client has since sent a newer generation is dropped (409) before each model's render.
pub fn render_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let t0 = Instant::now();
    let Chosen { models, reference } = chosen(state, q)?;
    let size = parse_u32(q, "size", 256, 16, MAX_SIZE)?;
    let spp = parse_u32(q, "spp", 1, 1, MAX_SPP)?;
    let mut spec = setup::SceneSpec::new();
    match q.get("mesh").unwrap_or("sphere") {
        "sphere" => {}
        "mesh" => {
            if state.loaded_mesh.is_none() {
                return Err(CliError::input(
                    "mesh=mesh: the server was started without --mesh",
                ));
            }
        }
        m => {
            return Err(CliError::input(format!(
                "mesh '{}': expected sphere or mesh",
                fastbrdf_io::shorten(m, 64)
            )));
        }
    }
    let use_mesh = q.get("mesh") == Some("mesh");
    if let Some(l) = q.get("light") {
        spec.lights = vec![Light::parse(&format!("dir:{l}"))?];
    }
    let client = q.get("client").unwrap_or("").to_string();
    let generation = match q.get("gen") {
        Some(g) => g.parse::<u64>().map_err(|_| {
            CliError::input(format!(
                "gen '{}': not a whole number",
                fastbrdf_io::shorten(g, 64)
            ))
        })?,
        None => 0,
    };
    state.note_generation(&client, generation);
    let loaded = if use_mesh {
        state.loaded_mesh.as_ref().expect("checked above")
    } else {
        &state.loaded_sphere
    };
    let scene_spec = if use_mesh {
        let mut s = spec.clone();
        s.mesh = state.mesh_path.clone();
        s
    } else {
        spec
    };
    let opts = Options {
        width: size,
        height: size,
        spp,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
    };
    let Some(_slot) = state.render_slot() else {
        return Ok(Response::error(503, "too many renders waiting; try again"));
    };
    // What is rendered, the reference first: a measured one as `fastbrdf compare --measured`
    // renders it (the whole BRDF in colour, weights 0, 1), the models as `fastbrdf compare`.
    let mut jobs: Vec<(String, setup::SceneSpec, Arc<Specular>)> = vec![];
    if let Some(Reference::Measured(m)) = &reference {
        let mut s = scene_spec.clone();
        (s.kd, s.ks) = (0.0, 1.0);
        let label = format!("measured {}", m.path.display());
        jobs.push((
            m.name.clone(),
            s,
            Arc::new(Specular::rgb(&label, m.brdf.clone())),
        ));
    }
    for (id, spec) in &models {
        let mut specular = Specular::new(spec)?;
        specular.id = id.to_string();
        jobs.push((id.to_string(), scene_spec.clone(), Arc::new(specular)));
    }
    let names: Vec<String> = jobs.iter().map(|j| j.0.clone()).collect();
    let mut pictures: Vec<Vec<u8>> = vec![];
    for (id, spec, specular) in jobs {
        // Nobody reads the answer of a client that has hung up: the slot goes to another.
        if client_gone() {
            return Ok(Response::error(499, "the client has gone"));
        }
        if state.superseded(&client, generation) {
            return Ok(Response::error(
                409,
                "superseded by a newer request from this client",
            ));
        }
        let scene = setup::scene(&spec, loaded, specular);
        let film = render(&scene, &opts, &|_, _| {})?;
        film.check_finite()
            .map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
        pictures.push(film.to_srgb8(1.0));
    }
    let mut images = vec![];
    for (id, px) in names.iter().zip(&pictures) {
        images.push(json!({"id": id, "png": base64(&png_bytes(px, size, size)?)}));
    }
    let mut diffs = vec![];
    let mut metrics = vec![];
    if reference.is_some() {
        let r = &pictures[0];
        let d: Vec<Vec<f32>> = pictures[1..]
            .iter()
            .map(|t| compare::difference(r, t))
            .collect();
        let scale = d
            .iter()
            .flatten()
            .copied()
            .fold(0.0f32, f32::max)
            .max(1.0 / 255.0);
        for (k, (id, px)) in names[1..].iter().zip(&pictures[1..]).enumerate() {
            let m = compare::metrics(id, r, px, size, size);
            metrics.push(json!({"model": id, "rmse": m.rmse, "psnr": m.psnr, "flip": m.flip}));
            diffs.push(json!({"id": id, "png": base64(&png_bytes(&compare::heat_map(&d[k], scale), size, size)?)}));
        }
        return Ok(Response::json(&json!({
            "width": size, "height": size, "spp": spp, "reference": names[0],
            "images": images, "diffs": diffs, "diff_scale": scale, "metrics": metrics,
            "ms": t0.elapsed().as_secs_f64() * 1e3,
        })));
    }
    Ok(Response::json(&json!({
        "width": size, "height": size, "spp": spp, "reference": Value::Null,
        "images": images, "diffs": diffs, "diff_scale": Value::Null, "metrics": metrics,
        "ms": t0.elapsed().as_secs_f64() * 1e3,
    })))
}
