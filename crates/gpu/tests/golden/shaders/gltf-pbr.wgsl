// fastbrdf 0.1.0 (brdf): gltf-pbr
// Made by: fastbrdf shader --model gltf-pbr --lang wgsl
//
// Formula: mix(sheen_color D_s V_s + S [(1 - m)((1 - F_d) diffuse + F_d D G / 4 cos_i cos_o) + m F_m D G / 4 cos_i cos_o], D_c G_c / 4 cos_i cos_o, clearcoat F_c(cos_o))
// Source: glTF 2.0 Appendix B; KHR_materials_ior, _specular, _clearcoat, _sheen, _anisotropy; Estevez & Kulla 2017; Burley 2012
// Note: ops exclude D, G and F; the whole material (diffuse included): a renderer gives it kd = 0, ks = 1; f32: 3.5e-2 found by the adversarial search (tests/precision.rs) at cos 1e-6 with anisotropy, where the stretch of directions rounded to f32 dominates
// Parameters (this export: anisotropy = 0, anisotropy_rotation = 0, base_color = 1, clearcoat = 0, clearcoat_roughness = 0, d = ggx, diffuse = lambert, f = schlick, g = smith-ggx-correlated, ior = 1.5, metallic = 1, ms = none, roughness = 1, sheen_albedo = table, sheen_color = 0, sheen_roughness = 0, sheen_v = charlie, spec_albedo = fresnel, specular = 1, specular_color = 1):
//   base_color: baseColorFactor (R,G,B for a colour) (range [0, 1], default 1)
//   metallic: metallicFactor (range [0, 1], default 1)
//   roughness: roughnessFactor; alpha = max(roughness^2, 0.005) (range [0, 1], default 1)
//   ior: KHR_materials_ior: the dielectric's index of refraction (range [1, 5], default 1.5)
//   specular: KHR_materials_specular: specularFactor (range [0, 1], default 1)
//   specular_color: KHR_materials_specular: specularColorFactor (F0 colour) (range [0, 10], default 1)
//   clearcoat: KHR_materials_clearcoat: clearcoatFactor (range [0, 1], default 0)
//   clearcoat_roughness: KHR_materials_clearcoat: clearcoatRoughnessFactor (range [0, 1], default 0)
//   sheen_color: KHR_materials_sheen: sheenColorFactor (range [0, 1], default 0)
//   sheen_roughness: KHR_materials_sheen: sheenRoughnessFactor (at least 0.07 in the lobe) (range [0, 1], default 0)
//   sheen_max: max3(sheenColor), which the sheen's albedo scaling uses (set from an R,G,B sheen_color; else sheen_color) (range [0, 1], default -)
//   anisotropy: KHR_materials_anisotropy: anisotropyStrength (range [0, 1], default 0)
//   anisotropy_rotation: KHR_materials_anisotropy: anisotropyRotation (radians from the tangent, the frame's x axis) (range [-6.283185307179586, 6.283185307179586], default 0)
//   d: microfacet distribution of the base and the coat (one of ggx, beckmann, default ggx)
//   g: shadowing-masking term of the base and the coat (the exact height-correlated Smith term first, then the shortcuts engines use) (one of smith-ggx-correlated, smith-ggx-correlated-fast, smith-ggx-correlated-fast-tuned, smith-ggx-joint-approx, smith-ggx, schlick-ggx, smith, default smith-ggx-correlated)
//   f: the curve of every Schlick Fresnel term (one of schlick, schlick-sg, schlick-sg-tuned, default schlick)
//   diffuse: the base's diffuse lobe (one of lambert, burley, default lambert)
//   sheen_v: sheen visibility: Charlie's fit (Estevez and Kulla 2017) or Neubelt and Pettineo's (one of charlie, neubelt, default charlie)
//   spec_albedo: what weights the dielectric's diffuse: fresnel (glTF's 1 - F(v.h)), or the specular albedo scaling 1 - E(cos) with E from a DFG ledger row: table (env-brdf-table, 32 x 32 half float), materialx (env-brdf-materialx), karis (env-brdf-approx); needs d = ggx, g = smith-ggx-correlated (one of fresnel, table, materialx, karis, default fresnel)
//   ms: energy compensation for multiple scattering: none, kulla-conty (Kulla and Conty 2017), filament (Filament's, view direction wo only; not reciprocal); needs d = ggx, g = smith-ggx-correlated (one of none, kulla-conty, filament, default none)
//   sheen_albedo: the sheen's directional albedo E: 32 x 32 table of the quadrature, the analytic fit, or no scaling (one of table, fit, none, default table)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 5e-2 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_gltf_pbr(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// The geometry of a direction pair (twin: ops::pair and fastbrdf::vec3::Pair::new).
struct FbPair {
    /// Both directions non-zero, above the surface (cos >= FB_COS_MIN), not opposite.
    valid: bool,
    /// cos theta_i (wi . n) and cos theta_o (wo . n), n = +z.
    cos_i: f32,
    cos_o: f32,
    /// The half vector, normalised.
    h: vec3<f32>,
    /// sin^2 theta_h = h.x^2 + h.y^2.
    sin2_h: f32,
    /// wi . h, computed as |wi + wo| / 2 (exactly symmetric in wi and wo).
    cos_ih: f32,
    /// The normalised directions.
    wi: vec3<f32>,
    wo: vec3<f32>,
}

