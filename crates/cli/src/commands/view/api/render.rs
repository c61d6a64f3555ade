//! `/api/render`: the pictures, difference maps and RMSE/PSNR/FLIP of `fastbrdf compare`,
//! under the server's render slots and per-client generations; FLIP computed by the pool of
//! [`flip`](crate::commands::view::flip) while the pictures go out (`flip=later`, then
//! `/api/flip?job=ID`), or waited for (`flip=wait`, the default).

use super::query::{Chosen, MAX_SIZE, MAX_SPP, Query, Reference, Response, base64, parse_u32};
use crate::CliError;
use crate::commands::view::flip::{Flips, Outcome, Waited};
use crate::commands::view::state::{State, client_gone};
use fastbrdf_render::compare::{self, Metrics};
use fastbrdf_render::film::png_bytes;
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::Specular;
use fastbrdf_render::setup;
use fastbrdf_render::user::UserRgb;
use rayon::prelude::*;
use serde_json::{Value, json};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Longest a request waits for a FLIP job (`flip=wait`, `/api/flip`) before its 503.
pub const FLIP_WAIT: Duration = Duration::from_secs(60);

/// When `/api/render` computes FLIP (`flip=`).
#[derive(Clone, Copy, PartialEq, Debug)]
enum FlipMode {
    /// The answer waits for it (the default: one request, every number).
    Wait,
    /// The answer goes out without it and names a job; `/api/flip?job=ID` waits for it.
    Later,
    /// Not at all (the page's preview): `flip` null.
    Skip,
}

fn flip_mode(q: &Query) -> Result<FlipMode, CliError> {
    match q.get("flip").unwrap_or("wait") {
        "wait" => Ok(FlipMode::Wait),
        "later" => Ok(FlipMode::Later),
        "none" => Ok(FlipMode::Skip),
        m => Err(CliError::input(format!(
            "flip '{}': expected wait, later or none",
            fastbrdf_io::shorten(m, 64)
        ))),
    }
}

/// A FLIP job this request feeds: cancelled if the request ends before handing it over.
struct Feeding<'a> {
    flips: &'a Flips,
    job: Option<u64>,
}

impl Drop for Feeding<'_> {
    fn drop(&mut self) {
        if let Some(j) = self.job {
            self.flips.cancel(j);
        }
    }
}

/// One metrics row of the JSON (`flip` null until computed; an infinite PSNR is null too).
fn row(m: &Metrics) -> Value {
    let flip = if m.flip.is_nan() {
        Value::Null
    } else {
        json!(m.flip)
    };
    json!({"model": m.model, "rmse": m.rmse, "psnr": m.psnr, "flip": flip})
}

