// fastbrdf 0.1.0 (brdf): ward-pow
// Made by: fastbrdf shader --model ward-pow --lang wgsl --runtime-params
//
// Formula: cos^(2/alpha^2) theta_h / (4 pi alpha^2 sqrt(cos_i cos_o))
// Source: seed 000 (exp replaced by one power)
// Note: isotropic only; f32: cos_h^(2/alpha^2) of a cosine rounded to f32 has a relative error up to (2/alpha^2) 2^-25 (6e-4 at alpha = 0.01, 2.4e-3 at alpha = 0.005)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   ward-pow vs ward: max rel error <= 0.108 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   ward-pow vs ward: max rel error <= 0.396 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   ward-pow vs ward: max rel error <= 0.108 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   ward-pow vs ward: max rel error <= 0.396 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2.5e-3 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_ward_pow(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_alpha; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// log2(x) with a small relative error for x in [0.5, 1] too, where WGSL's built-in log2 is
/// only held to 2^-21 absolute (relative error unbounded as x -> 1): 2 atanh(t) / ln 2 with
/// t = (x - 1) / (x + 1) in [-1/3, 0], x - 1 exact (Sterbenz), series to t^13 (truncation
/// 5e-9 relative). Below 0.5 the built-in. The CPU kernels' log2 is 0.5 ulp (an f64 series).
fn fb_log2(x: f32) -> f32 {
    let t = (x - 1.0) / (x + 1.0);
    let t2 = t * t;
    let s = t * (2.0 + t2 * (0.6666667 + t2 * (0.4 + t2 * (0.2857143 + t2 * (0.22222222
        + t2 * (0.18181818 + t2 * 0.15384615))))));
    return select(log2(x), s * 1.442695, x >= 0.5);
}

/// x^y for x in [0, 1] (any finite y): exp2(y fb_log2(x)), and 0 at x = 0 (callers with
/// y < 0 cut x = 0 away). WGSL's pow is exp2(y log2(x))
/// with the built-in log2 (2^-21 absolute near 1), which a large y turns into about 2y ulp of
/// relative error near x = 1 (issue 11: twice the "n ulp" once documented, on real GPUs at
/// n = 5000..10000); fb_log2's relative error keeps y log2(x) to a few ulp, so the result is
/// within a few ulp of the exact power where it is not negligible. At x = 1, exactly 1.
fn fb_powr(x: f32, y: f32) -> f32 {
    return select(0.0, exp2(y * fb_log2(max(x, 1e-30))), x > 0.0);
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

/// ward-pow (seed 000): the exponential replaced by cos^e theta_h, e = 2 / alpha^2 (fb_powr).
fn fb_brdf_ward_pow(wi: vec3<f32>, wo: vec3<f32>, e: f32, scale: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let lobe = fb_powr(p.h.z, e);
    return select(0.0, scale * lobe / sqrt(p.cos_i * p.cos_o), p.valid);
}

/// ward-pow: cos^(2/alpha^2) theta_h / (4 pi alpha^2 sqrt(cos_i cos_o))
/// Source: seed 000 (exp replaced by one power). Instance: runtime parameters p_alpha; fixed: no parameters.
fn fb_ward_pow(wi: vec3<f32>, wo: vec3<f32>, p_alpha: f32) -> f32 {
    return fb_brdf_ward_pow(wi, wo, (2.0 / (p_alpha * p_alpha)), (0.07957747154594767 / (p_alpha * p_alpha)));
}
