//! The explorer's endpoints that compute nothing heavy: the model list, a material's
//! parameters, and a model's shader (`fastbrdf shader`).

use super::query::{MAX_MODELS, MAX_SIZE, MAX_SPP, Query, Response, checked_id};
use crate::CliError;
use crate::commands::common::numbers::swept;
use crate::commands::view::state::State;
use crate::model_args::{self, Use};
use fastbrdf::params::ParamKind;
use fastbrdf::{Given, ModelSpec};
use fastbrdf_gpu::export::{Form, Lang, export_form};
use serde_json::{Value, json};

/// `GET /api/models`: every model the explorer can show, with its parameters (shadowing,
/// Fresnel and split-sum terms too: their curves are `/api/plots`' `terms`).
pub fn models(state: &State) -> Response {
    let mut list: Vec<Value> = fastbrdf::registry::all()
        .iter()
        .map(|e| {
            let mut params: Vec<Value> = e
                .info
                .params
                .iter()
                .map(|p| match p.kind {
                    ParamKind::Number {
                        min, max, default, ..
                    } => json!({
                        "name": p.name, "type": "number", "min": min, "max": max,
                        "default": default, "doc": p.doc,
                        // Exponents and roughness span decades: their sliders are logarithmic.
                        "log": min > 0.0 && max / min >= 50.0,
                    }),
                    ParamKind::Choice { options, default } => {
                        let mut v = json!({
                            "name": p.name, "type": "choice", "options": options.names(),
                            "default": default, "doc": p.doc,
                        });
                        // As `fastbrdf models --json`: a default that follows another choice
                        // (cook-torrance's g follows d), so the page's menu shows what is used.
                        if let Some(f) = options.follow() {
                            let defaults: serde_json::Map<String, Value> = f
                                .defaults
                                .iter()
                                .map(|(k, d)| ((*k).to_string(), json!(d)))
                                .collect();
                            v["default_follows"] = json!({"param": f.param, "defaults": defaults});
                        }
                        v
                    }
                })
                .collect();
            // A split-sum term's inputs (alpha, cos_v) as sliders too (`"input": true`).
            params.extend(super::kinds::input_params(e.info.kind));
            json!({
                "id": e.info.id, "kind": e.info.kind.name(), "params": params,
                "formula": e.info.formula, "source": e.info.source,
                "bounds": e.info.bounds, "ops": e.info.ops,
                "swept": swept(e),
                "cost": state.cost(e.info.id),
                // The committed SPIR-V counts at its defaults (as `fastbrdf models --json`).
                "instructions": fastbrdf::ModelSpec::parse(e.info.id, &[])
                    .ok()
                    .and_then(|s| fastbrdf_gpu::cost::lookup(&s)),
            })
        })
        .collect();
    // The users' models (`--model file:PATH`), after the registry's.
    let users = state.users();
    list.extend(users.iter().map(|u| u.entry_json()));
    let materials: Vec<&str> = fastbrdf_analysis::materials::all()
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    Response::json(&json!({
        "models": list,
        "materials": materials,
        "mesh": state.mesh_name,
        "env": state.env_file.as_ref().map(|(name, _)| name),
        "bench": state.bench_source,
        "measured": state.measured.as_ref().map(|m| json!({
            "name": m.name, "file": m.path.display().to_string(), "samples": m.data.len(),
        })),
        "users": users.iter().map(|u| u.name.as_str()).collect::<Vec<_>>(),
        "limits": {"size": MAX_SIZE, "spp": MAX_SPP, "models": MAX_MODELS},
        "langs": ["wgsl", "glsl", "hlsl", "msl", "brdf-explorer"],
    }))
}

/// `GET /api/material?name=NAME&model=ID`: the parameters a MERL material's fit supplies.
pub fn material(q: &Query) -> Result<Response, CliError> {
    let id = checked_id(q.need("model")?)?;
    let m = fastbrdf_analysis::materials::find(q.need("name")?).map_err(CliError::input)?;
    let spec = model_args::with_material(m, &ModelSpec::new(id, &[])?)?;
    let obj: serde_json::Map<String, Value> = spec
        .given()
        .iter()
        .map(|(k, v)| {
            let val = match v {
                Given::Num(x) => json!(x),
                other => json!(other.to_string()),
            };
            (k.to_string(), val)
        })
        .collect();
    Ok(Response::json(&json!({ "model": id, "params": obj })))
}

/// `GET /api/shader?model=ID&lang=LANG&NAME=VALUE...`: `fastbrdf shader` as text.
pub fn shader(state: &State, q: &Query) -> Result<Response, CliError> {
    if let Some(r) = super::user::user_shader(state, q) {
        return r;
    }
    let id = checked_id(q.need("model")?)?;
    let lang_text = q.get("lang").unwrap_or("wgsl");
    let lang = Lang::parse(lang_text).ok_or_else(|| {
        CliError::input(format!(
            "lang '{}': expected wgsl, glsl, hlsl, msl or brdf-explorer",
            fastbrdf_io::shorten(lang_text, 64)
        ))
    })?;
    // The model itself, with the query's values it takes (a BRDF Explorer file shades it).
    let spec = model_args::spec(
        id,
        &model_args::own_pairs(id, &q.params())?,
        None,
        None,
        Use::AsIs,
    )?;
    let text = export_form(&spec, lang, Form::Literals)?;
    Ok(Response {
        status: 200,
        content_type: "text/plain; charset=utf-8",
        body: text.into_bytes(),
    })
}