/// v divided by its largest component when |v|^2 leaves [2^-100, 2^100] (where it would
/// underflow to 0 or overflow in f32, and a finite direction such as (1e-30, 0, 1e-30) would
/// read as zero-length), else v: the normalisation is then scale-safe, as the CPU's
/// (twin: fastbrdf::vec3::unit).
fn fb_rescale(v: vec3<f32>) -> vec3<f32> {
    let l = dot(v, v);
    let m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    let safe = (l >= 7.888609052210118e-31) & (l <= 1.2676506002282294e30);
    return select(v / m, v, safe | (m == 0.0));
}

/// Normalises wi and wo (local frame, normal +z, any finite length) and builds their half vector.
fn fb_pair(wi_raw: vec3<f32>, wo_raw: vec3<f32>) -> FbPair {
    let wi_in = fb_rescale(wi_raw);
    let wo_in = fb_rescale(wo_raw);
    let li = dot(wi_in, wi_in);
    let lo = dot(wo_in, wo_in);
    let wi = wi_in * (1.0 / sqrt(li));
    let wo = wo_in * (1.0 / sqrt(lo));
    let s = wi + wo;
    let len = sqrt(dot(s, s));
    let h = s / len;
    let valid = (li > 0.0) & (lo > 0.0) & (wi.z >= FB_COS_MIN) & (wo.z >= FB_COS_MIN) & (len > 0.0);
    return FbPair(valid, wi.z, wo.z, h, h.x * h.x + h.y * h.y, 0.5 * len, wi, wo);
}

/// ggx (Trowbridge & Reitz 1975; Walter et al. 2007): alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2),
/// given cos and sin^2 of theta_h; scale = alpha^2 / pi. No cancellation at small alpha.
fn fb_d_ggx(c: f32, s2: f32, alpha2: f32, scale: f32) -> f32 {
    let t = alpha2 * (c * c) + s2;
    return scale / (t * t);
}

/// sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c, for the GGX Smith terms
/// (1 + Lambda = (1 + S) / 2; no S - 1 is formed).
fn fb_ggx_s(c: f32, alpha2: f32) -> f32 {
    let s2 = (1.0 - c) * (1.0 + c);
    return sqrt(c * c + alpha2 * s2) / c;
}

/// smith-ggx-correlated (Heitz 2014, eq. 99): 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (S(v) + S(l)).
fn fb_g_smith_ggx_correlated(cos_v: f32, cos_l: f32, alpha2: f32) -> f32 {
    let v = min(cos_v, 1.0);
    let l = min(cos_l, 1.0);
    return 2.0 / (fb_ggx_s(v, alpha2) + fb_ggx_s(l, alpha2));
}

/// fresnel-schlick (Schlick 1994): f0 + (f90 - f0)(1 - c)^5.
fn fb_f_schlick(c: f32, f0: f32, f90: f32) -> f32 {
    let m = 1.0 - fb_clamp01(c);
    let m2 = m * m;
    return f0 + (f90 - f0) * (m2 * m2 * m);
}

/// gltf-pbr: mix(sheen_color D_s V_s + S [(1 - m)((1 - F_d) diffuse + F_d D G / 4 cos_i cos_o) + m F_m D G / 4 cos_i cos_o], D_c G_c / 4 cos_i cos_o, clearcoat F_c(cos_o))
/// Source: glTF 2.0 Appendix B; KHR_materials_ior, _specular, _clearcoat, _sheen, _anisotropy; Estevez & Kulla 2017; Burley 2012. Instance: anisotropy = 0, anisotropy_rotation = 0, base_color = 1, clearcoat = 0, clearcoat_roughness = 0, d = ggx, diffuse = lambert, f = schlick, g = smith-ggx-correlated, ior = 1.5, metallic = 1, ms = none, roughness = 1, sheen_albedo = table, sheen_color = 0, sheen_roughness = 0, sheen_v = charlie, spec_albedo = fresnel, specular = 1, specular_color = 1.
fn fb_gltf_pbr(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = fb_pair(wi, wo);
    let d = select(0.0, fb_d_ggx(p.h.z, p.sin2_h, 1.0f, 0.31830987f), p.h.z >= FB_COS_MIN);
    let g = fb_g_smith_ggx_correlated(p.cos_o, p.cos_i, 1.0f);
    let denom = 4.0 * (p.cos_i * p.cos_o);
    let spec = d * g / denom;
    let fd = fb_f_schlick(p.cos_ih, 0.04f, 1.0f);
    let fm = fb_f_schlick(p.cos_ih, 1.0f, 1.0f);
    let diff = 1.0f * 0.3183098861837907;
    let m = 1.0f;
    var v = (1.0 - m) * ((1.0 - fd) * diff + fd * spec) + m * fm * spec;
    return select(0.0, v, p.valid);
}
