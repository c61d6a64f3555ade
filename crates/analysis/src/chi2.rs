//! `fastbrdf chi2`'s outputs, shared by the CLI and the Python package: the sizes
//! ([`config`]), the JSON object ([`json`]) and the picture of the histograms ([`picture`]).
//! The test itself is the core crate's (`fastbrdf::chi2`).

use fastbrdf::ModelSpec;
use fastbrdf::chi2::{Config, Outcome};
use fastbrdf::sample::Strategy;

/// The most samples a test draws.
pub const MAX_SAMPLES: usize = 100_000_000;

/// The most bins in theta (phi gets twice as many).
pub const MAX_RES: usize = 1000;

/// The test's sizes: the CI's (10 x 20 bins, 1e5 samples) or, `full`, Mitsuba's (101 x 202,
/// 1e6), with `samples` (1 to [`MAX_SAMPLES`]) and `res` (theta bins, 1 to [`MAX_RES`]) when
/// given. A message starts with the argument's name (`samples 0: expected ...`).
pub fn config(
    full: bool,
    samples: Option<usize>,
    res: Option<usize>,
    seed: u64,
) -> Result<Config, String> {
    let mut cfg = if full { Config::full() } else { Config::ci() };
    if let Some(n) = samples {
        if n == 0 || n > MAX_SAMPLES {
            return Err(format!("samples {n}: expected 1 to {MAX_SAMPLES}"));
        }
        cfg.samples = n;
    }
    if let Some(r) = res {
        if !(1..=MAX_RES).contains(&r) {
            return Err(format!("res {r}: expected 1 to {MAX_RES}"));
        }
        cfg.res_theta = r;
        cfg.res_phi = 2 * r;
    }
    cfg.seed = seed;
    Ok(cfg)
}

/// `fastbrdf chi2 --json`'s object: the outcome's fields, then `model`, `strategy`, `theta_i`
/// (degrees) and `params` (numbers as numbers, choices as their names).
pub fn json(
    out: &Outcome,
    model: &str,
    strategy: Strategy,
    theta_i: f64,
    spec: &ModelSpec,
) -> serde_json::Value {
    let mut v = serde_json::to_value(out).expect("numbers serialise");
    v["model"] = model.into();
    v["strategy"] = strategy.name().into();
    v["theta_i"] = theta_i.into();
    // Numbers as numbers, choices as their names (issue 27).
    v["params"] = crate::params_json(spec).into();
    v
}

/// A PNG: observed | expected | difference (red: more observed, blue: fewer, scaled by the
/// expected count's standard deviation, saturating at 4), theta down, phi across, each bin a
/// block of pixels, each panel labelled (the renderer's labelled grid, `compare::grid`).
pub fn picture(o: &Outcome) -> Result<Vec<u8>, String> {
    let (rt, rp) = (o.res_theta, o.res_phi);
    let scale = (600 / rp).clamp(1, 16);
    let (pw, ph) = (rp * scale, rt * scale);
    let max = o
        .observed
        .iter()
        .chain(o.expected.iter())
        .fold(0.0f64, |m, v| m.max(*v))
        .max(1e-300);
    let heat = |v: f64| -> [u8; 3] {
        // A dark-to-bright ramp (black, purple, orange, yellow).
        let t = (v / max).clamp(0.0, 1.0).sqrt();
        let r = (255.0 * (1.5 * t).min(1.0)) as u8;
        let g = (255.0 * (2.0 * t - 1.0).clamp(0.0, 1.0)) as u8;
        let b = (255.0 * (0.6 - (t - 0.3).abs() * 2.0).clamp(0.0, 0.6)) as u8;
        [r, g, b]
    };
    let mut panels = vec![vec![0u8; pw * ph * 3]; 3];
    for i in 0..rt {
        for j in 0..rp {
            let k = i * rp + j;
            let (ob, ex) = (o.observed[k], o.expected[k]);
            let d = ((ob - ex) / ex.max(1.0).sqrt() / 4.0).clamp(-1.0, 1.0);
            let diff = if d >= 0.0 {
                [255, (255.0 * (1.0 - d)) as u8, (255.0 * (1.0 - d)) as u8]
            } else {
                [(255.0 * (1.0 + d)) as u8, (255.0 * (1.0 + d)) as u8, 255]
            };
            for (panel, c) in panels.iter_mut().zip([heat(ob), heat(ex), diff]) {
                for y in i * scale..(i + 1) * scale {
                    for x in j * scale..(j + 1) * scale {
                        let p = (y * pw + x) * 3;
                        panel[p..p + 3].copy_from_slice(&c);
                    }
                }
            }
        }
    }
    let labels = ["observed", "expected", "difference (red +, blue -)"];
    let cells: Vec<fastbrdf_render::compare::Cell> = labels
        .iter()
        .zip(panels)
        .map(|(l, rgb)| fastbrdf_render::compare::Cell {
            label: l.to_string(),
            rgb,
        })
        .collect();
    let (rgb, w, h) = fastbrdf_render::compare::grid(&[cells], pw as u32, ph as u32, None)
        .map_err(|e| format!("chi-square picture: {e}"))?;
    let mut png = Vec::new();
    {
        use image::ImageEncoder;
        image::codecs::png::PngEncoder::new(&mut png)
            .write_image(&rgb, w, h, image::ExtendedColorType::Rgb8)
            .map_err(|e| format!("PNG encoding: {e}"))?;
    }
    Ok(png)
}
