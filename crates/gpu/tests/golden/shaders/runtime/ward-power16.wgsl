// fastbrdf 0.1.0 (brdf): ward-power16
// Made by: fastbrdf shader --model ward-power16 --lang wgsl --runtime-params
//
// Formula: max(0, 1 + (2/alpha^2/16)(cos theta_h - 1))^16 / (4 pi alpha^2 sqrt(cos_i cos_o))
// Source: seed 000 (g = 16 form of the exponential)
// Note: isotropic only
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   ward-power16 vs ward: max rel error <= 0.142 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   ward-power16 vs ward: max rel error <= 0.549 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   ward-power16 vs ward: max rel error <= 0.142 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   ward-power16 vs ward: max rel error <= 0.549 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 1e-5 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_ward_power16(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_alpha; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// x^4, x^8 and x^16 by repeated squaring (twin: ops::pow2k).
fn fb_pow4(x: f32) -> f32 {
    let x2 = x * x;
    return x2 * x2;
}

fn fb_pow8(x: f32) -> f32 {
    let x4 = fb_pow4(x);
    return x4 * x4;
}

fn fb_pow16(x: f32) -> f32 {
    let x8 = fb_pow8(x);
    return x8 * x8;
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

/// ward-power16 (seed 000): the exponential replaced by max(1 + s (cos theta_h - 1), 0)^16,
/// s = (2 / alpha^2) / 16.
fn fb_brdf_ward_power16(wi: vec3<f32>, wo: vec3<f32>, s: f32, scale: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let lobe = fb_pow16(max(1.0 + s * (-p.sin2_h / (1.0 + p.h.z)), 0.0));
    return select(0.0, scale * lobe / sqrt(p.cos_i * p.cos_o), p.valid);
}

/// ward-power16: max(0, 1 + (2/alpha^2/16)(cos theta_h - 1))^16 / (4 pi alpha^2 sqrt(cos_i cos_o))
/// Source: seed 000 (g = 16 form of the exponential). Instance: runtime parameters p_alpha; fixed: no parameters.
fn fb_ward_power16(wi: vec3<f32>, wo: vec3<f32>, p_alpha: f32) -> f32 {
    return fb_brdf_ward_power16(wi, wo, (0.125 / (p_alpha * p_alpha)), (0.07957747154594767 / (p_alpha * p_alpha)));
}
