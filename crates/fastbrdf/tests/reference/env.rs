//! The split-sum terms against adaptive quadrature of their definition and Karis's fits.

use super::*;

/// The split-sum terms of GGX with height-correlated Smith, from their definition: the
/// integral over light directions of `w(v.h) D G2 / (4 cos_v cos_l) cos_l` with
/// `w = 1 - (1 - v.h)^5` (scale) or `(1 - v.h)^5` (bias), every factor written here from the
/// published formulas (Walter et al. 2007's GGX D; Heitz 2014's correlated G2), integrated by
/// the adaptive Gauss-Kronrod of `quad::albedo` around the mirror direction (another
/// variable and another rule than `env-brdf`'s product Gauss-Legendre in the half vector).
pub(crate) fn ref_env(cos_v: f64, alpha: f64, bias: bool) -> f64 {
    let a2 = alpha * alpha;
    let v = [(1.0 - cos_v * cos_v).sqrt(), 0.0, cos_v];
    let lambda = |c: f64| ((1.0 + a2 * (1.0 - c * c) / (c * c)).sqrt() - 1.0) / 2.0;
    let f = |l: [f64; 3]| {
        let h = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
        let n = dotv(h, h).sqrt();
        let h = [h[0] / n, h[1] / n, h[2] / n];
        let (ch, vh, cl) = (h[2], dotv(v, h), l[2]);
        if cl <= 0.0 || ch <= 0.0 {
            return 0.0;
        }
        let t2 = (1.0 - ch * ch) / (ch * ch);
        let d = a2 / (PI * ch.powi(4) * (a2 + t2).powi(2));
        let g2 = 1.0 / (1.0 + lambda(cos_v) + lambda(cl));
        let f5 = (1.0 - vh).powi(5);
        let w = if bias { f5 } else { 1.0 - f5 };
        w * d * g2 / (4.0 * cos_v * cl)
    };
    let mirror = [-v[0], 0.0, v[2]];
    fastbrdf::quad::albedo(f, mirror, &[], 1e-9).0
}

/// Karis's `EnvBRDFApprox` as printed (UE4 mobile, 2014), with the bias clamped at 0.
pub(crate) fn ref_env_approx(cos_v: f64, alpha: f64, c: &[f64; 11], bias: bool) -> f64 {
    let r = alpha.sqrt();
    let p = [0, 1, 2, 3].map(|i| r * c[i] + c[i + 4]);
    let a004 = (p[0] * p[0]).min((c[8] * cos_v).exp2()) * p[0] + p[1];
    let v = if bias {
        c[10] * a004 + p[3]
    } else {
        c[9] * a004 + p[2]
    };
    v.max(0.0)
}

pub(crate) fn env64(id: &str, bias: bool) -> Box<dyn fastbrdf::model::Env<f64>> {
    let term = if bias { "bias" } else { "scale" };
    match build::<f64>(id, &[("term", term)]).unwrap() {
        Model::Env(e) => e,
        _ => panic!("{id} is not a split-sum term"),
    }
}

/// `env-brdf`'s fixed rule against adaptive quadrature of the definition, within its
/// documented quadrature error, on views from grazing (0.001) to normal and the whole alpha
/// range; and the white-furnace anchors (scale + bias = the directional albedo with F = 1)
/// that a three.js issue published for GGX with height-correlated Smith: 0.86, 0.66, 0.45,
/// 0.31 at perceptual roughness r (alpha = r^2) and cos_v (0.5, 0.5), (0.75, 0.5), (1, 0.5),
/// (1, 1).
#[test]
fn env_brdf_matches_adaptive_quadrature_of_its_definition_and_the_furnace_anchors() {
    let (scale, bias) = (env64("env-brdf", false), env64("env-brdf", true));
    let mut worst: f64 = 0.0;
    for cos_v in [0.001, 0.01, 0.1, 0.3, 0.5, 0.8, 0.999, 1.0] {
        for alpha in [0.005, 0.01, 0.05, 0.2, 0.5, 1.0] {
            for (m, b) in [(&scale, false), (&bias, true)] {
                let (got, want) = (m.e(cos_v, alpha), ref_env(cos_v.min(1.0 - 1e-12), alpha, b));
                worst = worst.max((got - want).abs());
                assert!(
                    (got - want).abs() <= fastbrdf::microfacet::env_brdf::QUADRATURE_ERROR,
                    "env-brdf bias={b} cos_v={cos_v} alpha={alpha}: {got} vs {want}"
                );
            }
        }
    }
    println!("env-brdf vs adaptive quadrature: max abs {worst:.2e}");
    for (r, cos_v, want) in [
        (0.5, 0.5, 0.86),
        (0.75, 0.5, 0.66),
        (1.0, 0.5, 0.45),
        (1.0, 1.0, 0.31),
    ] {
        let a: f64 = r * r;
        let got = scale.e(cos_v, a) + bias.e(cos_v, a);
        assert!(
            (got - want).abs() < 0.01,
            "r={r} cos_v={cos_v}: {got} vs {want}"
        );
    }
}

#[test]
fn env_brdf_approximations_match_karis_formula() {
    use fastbrdf::microfacet::env_brdf::{KARIS, TUNED};
    for (id, c) in [("env-brdf-approx", KARIS), ("env-brdf-approx-tuned", TUNED)] {
        for b in [false, true] {
            let m = env64(id, b);
            for i in 0..=20 {
                for j in 0..=20 {
                    let (v, a) = (i as f64 / 20.0, 0.005 + 0.995 * j as f64 / 20.0);
                    let want = ref_env_approx(v, a, &c, b);
                    assert!((m.e(v, a) - want).abs() < 1e-14, "{id} {b} {v} {a}");
                }
            }
        }
    }
}

