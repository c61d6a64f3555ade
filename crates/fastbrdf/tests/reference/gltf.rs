//! `gltf-pbr` against the glTF 2.0 specification's formulas as its Appendix B and the
//! extensions' implementation notes print them (issue 33), written here from those texts:
//! vectors, not the crate's pair set-up; Filament's form of the height-correlated visibility
//! `V = 0.5 / (NL sqrt(NV^2 (1 - a^2) + a^2) + NV sqrt(NL^2 (1 - a^2) + a^2))`, not the
//! crate's Smith Lambda; the anisotropic GGX and its visibility from the
//! `KHR_materials_anisotropy` text; the sheen as `KHR_materials_sheen` prints it.

use super::*;
use crate::brdfs::brdf64;

fn ggx_d(a: f64, nh: f64) -> f64 {
    let a2 = a * a;
    let t = nh * nh * (a2 - 1.0) + 1.0;
    a2 / (PI * t * t)
}

fn ggx_v(a: f64, nl: f64, nv: f64) -> f64 {
    let a2 = a * a;
    0.5 / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt())
}

/// KHR_materials_anisotropy's D and V: `at` along `t`, `ab` along `b`.
fn aniso_dv(
    at: f64,
    ab: f64,
    t: [f64; 3],
    b: [f64; 3],
    h: [f64; 3],
    l: [f64; 3],
    v: [f64; 3],
) -> f64 {
    let a2 = at * ab;
    let f = [ab * dotv(t, h), at * dotv(b, h), a2 * h[2]];
    let w2 = a2 / (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    let d = a2 * w2 * w2 / PI;
    let gv = l[2] * ((at * dotv(t, v)).powi(2) + (ab * dotv(b, v)).powi(2) + v[2] * v[2]).sqrt();
    let gl = v[2] * ((at * dotv(t, l)).powi(2) + (ab * dotv(b, l)).powi(2) + l[2] * l[2]).sqrt();
    d * 0.5 / (gv + gl)
}

fn schlick(f0: f64, f90: f64, c: f64) -> f64 {
    f0 + (f90 - f0) * (1.0 - c.abs()).powi(5)
}

fn sheen_l(x: f64, a: f64) -> f64 {
    let t = (1.0 - a) * (1.0 - a);
    let mix = |p: f64, q: f64| p * (1.0 - t) + q * t;
    mix(21.5473, 25.3245) / (1.0 + mix(3.82987, 3.32435) * x.powf(mix(0.19823, 0.16801)))
        + mix(-1.97760, -1.27393) * x
        + mix(-4.32054, -4.85967)
}

fn sheen_lambda(c: f64, a: f64) -> f64 {
    if c.abs() < 0.5 {
        sheen_l(c, a).exp()
    } else {
        (2.0 * sheen_l(0.5, a) - sheen_l(1.0 - c, a)).exp()
    }
}

fn sheen_fit(c: f64, a: f64) -> f64 {
    0.65584461 * (1.0 - c).powi(3)
        + 1.0 / (4.16526551 + (-7.97291361 * a.sqrt() + 6.33516894).exp())
}

#[derive(Clone, Copy)]
struct Mat {
    base: f64,
    metallic: f64,
    rough: f64,
    ior: f64,
    specular: f64,
    specular_color: f64,
    coat: f64,
    coat_rough: f64,
    sheen: f64,
    sheen_rough: f64,
    aniso: f64,
    rot: f64,
    burley: bool,
    fit: bool,
    /// The energy compensation: 0 none, 1 Kulla and Conty, 2 Filament.
    ms: u8,
    /// The specular albedo scaling: 0 glTF's Fresnel mix, else the row of [`SPEC_ALBEDO`].
    sa: u8,
}

/// `spec_albedo`'s choices and the split-sum rows they read (each tested against the
/// quadrature of GGX's albedo in `reference/env.rs` and the DFG ledger).
const SPEC_ALBEDO: [(&str, &str); 4] = [
    ("fresnel", ""),
    ("table", "env-brdf-table"),
    ("materialx", "env-brdf-materialx"),
    ("karis", "env-brdf-approx"),
];

/// The split-sum term `term` of env row `id` at (mu, alpha).
fn env_term(id: &str, term: &str, mu: f64, alpha: f64) -> f64 {
    let spec = fastbrdf::ModelSpec::parse(id, &[("term", term)]).unwrap();
    let fastbrdf::Model::Env(e) = spec.model::<f64>().unwrap() else {
        panic!("{id} is an env model")
    };
    e.e(mu, alpha)
}

const PLAIN: Mat = Mat {
    base: 0.8,
    metallic: 0.0,
    rough: 0.5,
    ior: 1.5,
    specular: 1.0,
    specular_color: 1.0,
    coat: 0.0,
    coat_rough: 0.0,
    sheen: 0.0,
    sheen_rough: 0.0,
    aniso: 0.0,
    rot: 0.0,
    burley: false,
    fit: false,
    ms: 0,
    sa: 0,
};

/// The specification's material, written from its text.
fn spec(m: &Mat, l: [f64; 3], v: [f64; 3]) -> f64 {
    let h = unit([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
    let (nl, nv, nh, vh) = (l[2], v[2], h[2], dotv(v, h));
    let alpha = (m.rough * m.rough).max(0.005);
    let specular_brdf = if m.aniso > 0.0 {
        let at = alpha + (1.0 - alpha) * m.aniso * m.aniso;
        let t = [m.rot.cos(), m.rot.sin(), 0.0];
        let b = [-m.rot.sin(), m.rot.cos(), 0.0];
        aniso_dv(at, alpha, t, b, h, l, v)
    } else {
        ggx_d(alpha, nh) * ggx_v(alpha, nl, nv)
    };
    let f0d = (((m.ior - 1.0) / (m.ior + 1.0)).powi(2) * m.specular_color).min(1.0) * m.specular;
    let fd = schlick(f0d, m.specular, vh);
    let diffuse = if m.burley {
        let f90 = 0.5 + 2.0 * m.rough * dotv(l, h).powi(2);
        m.base / PI * schlick(1.0, f90, nl) * schlick(1.0, f90, nv)
    } else {
        m.base / PI
    };
    // Energy compensation of a specular term ss whose Fresnel is f1 at normal incidence and
    // f0g at grazing (Kulla and Conty 2017; Filament's documentation); E from the crate's
    // table of GGX's albedo (`microfacet::ms`, tested against its quadrature there).
    let compensate = |ss: f64, f1: f64, f0g: f64| {
        use fastbrdf::microfacet::ms::{avg_loss, loss};
        match m.ms {
            0 => ss,
            1 => {
                let e_avg = 1.0 - avg_loss(alpha);
                let favg = (20.0 * f1 + f0g) / 21.0;
                let f_ms = favg * favg * e_avg / (1.0 - favg * (1.0 - e_avg));
                ss + loss(nl, alpha) * loss(nv, alpha) / (PI * (1.0 - e_avg)) * f_ms
            }
            _ => ss * (1.0 + f1 * (1.0 / (1.0 - loss(nv, alpha)) - 1.0)),
        }
    };
    // The diffuse's weight: the specification's 1 - F(v.h), or 1 - E of the specular layer
    // seen from either side (E = F(1) scale + F(0) bias of a split-sum row).
    let weight = if m.sa == 0 {
        1.0 - fd
    } else {
        let id = SPEC_ALBEDO[m.sa as usize].1;
        let e = |mu: f64| {
            f0d * env_term(id, "scale", mu, alpha) + m.specular * env_term(id, "bias", mu, alpha)
        };
        (1.0 - e(nv)).min(1.0 - e(nl)).max(0.0)
    };
    let dielectric = weight * diffuse + compensate(fd * specular_brdf, f0d, m.specular);
    let metal = compensate(schlick(m.base, 1.0, vh) * specular_brdf, m.base, 1.0);
    let mut material = dielectric * (1.0 - m.metallic) + metal * m.metallic;
    if m.sheen > 0.0 {
        let a = m.sheen_rough.max(0.07);
        let sin2h = 1.0 - nh * nh;
        let d = (2.0 + 1.0 / a) * sin2h.powf(0.5 / a) / (2.0 * PI);
        let vis = 1.0 / ((1.0 + sheen_lambda(nv, a) + sheen_lambda(nl, a)) * (4.0 * nv * nl));
        let scaling = if m.fit {
            (1.0 - m.sheen * sheen_fit(nv, a)).min(1.0 - m.sheen * sheen_fit(nl, a))
        } else {
            1.0
        };
        material = m.sheen * d * vis + material * scaling;
    }
    if m.coat > 0.0 {
        let ac = (m.coat_rough * m.coat_rough).max(0.005);
        let coat = ggx_d(ac, nh) * ggx_v(ac, nl, nv);
        let fr = m.coat * schlick(0.04, 1.0, nv);
        material = material * (1.0 - fr) + coat * fr;
    }
    material
}

fn model(m: &Mat) -> Box<dyn fastbrdf::Brdf<f64>> {
    let s = |x: f64| x.to_string();
    let vals = [
        ("base_color", s(m.base)),
        ("metallic", s(m.metallic)),
        ("roughness", s(m.rough)),
        ("ior", s(m.ior)),
        ("specular", s(m.specular)),
        ("specular_color", s(m.specular_color)),
        ("clearcoat", s(m.coat)),
        ("clearcoat_roughness", s(m.coat_rough)),
        ("sheen_color", s(m.sheen)),
        ("sheen_roughness", s(m.sheen_rough)),
        ("anisotropy", s(m.aniso)),
        ("anisotropy_rotation", s(m.rot)),
        (
            "diffuse",
            (if m.burley { "burley" } else { "lambert" }).into(),
        ),
        ("sheen_albedo", (if m.fit { "fit" } else { "none" }).into()),
        (
            "ms",
            ["none", "kulla-conty", "filament"][m.ms as usize].into(),
        ),
        ("spec_albedo", SPEC_ALBEDO[m.sa as usize].0.into()),
    ];
    let given: Vec<(&str, &str)> = vals.iter().map(|(a, b)| (*a, b.as_str())).collect();
    brdf64("gltf-pbr", &given)
}

fn materials() -> Vec<(&'static str, Mat)> {
    vec![
        ("dielectric", PLAIN),
        (
            "rough gold, Kulla-Conty",
            Mat {
                base: 0.9,
                metallic: 1.0,
                rough: 0.8,
                ms: 1,
                ..PLAIN
            },
        ),
        (
            "half metal, Filament's compensation, sheen and coat",
            Mat {
                metallic: 0.5,
                rough: 0.6,
                ms: 2,
                sheen: 0.4,
                sheen_rough: 0.5,
                fit: true,
                coat: 0.5,
                coat_rough: 0.3,
                ..PLAIN
            },
        ),
        (
            "dielectric, specular albedo scaling by Filament's table",
            Mat {
                rough: 0.3,
                sa: 1,
                ..PLAIN
            },
        ),
        (
            "half metal, MaterialX's fit, coloured specular, Kulla-Conty",
            Mat {
                metallic: 0.3,
                rough: 0.7,
                ior: 1.8,
                specular: 0.7,
                specular_color: 1.5,
                sa: 2,
                ms: 1,
                ..PLAIN
            },
        ),
        (
            "dielectric, Karis's fit, sheen and coat",
            Mat {
                rough: 0.5,
                sa: 3,
                sheen: 0.5,
                sheen_rough: 0.3,
                fit: true,
                coat: 0.4,
                coat_rough: 0.2,
                ..PLAIN
            },
        ),
        (
            "dielectric, Kulla-Conty, Burley",
            Mat {
                rough: 0.9,
                ms: 1,
                burley: true,
                ..PLAIN
            },
        ),
        (
            "gold metal",
            Mat {
                base: 0.9,
                metallic: 1.0,
                rough: 0.3,
                ..PLAIN
            },
        ),
        (
            "half metal, smooth",
            Mat {
                metallic: 0.5,
                rough: 0.1,
                ..PLAIN
            },
        ),
        (
            "ior 2.2, coloured specular",
            Mat {
                ior: 2.2,
                specular: 0.6,
                specular_color: 3.0,
                ..PLAIN
            },
        ),
        (
            "burley",
            Mat {
                burley: true,
                rough: 0.8,
                ..PLAIN
            },
        ),
        (
            "clearcoat",
            Mat {
                coat: 0.8,
                coat_rough: 0.2,
                rough: 0.7,
                ..PLAIN
            },
        ),
        (
            "sheen, no scaling",
            Mat {
                sheen: 0.7,
                sheen_rough: 0.4,
                ..PLAIN
            },
        ),
        (
            "sheen, fit scaling",
            Mat {
                sheen: 0.9,
                sheen_rough: 0.6,
                fit: true,
                ..PLAIN
            },
        ),
        (
            "sheen at its floor",
            Mat {
                sheen: 0.5,
                sheen_rough: 0.0,
                fit: true,
                ..PLAIN
            },
        ),
        (
            "anisotropic",
            Mat {
                aniso: 0.7,
                rot: 0.6,
                rough: 0.4,
                metallic: 1.0,
                ..PLAIN
            },
        ),
        (
            "anisotropic, negative rotation",
            Mat {
                aniso: 0.3,
                rot: -2.0,
                rough: 0.2,
                ..PLAIN
            },
        ),
        (
            "everything",
            Mat {
                metallic: 0.3,
                coat: 0.5,
                sheen: 0.4,
                sheen_rough: 0.3,
                aniso: 0.5,
                rot: 1.0,
                burley: true,
                fit: true,
                ..PLAIN
            },
        ),
    ]
}

#[test]
fn gltf_pbr_matches_the_specification() {
    let pairs = direction_pairs(400, 33);
    for (name, m) in materials() {
        let brdf = model(&m);
        let mut worst: f64 = 0.0;
        for (wi, wo) in &pairs {
            let (wi, wo) = (unit(*wi), unit(*wo));
            if wi[2] < 1e-3 || wo[2] < 1e-3 {
                continue;
            }
            let want = spec(&m, wi, wo);
            let got = brdf.eval(wi, wo);
            let err = (got - want).abs() / want.abs().max(1e-3);
            worst = worst.max(err);
            assert!(
                err < 1e-9,
                "{name}: wi {wi:?} wo {wo:?}: {got} against the specification's {want}"
            );
        }
        assert!(worst.is_finite(), "{name}");
    }
}

/// `sheen_albedo = table` reads `E` from the lobe's own quadrature: against the crate's
/// adaptive hemisphere integrator (nested Gauss-Kronrod, a different method) of the
/// specification's sheen lobe, the model's scaling agrees within the table's 2e-2.
#[test]
fn gltf_pbr_sheen_table_scaling_is_the_lobes_albedo() {
    let (mu_o, mu_i, a, c) = (0.7, 0.4, 0.35, 0.8);
    let albedo = |mu: f64| {
        let v = [(1.0 - mu * mu).sqrt(), 0.0, mu];
        let f = |l: [f64; 3]| {
            if l[2] <= 0.0 {
                return 0.0;
            }
            let h = unit([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
            let d = (2.0 + 1.0 / a) * (1.0 - h[2] * h[2]).powf(0.5 / a) / (2.0 * PI);
            // quad::albedo multiplies by the cosine itself.
            d / ((1.0 + sheen_lambda(v[2], a) + sheen_lambda(l[2], a)) * 4.0 * v[2] * l[2])
        };
        fastbrdf::quad::albedo(f, [0.0, 0.0, 1.0], &[], 1e-8).0
    };
    let scale = (1.0 - c * albedo(mu_o)).min(1.0 - c * albedo(mu_i));
    let m = Mat {
        sheen: c,
        sheen_rough: a,
        metallic: 1.0,
        base: 1.0,
        ..PLAIN
    };
    let wo = [(1.0f64 - mu_o * mu_o).sqrt(), 0.0, mu_o];
    let wi = [
        -(1.0f64 - mu_i * mu_i).sqrt() * 0.6,
        (1.0f64 - mu_i * mu_i).sqrt() * 0.8,
        mu_i,
    ];
    let no_sheen = spec(&Mat { sheen: 0.0, ..m }, wi, wo);
    let sheen_only = spec(&m, wi, wo) - no_sheen; // the lobe without scaling
    let table = brdf64(
        "gltf-pbr",
        &[
            ("sheen_color", "0.8"),
            ("sheen_roughness", "0.35"),
            ("base_color", "1"),
            ("metallic", "1"),
            ("roughness", "0.5"),
        ],
    )
    .eval(wi, wo);
    let want = sheen_only + no_sheen * scale;
    assert!((table - want).abs() < 2e-2 * no_sheen, "{table} vs {want}");
}

/// An R,G,B `sheen_color` couples the channels through `max3` (the colour rule sets
/// `sheen_max` in every channel).
#[test]
fn gltf_pbr_sheen_colour_scales_every_channel_by_its_maximum() {
    let spec = fastbrdf::ModelSpec::parse("gltf-pbr", &[("sheen_color", "0.9,0.2,0.1")]).unwrap();
    for ch in spec.channel_specs() {
        let pairs = ch.pairs();
        assert!(
            pairs.iter().any(|(n, v)| n == "sheen_max" && v == "0.9"),
            "{pairs:?}"
        );
    }
}
