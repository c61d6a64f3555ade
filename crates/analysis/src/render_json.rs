//! The JSON the CLI prints and Python returns for the same questions, built once: `compare
//! --json`'s scores, `materials --json` and `metals --json`.

use crate::materials::{self, Albedos};
use fastbrdf::colour::{METALS, WAVELENGTHS_NM};
use fastbrdf_render::compare::{LinearMetrics, Metrics};
use serde_json::{Value, json};

/// One model's scores of a comparison: on the clipped 8-bit sRGB pictures (`rmse`, `psnr`,
/// `flip`) and on the linear film (`rmse_linear`, `psnr_linear`, `psnr_linear_peak`,
/// `flip_reinhard`); PSNR null when infinite.
pub fn scores(srgb: &Metrics, linear: &LinearMetrics) -> Value {
    let finite = |x: f64| x.is_finite().then_some(x);
    json!({
        "model": srgb.model,
        "rmse": srgb.rmse,
        "psnr": finite(srgb.psnr),
        "flip": srgb.flip,
        "rmse_linear": linear.rmse,
        "psnr_linear": finite(linear.psnr),
        "psnr_linear_peak": linear.peak,
        "flip_reinhard": linear.flip_reinhard,
    })
}

/// `compare --json`: `{"reference": NAME, "metrics": [scores, ...]}`.
pub fn comparison(reference: &str, rows: Vec<Value>) -> Value {
    json!({"reference": reference, "metrics": rows})
}

fn albedos(a: &Albedos) -> (Value, Value) {
    (json!(a.kd), json!(a.ks))
}

/// `materials --json`: an array of {"name", "blinn_phong": {"n", "kd", "ks"},
/// "cook_torrance": {"m", "f0", "kd", "ks"}, "ward": {"alpha", "kd", "ks"}, "inside":
/// [family, ...]} in the table's order.
pub fn materials() -> Value {
    let rows: Vec<Value> = materials::all()
        .iter()
        .map(|m| {
            let (bkd, bks) = albedos(&m.blinn_phong);
            let (ckd, cks) = albedos(&m.cook_torrance);
            let (wkd, wks) = albedos(&m.ward);
            json!({
                "name": m.name,
                "blinn_phong": {"n": m.blinn_phong_n, "kd": bkd, "ks": bks},
                "cook_torrance": {"m": m.cook_torrance_m, "f0": m.cook_torrance_f0, "kd": ckd, "ks": cks},
                "ward": {"alpha": m.ward_alpha, "kd": wkd, "ks": wks},
                "inside": materials::families(m),
            })
        })
        .collect();
    Value::Array(rows)
}

/// `metals --json`: {"wavelengths_nm": [650, 550, 450], "metals": [{"id", "symbol", "eta",
/// "k", "f0", "source"}, ...]}.
pub fn metals() -> Value {
    let rows: Vec<Value> = METALS
        .iter()
        .map(|m| {
            json!({
                "id": m.id,
                "symbol": m.symbol,
                "eta": m.eta,
                "k": m.k,
                "f0": m.f0(),
                "source": m.source,
            })
        })
        .collect();
    json!({"wavelengths_nm": WAVELENGTHS_NM, "metals": rows})
}
