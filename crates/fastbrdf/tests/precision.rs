//! f32 against f64 for every model over its whole documented domain, on the same (f32)
//! inputs: the mixed error `|v32 - v64| / max(1, |v64|)` must stay within the model's
//! documented `f32_bound`. Run with `--nocapture` to print the measured bound per model.

mod common;

use common::{as_refs, configs, direction_pairs, get};
use fastbrdf::accuracy::{lobe_samples, samples};
use fastbrdf::model::ShadowInput;
use fastbrdf::{Model, registry};

fn mixed(v32: f32, v64: f64) -> f64 {
    (v32 as f64 - v64).abs() / v64.abs().max(1.0)
}

/// The worst mixed error of one model configuration, over inputs covering its domain.
fn worst(id: &str, cfg: &[(String, String)]) -> (f64, String) {
    let given = as_refs(cfg);
    let m32 = registry::build::<f32>(id, &given).unwrap();
    let m64 = registry::build::<f64>(id, &given).unwrap();
    let mut worst = (0.0, String::new());
    let mut note = |e: f64, what: String| {
        assert!(
            e.is_finite(),
            "{id} {cfg:?}: non-finite f32/f64 difference at {what}"
        );
        if e > worst.0 {
            worst = (e, what);
        }
    };
    match (&m32, &m64) {
        (Model::Lobe(a), Model::Lobe(b)) => {
            let n = get(cfg, "n").unwrap();
            for c in lobe_samples(n)
                .into_iter()
                .chain((0..=1000).map(|i| i as f64 / 1000.0))
            {
                let c32 = c as f32;
                note(mixed(a.eval(c32), b.eval(c32 as f64)), format!("c={c32}"));
            }
        }
        (Model::Distribution(a), Model::Distribution(b)) => {
            let alpha = get(cfg, "alpha").unwrap();
            for c in samples(&m64, alpha) {
                let c32 = c as f32;
                note(
                    mixed(a.eval(c32), b.eval(c32 as f64)),
                    format!("cos_h={c32}"),
                );
            }
        }
        (Model::Shadowing(a), Model::Shadowing(b)) => {
            for (wi, wo) in direction_pairs(400, 5) {
                let h = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
                let l = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
                let h = [h[0] / l, h[1] / l, h[2] / l];
                let vh = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2];
                let s32 = ShadowInput {
                    cos_v: wo[2] as f32,
                    cos_l: Some(wi[2] as f32),
                    cos_h: h[2] as f32,
                    cos_vh: vh as f32,
                };
                let s64 = ShadowInput {
                    cos_v: s32.cos_v as f64,
                    cos_l: s32.cos_l.map(f64::from),
                    cos_h: s32.cos_h as f64,
                    cos_vh: s32.cos_vh as f64,
                };
                note(mixed(a.g(&s32), b.g(&s64)), format!("{s32:?}"));
                let (o32, o64) = (
                    ShadowInput { cos_l: None, ..s32 },
                    ShadowInput { cos_l: None, ..s64 },
                );
                note(mixed(a.g(&o32), b.g(&o64)), format!("{o32:?}"));
            }
        }
        (Model::Fresnel(a), Model::Fresnel(b)) => {
            for i in 0..=2000 {
                let c32 = i as f32 / 2000.0;
                note(mixed(a.f(c32), b.f(c32 as f64)), format!("cos={c32}"));
            }
        }
        (Model::Brdf(a), Model::Brdf(b)) => {
            for (wi, wo) in direction_pairs(600, 3) {
                let (i32, o32) = (wi.map(|x| x as f32), wo.map(|x| x as f32));
                note(
                    mixed(
                        a.eval(i32, o32),
                        b.eval(i32.map(f64::from), o32.map(f64::from)),
                    ),
                    format!("wi={i32:?} wo={o32:?}"),
                );
            }
        }
        _ => unreachable!(),
    }
    worst
}

#[test]
fn f32_tracks_f64_within_the_documented_bound() {
    let mut failures = vec![];
    for e in registry::all() {
        let mut model_worst = (0.0, String::new());
        for cfg in configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf) {
            let (err, at) = worst(e.info.id, &cfg);
            if err > model_worst.0 {
                model_worst = (err, format!("{cfg:?} {at}"));
            }
        }
        println!(
            "f32-vs-f64 {:<24} measured {:.3e} (documented {:.0e}) at {}",
            e.info.id, model_worst.0, e.info.f32_bound, model_worst.1
        );
        if model_worst.0 > e.info.f32_bound {
            failures.push(format!(
                "{}: {:.3e} > {:.0e} at {}",
                e.info.id, model_worst.0, e.info.f32_bound, model_worst.1
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "f32 bound exceeded:\n{}",
        failures.join("\n")
    );
}
