//! The WGSL twin of `gltf-pbr`'s value (`brdf/gltf_pbr.rs`), written per instance from its
//! parts' calls: kept apart from the model's Rust form to keep each file short.

use crate::brdf::gltf_pbr::{Albedo, GltfPbr};
use crate::forms::{DistForm, EnvForm, FresnelForm, ShadowForm};
use crate::microfacet::ms::Ms;
use crate::microfacet::sheen::Vis;
use crate::plan::FresnelPlan;
use crate::real::K;
use crate::wgsl::{Emit, PAIR};

/// The runtime expression of the base's alpha.
const ALPHA_EXPR: &str = "max(p_roughness * p_roughness, 0.005)";
/// The runtime expression of the coat's alpha.
const COAT_ALPHA_EXPR: &str = "max(p_clearcoat_roughness * p_clearcoat_roughness, 0.005)";
/// The runtime expression of the dielectric f0.
const F0D_EXPR: &str = "min((p_ior - 1.0) * (p_ior - 1.0) / ((p_ior + 1.0) * (p_ior + 1.0)) * p_specular_color, 1.0) * p_specular";

/// The sheen slope at runtime.
const SHEEN_ALPHA: &str = "max(p_sheen_roughness, 0.07)";

impl GltfPbr {
    /// The WGSL body (`BrdfForm::wgsl_body`), assembled per instance from its parts' calls
    /// (as `cook-torrance` does), in the three coefficient forms. The runtime form always
    /// carries the sheen and the coat (and the anisotropic stretch when `d` and `g` have one):
    /// its parameters may turn them on; with their defaults they add exactly nothing. The
    /// energy compensation is a choice, so only an instance with it carries it.
    pub(super) fn wgsl_parts(&self, e: &Emit) -> String {
        wgsl_body(self, e)
    }
}

