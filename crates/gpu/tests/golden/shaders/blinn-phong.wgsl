// fastbrdf 0.1.0 (brdf): blinn-phong
// Made by: fastbrdf shader --model blinn-phong --lang wgsl
//
// Formula: coef(n) lobe(n . h) / (4 wi . h) (energy) or lobe(n . h) (none)
// Source: Blinn 1977; Torrance & Sparrow 1967 (microfacet form); seed 001 (coef by Int(n))
// Note: ops are the wrapper's, add the lobe's; albedo <= 1 with norm = energy; f32: cos_h rounded once to f32 moves flog-normalized-clamped near its zero by up to 0.3, times coef(n) / (4 wi.h): 265 at n = 10000 (check --full); 2 for flog-normalized
// Parameters (this export: lobe = pow, n = 20, norm = energy):
//   lobe: lobe id (one of pow, schlick, schlick-modified, gauss, flog, flog-normalized, flog-normalized-clamped, cubic, cubic3, rational, cubic-rational, power4, power8, power16, sg, ue4-phong-approx, power4-tuned, power8-tuned, power16-tuned, sg-tuned, cubic-rational-tuned, default pow)
//   n: specular exponent (range [1, 10000], default 20)
//   norm: energy: coef(n) = 1 / (2 pi Int(n)); none: the bare lobe (one of energy, none, default energy)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 6e2 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_blinn_phong(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

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

/// Normalises wi and wo (local frame, normal +z) and builds their half vector.
fn fb_pair(wi_in: vec3<f32>, wo_in: vec3<f32>) -> FbPair {
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

/// pow: c^n, the Phong/Blinn-Phong reference (Phong 1975). Cost: 1 pow (exp2 + log2).
fn fb_lobe_pow(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    return select(0.0, pow(x, n), x > 0.0);
}

/// blinn-phong: coef(n) lobe(n . h) / (4 wi . h) (energy) or lobe(n . h) (none)
/// Source: Blinn 1977; Torrance & Sparrow 1967 (microfacet form); seed 001 (coef by Int(n)). Instance: lobe = pow, n = 20, norm = energy.
fn fb_blinn_phong(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = fb_pair(wi, wo);
    let v = 3.5014088f * fb_lobe_pow(p.h.z, 20.0f) / (4.0 * p.cos_ih);
    return select(0.0, v, p.valid);
}