/// MaterialX's `mx_ggx_dir_albedo_analytic` as printed (libraries/pbrlib/genglsl/lib/
/// mx_microfacet_specular.glsl): `r = c0 + c1 x + c2 y + c3 x y + c4 x^2 + c5 y^2 + c6 x^2 y +
/// c7 x y^2 + c8 x^2 y^2` with `vec4` coefficients, `(scale, bias) = r.xy / r.zw`, summed
/// monomial by monomial; clamped at 0.
pub(crate) fn ref_env_rational(x: f64, y: f64, c: &[[f64; 9]; 4], bias: bool) -> f64 {
    let mono = [
        1.0,
        x,
        y,
        x * y,
        x * x,
        y * y,
        x * x * y,
        x * y * y,
        x * x * y * y,
    ];
    let r: Vec<f64> = (0..4)
        .map(|k| mono.iter().zip(c[k].iter()).map(|(m, c)| m * c).sum())
        .collect();
    let v = if bias { r[1] / r[3] } else { r[0] / r[2] };
    v.max(0.0)
}

#[test]
fn env_brdf_rational_fits_match_materialx_formula() {
    use fastbrdf::microfacet::env_rational::{MATERIALX, TUNED};
    // MaterialX's vec4 rows, copied from the shader: the Rust constants are their transpose.
    let rows: [[f64; 4]; 9] = [
        [0.10031, 0.93450, 1.0, 1.0],
        [-0.63301, -2.32352, -1.76427, 0.22797],
        [9.74995, 2.22823, 8.26501, 15.93688],
        [-2.02075, -3.74584, 11.54840, -55.82466],
        [29.38247, 1.42450, 28.99991, 13.07919],
        [-8.24713, -0.76829, -7.50867, 41.25882],
        [-26.51510, 1.43366, -36.16186, 54.86775],
        [19.98406, 0.29060, 15.85408, 300.10923],
        [-5.41717, 0.62933, 33.41550, -284.73288],
    ];
    let printed: [[f64; 9]; 4] = std::array::from_fn(|k| std::array::from_fn(|m| rows[m][k]));
    assert_eq!(printed, MATERIALX);
    for (id, c) in [
        ("env-brdf-materialx", printed),
        ("env-brdf-materialx-tuned", TUNED),
    ] {
        for b in [false, true] {
            let m = env64(id, b);
            for i in 0..=20 {
                for j in 0..=20 {
                    let (v, a) = (i as f64 / 20.0, 0.005 + 0.995 * j as f64 / 20.0);
                    let want = ref_env_rational(v, a, &c, b);
                    assert!(
                        (m.e(v, a) - want).abs() < 1e-13 * want.max(1.0),
                        "{id} {b} {v} {a}"
                    );
                }
            }
        }
    }
}

/// `env-brdf-table` against a table built here from the adaptive-quadrature reference: texel
/// (i, j) at cos_v = (i + 0.5) / N, perceptual roughness (j + 0.5) / N (alpha = r^2, at
/// least 0.005), rounded to f32 and then to the storage (unorm8 by f64 rounding of 255 v;
/// binary16 by rounding to the spacing of its exponent), and a bilinear clamp-to-edge fetch
/// written out. Only the 4 texels around each probe are computed (the reference quadrature is
/// slow); the rule's own values differ from adaptive quadrature by up to QUADRATURE_ERROR at
/// grazing, so texels within 0.05 of grazing are compared with that tolerance and the rest at
/// 2e-5 (plus a storage step where the rounding of nearly equal values can differ).
#[test]
fn env_brdf_table_matches_a_table_built_from_the_definition() {
    let stored = |v: f64, bits: u32| -> f64 {
        let v = v as f32 as f64;
        match bits {
            8 => (v.clamp(0.0, 1.0) * 255.0).round() / 255.0,
            16 => {
                let e = v.log2().floor().max(-14.0);
                let ulp = (e - 10.0).exp2();
                (v / ulp).round() * ulp
            }
            _ => v,
        }
    };
    for (size, bits) in [(16usize, 8u32), (32, 16), (64, 32), (128, 16)] {
        for bias in [false, true] {
            let term = if bias { "bias" } else { "scale" };
            let m = match build::<f64>(
                "env-brdf-table",
                &[
                    ("term", term),
                    ("size", &size.to_string()),
                    ("bits", &bits.to_string()),
                ],
            )
            .unwrap()
            {
                Model::Env(e) => e,
                _ => unreachable!(),
            };
            let n = size as f64;
            for (v, a) in [(0.3, 0.2), (0.77, 0.05), (0.5, 0.6), (0.92, 0.9)] {
                let texel = |i: f64, j: f64| -> f64 {
                    let (cv, r) = ((i + 0.5) / n, (j + 0.5) / n);
                    stored(ref_env(cv, (r * r).max(0.005), bias), bits)
                };
                let (sx, sy) = (v * n - 0.5, f64::sqrt(a) * n - 0.5);
                let (i, j) = (sx.floor(), sy.floor());
                let (tx, ty) = (sx - i, sy - j);
                let want = (1.0 - ty) * ((1.0 - tx) * texel(i, j) + tx * texel(i + 1.0, j))
                    + ty * ((1.0 - tx) * texel(i, j + 1.0) + tx * texel(i + 1.0, j + 1.0));
                let step = match bits {
                    8 => 1.0 / 255.0,
                    16 => 1.0 / 2048.0,
                    _ => 0.0,
                };
                let got = m.e(v, a);
                assert!(
                    (got - want).abs() <= 2e-5 + step,
                    "size {size} bits {bits} {term} ({v}, {a}): {got} vs {want}"
                );
            }
        }
    }
}