/// `GET /api/render?models=A,B&ref=R&size=N&spp=S&mesh=sphere|mesh&light=X,Y,Z&client=C&gen=G&flip=wait|later|none`:
/// the pictures (PNG, base64), difference maps against the reference, and RMSE/PSNR/FLIP as
/// `fastbrdf compare`. Renders wait for one of the server's render slots; a request whose
/// client has since sent a newer generation is dropped (409) before each model's render. Each
/// model's FLIP starts in the pool as soon as its picture exists; with `flip=later` the answer
/// has `flip` null and `flip_job`, the id for `/api/flip`.
pub fn render_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let t0 = Instant::now();
    let Chosen {
        models,
        users,
        reference,
        ref_user,
    } = super::kinds::shaded(state, q)?; // terms (shadowing, Fresnel, env) skipped
    let mode = flip_mode(q)?;
    let size = parse_u32(q, "size", 256, 16, MAX_SIZE)?;
    let spp = parse_u32(q, "spp", 1, 1, MAX_SPP)?;
    // The scene (mesh or sphere, light) as the page's WebGPU pictures take it.
    let (scene_spec, loaded) = super::gpu::scene_choice(state, q)?;
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
    let opts = Options {
        width: size,
        height: size,
        spp,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    let Some(slot) = state.render_slot() else {
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
    // A user's model as `fastbrdf render --model file:PATH` renders it: through `UserRgb`, the
    // whole BRDF (weights 0, 1), the reference first.
    let user_job = |u: &super::query::UserPick| {
        let mut s = scene_spec.clone();
        (s.kd, s.ks) = (0.0, 1.0);
        let brdf = Arc::new(UserRgb::new(u.brdf.clone()));
        (
            u.model.name.clone(),
            s,
            Arc::new(Specular::rgb(&u.model.name, brdf)),
        )
    };
    jobs.extend(ref_user.iter().map(user_job));
    for (id, spec) in &models {
        let mut specular = Specular::new(spec)?;
        specular.id = id.to_string();
        jobs.push((id.to_string(), scene_spec.clone(), Arc::new(specular)));
    }
    jobs.extend(users.iter().map(user_job));
    let names: Vec<String> = jobs.iter().map(|j| j.0.clone()).collect();
    let compared = reference.is_some() && names.len() > 1;
    // FLIP in the pool when it has room; else (FLIP_JOBS taken) on this thread, in the slot.
    let mut feeding = Feeding {
        flips: &state.flips,
        job: (compared && mode != FlipMode::Skip)
            .then(|| {
                state
                    .flips
                    .open(&client, generation, (size, size), &names[1..])
            })
            .flatten(),
    };
    let mut pictures: Vec<Arc<Vec<u8>>> = vec![];
    let mut render_ms = vec![];
    for (k, (id, spec, specular)) in jobs.into_iter().enumerate() {
        // Nobody reads the answer of a client that has hung up: the slot goes to another.
        if client_gone() {
            return Ok(Response::error(499, "the client has gone"));
        }
        if state.superseded(&client, generation) {
            return Ok(superseded());
        }
        let t = Instant::now();
        let scene = setup::scene(&spec, loaded, specular.clone());
        let film = render(&scene, &opts, &|_, _| {})?;
        if let Some(e) = specular.rgb.as_ref().and_then(|b| b.failure()) {
            // A user's model evaluated on the GPU failed mid-render (its device was lost).
            return Err(CliError {
                code: crate::EXIT_CHECK_FAILED,
                message: format!("--model {id}: {e}"),
            });
        }
        film.check_finite()
            .map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
        let px = Arc::new(film.to_srgb8(1.0));
        render_ms.push(t.elapsed().as_secs_f64() * 1e3);
        if let Some(j) = feeding.job {
            // The reference is rendered first: model k's FLIP can start now.
            state.flips.picture(j, k.checked_sub(1), px.clone());
        }
        pictures.push(px);
    }
    // The pictures and heat maps encoded in parallel (the renders are done: the cores are
    // free but for FLIP, which runs at a lower priority).
    let t = Instant::now();
    let png = |px: &[u8]| png_bytes(px, size, size).map(|b| base64(&b));
    let encoded: Vec<String> = pictures
        .par_iter()
        .map(|px| png(px))
        .collect::<Result<_, _>>()?;
    let images: Vec<Value> = names
        .iter()
        .zip(encoded)
        .map(|(id, png)| json!({"id": id, "png": png}))
        .collect();
    let mut diffs = vec![];
    let mut metrics: Vec<Metrics> = vec![];
    let mut scale = Value::Null;
    if reference.is_some() {
        let r = &pictures[0];
        let d: Vec<Vec<f32>> = pictures[1..]
            .par_iter()
            .map(|t| compare::difference(r, t))
            .collect();
        let max = d
            .iter()
            .flatten()
            .copied()
            .fold(0.0f32, f32::max)
            .max(1.0 / 255.0);
        scale = json!(max);
        let heat: Vec<String> = d
            .par_iter()
            .map(|d| png(&compare::heat_map(d, max)))
            .collect::<Result<_, _>>()?;
        for (id, png) in names[1..].iter().zip(heat) {
            diffs.push(json!({"id": id, "png": png}));
        }
        metrics = names[1..]
            .iter()
            .zip(&pictures[1..])
            .map(|(id, px)| compare::pixel_metrics(id, r, px))
            .collect();
    }
    let encode_ms = t.elapsed().as_secs_f64() * 1e3;
    let mut flip_ms = Value::Null;
    let mut flip_job = Value::Null;
    if compared && mode != FlipMode::Skip {
        let t = Instant::now();
        match (feeding.job, mode) {
            (Some(j), FlipMode::Later) => {
                flip_job = json!(j);
                feeding.job = None;
            }
            (Some(j), _) => {
                // Waiting needs no slot: the pool bounds FLIP's work.
                drop(slot);
                match state
                    .flips
                    .wait(j, Instant::now() + FLIP_WAIT, &client_gone)
                {
                    Waited::Ended(_, _, Outcome::Done(m, secs)) => {
                        metrics = m;
                        flip_ms = json!(secs * 1e3);
                    }
                    Waited::Ended(_, _, Outcome::Superseded) => return Ok(superseded()),
                    Waited::Gone => return Ok(Response::error(499, "the client has gone")),
                    Waited::Pending => {
                        return Ok(Response::error(503, "FLIP still computing; try again"));
                    }
                    Waited::Ended(_, _, Outcome::Cancelled | Outcome::Failed) | Waited::Unknown => {
                        return Ok(Response::error(
                            500,
                            "internal error (FLIP failed); the server goes on",
                        ));
                    }
                }
            }
            (None, _) => {
                // The pool is full: FLIP here, inside the render slot (back-pressure).
                let r = &pictures[0];
                metrics = names[1..]
                    .iter()
                    .zip(&pictures[1..])
                    .map(|(id, px)| compare::metrics(id, r, px, size, size))
                    .collect();
                flip_ms = json!(t.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    let metrics: Vec<Value> = metrics.iter().map(row).collect();
    Ok(Response::json(&json!({
        "width": size, "height": size, "spp": spp,
        "reference": if reference.is_some() { json!(names[0]) } else { Value::Null },
        "images": images, "diffs": diffs, "diff_scale": scale, "metrics": metrics,
        "flip_job": flip_job,
        "timings_ms": {"render": render_ms, "encode": encode_ms, "flip": flip_ms},
        "ms": t0.elapsed().as_secs_f64() * 1e3,
    })))
}

fn superseded() -> Response {
    Response::error(409, "superseded by a newer request from this client")
}

/// `GET /api/flip?job=ID`: the metrics of a `/api/render?flip=later` answer, FLIP included,
/// once the pool has computed them (waiting at most [`FLIP_WAIT`], then 503):
/// `{job, reference, metrics: [{model, rmse, psnr, flip}], flip_ms, ms}`. 409 when the job's
/// client has since asked for a newer generation (its FLIP is not computed, or not wanted), 410
/// when its render did not finish, 404 for a job unknown or no longer kept.
pub fn flip_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let t0 = Instant::now();
    let text = q.need("job")?;
    let job: u64 = text.parse().map_err(|_| {
        CliError::input(format!(
            "job '{}': not a whole number",
            fastbrdf_io::shorten(text, 64)
        ))
    })?;
    match state
        .flips
        .wait(job, Instant::now() + FLIP_WAIT, &client_gone)
    {
        Waited::Unknown => Ok(Response::error(
            404,
            &format!(
                "job {job}: no such FLIP job (made by /api/render?flip=later; the last {} are kept)",
                crate::commands::view::flip::KEPT_RESULTS
            ),
        )),
        Waited::Pending => Ok(Response::error(
            503,
            &format!("job {job}: FLIP still computing; try again"),
        )),
        Waited::Gone => Ok(Response::error(499, "the client has gone")),
        Waited::Ended(client, generation, outcome) => {
            if state.superseded(&client, generation) {
                return Ok(superseded());
            }
            match outcome {
                Outcome::Done(m, secs) => Ok(Response::json(&json!({
                    "job": job,
                    "metrics": m.iter().map(row).collect::<Vec<_>>(),
                    "flip_ms": secs * 1e3,
                    "ms": t0.elapsed().as_secs_f64() * 1e3,
                }))),
                Outcome::Superseded => Ok(superseded()),
                Outcome::Cancelled => Ok(Response::error(
                    410,
                    &format!("job {job}: its render did not finish"),
                )),
                Outcome::Failed => Ok(Response::error(
                    500,
                    "internal error (a panic in FLIP); the server goes on",
                )),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::commands::view::flip::FLIP_JOBS;

    /// A server's state whose FLIP pool has no threads: its tasks run only when a test runs
    /// them, so what a request computed itself is visible.
    fn state() -> State {
        State::with_flip_threads(None, None, None, 0).unwrap()
    }

    fn json_of(r: Response) -> Value {
        assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
        serde_json::from_slice(&r.body).unwrap()
    }

    fn pixels(png_base64: &Value) -> Vec<u8> {
        let png = crate::commands::view::cdp::base64_decode(png_base64.as_str().unwrap()).unwrap();
        image::load_from_memory(&png).unwrap().to_rgb8().into_raw()
    }

    /// `x` as a JSON answer carries it (serde_json's float parsing may differ in the last bit,
    /// the same way for every answer).
    fn as_sent(x: f64) -> Value {
        serde_json::from_slice(&serde_json::to_vec(&json!(x)).unwrap()).unwrap()
    }

    const LATER: &str = "models=flog,schlick&ref=pow&n=100&size=32&spp=1&client=a&gen=1&flip=later";

    #[test]
    fn the_pictures_answer_leaves_flip_to_the_pool_which_computes_compares_metrics() {
        let s = state();
        let v = json_of(render_endpoint(&s, &Query::parse(LATER)).unwrap());
        // Answered with the pictures, RMSE and PSNR, and no FLIP computed (by anyone).
        assert_eq!(s.flips.computed(), 0);
        let job = v["flip_job"].as_u64().expect("a job id");
        assert!(matches!(
            s.flips.wait(job, Instant::now(), &|| false),
            Waited::Pending
        ));
        for m in v["metrics"].as_array().unwrap() {
            assert!(
                m["flip"].is_null() && m["rmse"].as_f64().unwrap() > 0.0,
                "{m}"
            );
        }
        while s.flips.run_one() {}
        assert_eq!(s.flips.computed(), 2);
        let f = json_of(flip_endpoint(&s, &Query::parse(&format!("job={job}"))).unwrap());
        // The numbers of `compare::metrics` (what `fastbrdf compare` prints) on the pictures
        // the answer carried.
        let images = v["images"].as_array().unwrap();
        let r = pixels(&images[0]["png"]);
        for (k, id) in ["flog", "schlick"].into_iter().enumerate() {
            let want = compare::metrics(id, &r, &pixels(&images[k + 1]["png"]), 32, 32);
            let got = &f["metrics"][k];
            assert_eq!(got["model"], id);
            assert_eq!(got["flip"], as_sent(want.flip), "{id}");
            assert!(want.flip > 0.0);
            for (field, x) in [("rmse", want.rmse), ("psnr", want.psnr)] {
                assert_eq!(got[field], as_sent(x), "{id} {field}");
                assert_eq!(v["metrics"][k][field], got[field], "{id} {field}");
            }
        }
    }

    #[test]
    fn a_newer_generation_ends_the_older_flip_job_409() {
        let s = state();
        let v = json_of(render_endpoint(&s, &Query::parse(LATER)).unwrap());
        let job = v["flip_job"].as_u64().unwrap();
        json_of(
            render_endpoint(
                &s,
                &Query::parse("models=flog&size=16&client=a&gen=2&flip=none"),
            )
            .unwrap(),
        );
        // Its FLIPs are never computed, and asking for them is a 409.
        assert!(!s.flips.run_one());
        assert_eq!(s.flips.computed(), 0);
        let r = flip_endpoint(&s, &Query::parse(&format!("job={job}"))).unwrap();
        assert_eq!(r.status, 409);
        // Another client's jobs are not affected.
        let other = LATER.replace("client=a", "client=b");
        let v = json_of(render_endpoint(&s, &Query::parse(&other)).unwrap());
        while s.flips.run_one() {}
        let job = v["flip_job"].as_u64().unwrap();
        json_of(flip_endpoint(&s, &Query::parse(&format!("job={job}"))).unwrap());
    }

    #[test]
    fn a_full_pool_makes_the_render_compute_flip_itself() {
        let s = state();
        for k in 0..FLIP_JOBS {
            assert!(
                s.flips
                    .open("x", k as u64, (16, 16), &["m".into()])
                    .is_some()
            );
        }
        let v = json_of(render_endpoint(&s, &Query::parse(LATER)).unwrap());
        assert!(v["flip_job"].is_null());
        assert_eq!(s.flips.computed(), 0);
        for m in v["metrics"].as_array().unwrap() {
            assert!(m["flip"].as_f64().unwrap() > 0.0, "{m}");
        }
    }

    #[test]
    fn flip_none_and_bad_values() {
        let s = state();
        let v =
            json_of(render_endpoint(&s, &Query::parse(&LATER.replace("later", "none"))).unwrap());
        assert!(v["flip_job"].is_null() && v["metrics"][0]["flip"].is_null());
        assert!(!s.flips.run_one());
        for (q, status, message) in [
            (LATER.replace("later", "soon"), 400, "flip 'soon'"),
            ("job=x".into(), 400, "job 'x'"),
            ("".into(), 400, "'job'"),
            ("job=12345".into(), 404, "job 12345"),
        ] {
            let q = Query::parse(&q);
            let r = if q.get("models").is_some() {
                render_endpoint(&s, &q)
            } else {
                flip_endpoint(&s, &q)
            }
            .unwrap_or_else(Response::from);
            assert_eq!(r.status, status, "{}", String::from_utf8_lossy(&r.body));
            assert!(String::from_utf8_lossy(&r.body).contains(message));
        }
    }
}