fn wgsl_body(b: &GltfPbr, e: &Emit) -> String {
    let rt = e.is_runtime();
    let mut s = String::from(PAIR);
    let aniso = b.aniso.is_some() || (rt && b.d.aniso() && b.g.aniso());
    let at = format!("({ALPHA_EXPR} + (1.0 - {ALPHA_EXPR}) * p_anisotropy * p_anisotropy)");
    let (s2, v, l) = if aniso {
        let one = K::new(1.0);
        let (xy, yx, c, sn) = match &b.aniso {
            Some(r) => (r.s.x_over_y, r.s.y_over_x, r.cos, r.sin),
            None => (one, one, one, K::new(0.0)),
        };
        let ra = ["roughness", "anisotropy"];
        s += &format!(
            "    let xy = {};\n    let yx = {};\n    let rc = {};\n    let rs = {};\n    let s2 = fb_aniso_sin2(fb_gltf_rot(p.h, rc, rs), xy, yx);\n    let cv = fb_aniso_cos(fb_gltf_rot(p.wo, rc, rs), xy, yx);\n    let cl = fb_aniso_cos(fb_gltf_rot(p.wi, rc, rs), xy, yx);\n",
            e.kx(xy, &format!("{at} / {ALPHA_EXPR}"), &ra),
            e.kx(yx, &format!("{ALPHA_EXPR} / {at}"), &ra),
            e.kx(c, "cos(p_anisotropy_rotation)", &["anisotropy_rotation"]),
            e.kx(sn, "sin(p_anisotropy_rotation)", &["anisotropy_rotation"]),
        );
        ("s2", "cv", "cl")
    } else {
        ("p.sin2_h", "p.cos_o", "p.cos_i")
    };
    let (alpha, alpha_params): (String, &[&str]) = if aniso {
        (
            format!("sqrt({ALPHA_EXPR} * {at})"),
            &["roughness", "anisotropy"],
        )
    } else {
        (ALPHA_EXPR.into(), &["roughness"])
    };
    let (d, g) = e.with_alias("alpha", &alpha, alpha_params, || {
        (
            b.d.wgsl("p.h.z", s2, e),
            b.g.wgsl(v, l, "p.h.z", "p.cos_ih", e),
        )
    });
    let fresnel = |f: &FresnelPlan, f0: (&str, &[&str]), f90: (&str, &[&str]), c: &str| {
        e.with_alias("f0", f0.0, f0.1, || {
            e.with_alias("f90", f90.0, f90.1, || f.wgsl(c, e))
        })
    };
    let fd = fresnel(
        &b.fd,
        (F0D_EXPR, &["ior", "specular_color", "specular"]),
        ("p_specular", &["specular"]),
        "p.cos_ih",
    );
    let fm = fresnel(
        &b.fm,
        ("p_base_color", &["base_color"]),
        ("1.0", &[]),
        "p.cos_ih",
    );
    let base = e.kx(b.base, "p_base_color", &["base_color"]);
    let diff = match b.burley {
        None => format!("{base} * 0.3183098861837907"),
        Some(r) => format!(
            "{base} * 0.3183098861837907 * fb_gltf_burley(p.cos_i, p.cos_o, p.cos_ih, {})",
            e.kx(r, "p_roughness", &["roughness"])
        ),
    };
    let m = e.kx(b.metallic, "p_metallic", &["metallic"]);
    s += &format!(
        "    let d = select(0.0, {d}, p.h.z >= FB_COS_MIN);\n    let g = {g};\n    let denom = 4.0 * (p.cos_i * p.cos_o);\n    let spec = d * g / denom;\n    let fd = {fd};\n    let fm = {fm};\n    let diff = {diff};\n    let m = {m};\n"
    );
    // The energy compensation of each specular term, with its Fresnel ends.
    let ends = |f: &FresnelPlan, f0: (&str, &[&str]), f90: (&str, &[&str])| {
        (fresnel(f, f0, f90, "1.0"), fresnel(f, f0, f90, "0.0"))
    };
    let (fd1, fd0) = ends(
        &b.fd,
        (F0D_EXPR, &["ior", "specular_color", "specular"]),
        ("p_specular", &["specular"]),
    );
    let (fm1, fm0) = ends(&b.fm, ("p_base_color", &["base_color"]), ("1.0", &[]));
    // The diffuse's weight: glTF's 1 - F_d(v . h), or the specular albedo scaling.
    let wd = match &b.spec_albedo {
        None => "(1.0 - fd)",
        Some(sa) => {
            let a = e.kx(sa.alpha, &alpha, alpha_params);
            let ea = |mu: &str| {
                format!(
                    "{fd1} * {} + {fd0} * {}",
                    sa.scale.wgsl(mu, "sa", e),
                    sa.bias.wgsl(mu, "sa", e)
                )
            };
            s += &format!(
                "    let sa = {a};\n    let ea_o = {};\n    let ea_i = {};\n    let wd = max(min(1.0 - ea_o, 1.0 - ea_i), 0.0);\n",
                ea("p.cos_o"),
                ea("p.cos_i")
            );
            "wd"
        }
    };
    let comp = |ss: &str, f1: &str, f0: &str, a: K| match b.ms {
        Ms::None => unreachable!("only called with a compensation"),
        Ms::KullaConty { .. } => format!(
            "fb_ms_kulla_conty({ss}, p.cos_i, p.cos_o, {}, {f1}, {f0})",
            e.kx(a, &alpha, alpha_params)
        ),
        Ms::Filament { .. } => format!(
            "fb_ms_filament({ss}, p.cos_o, {}, {f1})",
            e.kx(a, &alpha, alpha_params)
        ),
    };
    s += &match b.ms {
        Ms::None => {
            format!("    var v = (1.0 - m) * ({wd} * diff + fd * spec) + m * fm * spec;\n")
        }
        Ms::KullaConty { alpha: a } | Ms::Filament { alpha: a } => format!(
            "    let sd = {};\n    let sm = {};\n    var v = (1.0 - m) * ({wd} * diff + sd) + m * sm;\n",
            comp("fd * spec", &fd1, &fd0, a),
            comp("fm * spec", &fm1, &fm0, a)
        ),
    };
    let sh = &b.sheen;
    if sh.on || rt {
        let sr = ["sheen_roughness"];
        let mix = |k: K, x: f64, y: f64| {
            e.kx(
                k,
                &format!(
                    "({x:?}) + (({y:?}) - ({x:?})) * (1.0 - {SHEEN_ALPHA}) * (1.0 - {SHEEN_ALPHA})"
                ),
                &sr,
            )
        };
        const L0: [f64; 5] = [21.5473, 3.82987, 0.19823, -1.97760, -4.32054];
        const L1: [f64; 5] = [25.3245, 3.32435, 0.16801, -1.27393, -4.85967];
        let ls: Vec<String> = (0..5).map(|k| mix(sh.c.l[k], L0[k], L1[k])).collect();
        s += &format!(
            "    let ls = array<f32, 5>({});\n    let lh = {};\n    let ds = fb_sheen_d(p.sin2_h, {}, {});\n",
            ls.join(", "),
            e.kx(sh.c.l_half, "fb_sheen_l(0.5, ls)", &sr),
            e.kx(
                sh.c.norm,
                &format!("(2.0 + 1.0 / {SHEEN_ALPHA}) / 6.283185307179586"),
                &sr
            ),
            e.kx(sh.c.expo, &format!("0.5 / {SHEEN_ALPHA}"), &sr),
        );
        s += match sh.vis {
            Vis::Charlie => "    let vs = fb_sheen_v_charlie(p.cos_o, p.cos_i, ls, lh);\n",
            Vis::Neubelt => "    let vs = fb_sheen_v_neubelt(p.cos_o, p.cos_i);\n",
        };
        let smax = if sh.max_given {
            e.kx(sh.max, "p_sheen_max", &["sheen_max"])
        } else {
            e.kx(sh.max, "p_sheen_color", &["sheen_color"])
        };
        let scale = match sh.albedo {
            Albedo::None => "1.0".to_string(),
            Albedo::Fit => {
                let k = e.kx(
                    sh.fit_k,
                    &format!(
                        "1.0 / (4.16526551 + exp(-7.97291361 * sqrt({SHEEN_ALPHA}) + 6.33516894))"
                    ),
                    &sr,
                );
                s += &format!(
                    "    let eo = fb_sheen_fit(p.cos_o, {k});\n    let ei = fb_sheen_fit(p.cos_i, {k});\n"
                );
                format!("max(min(1.0 - {smax} * eo, 1.0 - {smax} * ei), 0.0)")
            }
            Albedo::Table => {
                let ri = e.kx(
                    sh.row.0 as f64,
                    &format!("fb_sheen_row({SHEEN_ALPHA}).x"),
                    &sr,
                );
                let rtt = e.kx(sh.row.1, &format!("fb_sheen_row({SHEEN_ALPHA}).y"), &sr);
                let charlie = sh.vis == Vis::Charlie;
                s += &format!(
                    "    let si = i32({ri});\n    let st = {rtt};\n    let eo = fb_sheen_table({charlie}, si, st, p.cos_o);\n    let ei = fb_sheen_table({charlie}, si, st, p.cos_i);\n"
                );
                format!("max(min(1.0 - {smax} * eo, 1.0 - {smax} * ei), 0.0)")
            }
        };
        s += &format!(
            "    v = {} * ds * vs + v * {scale};\n",
            e.kx(sh.color, "p_sheen_color", &["sheen_color"])
        );
    }
    let c = &b.coat;
    if c.on || rt {
        let (dc, gc) = e.with_alias("alpha", COAT_ALPHA_EXPR, &["clearcoat_roughness"], || {
            (
                c.d.wgsl("p.h.z", "p.sin2_h", e),
                c.g.wgsl("p.cos_o", "p.cos_i", "p.h.z", "p.cos_ih", e),
            )
        });
        let fc = fresnel(&c.f, ("0.04", &[]), ("1.0", &[]), "p.cos_o");
        s += &format!(
            "    let dc = select(0.0, {dc}, p.h.z >= FB_COS_MIN);\n    let gc = {gc};\n    let wc = {} * {fc};\n    v = v * (1.0 - wc) + wc * dc * gc / denom;\n",
            e.kx(c.weight, "p_clearcoat", &["clearcoat"])
        );
    }
    s += "    return select(0.0, v, p.valid);\n";
    s
}
