// fastbrdf 0.1.0 (brdf): phong
// Made by: fastbrdf shader --model phong --lang wgsl --runtime-params
//
// Formula: coef(n) lobe(reflect(wi) . wo), coef(n) = 1 / (2 pi Int(n))
// Source: Phong 1975; Lewis 1994 and Lafortune 1994 (normalisation); seed 001 (coef by Int(n))
// Note: ops are the wrapper's, add the lobe's; albedo at normal incidence = 1 with norm = energy; f32: reflect(wi).wo rounded once to f32 moves flog-normalized-clamped near its zero (slope ~3e6 at n = 1e4, ~3e8 at n = 1e5) by up to 0.3 at n = 1e4 and by its whole height 1 above n ~ 2e4, times coef(n): 85 at n = 1e4, 4758 (the peak) at n = 6.2e4 (check --full), up to the peak 7654 at n = 1e5; at most 1.4 for the other lobes (flog-normalized at n = 1e5)
// Parameters (this export: lobe = pow, n = 20, norm = energy):
//   lobe: lobe id (one of pow, schlick, schlick-modified, gauss, flog, flog-normalized, flog-normalized-clamped, cubic, cubic3, rational, cubic-rational, power4, power8, power16, sg, ue4-phong-approx, power4-tuned, power8-tuned, power16-tuned, sg-tuned, cubic-rational-tuned, default pow)
//   n: specular exponent (range [1, 100000], default 20)
//   norm: energy: coef(n) = 1 / (2 pi Int(n)); none: the bare lobe (one of energy, none, default energy)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 8e3 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_phong(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_n; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

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

/// pow: c^n, the Phong/Blinn-Phong reference (Phong 1975), as fb_powr (exp2 of n fb_log2(c),
/// not WGSL's pow, whose log2 near 1 cost about 2n ulp: 6.4e-4 at n = 10000 on lavapipe, and
/// issue 11 reported the same on real GPUs). Cost: 1 exp2, 1 log2 (fb_log2's branch below
/// 0.5, evaluated by the select), 1 div, 10 mul, 8 add.
fn fb_lobe_pow(c: f32, n: f32) -> f32 {
    return fb_powr(fb_clamp01(c), n);
}

/// phong: coef(n) lobe(reflect(wi) . wo), coef(n) = 1 / (2 pi Int(n))
/// Source: Phong 1975; Lewis 1994 and Lafortune 1994 (normalisation); seed 001 (coef by Int(n)). Instance: runtime parameters p_n; fixed: lobe = pow, norm = energy.
fn fb_phong(wi: vec3<f32>, wo: vec3<f32>, p_n: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let r_dot_wo = -p.wi.x * p.wo.x - p.wi.y * p.wo.y + p.wi.z * p.wo.z;
    let v = (p_n + 2.0) * 0.15915494309189535 * fb_lobe_pow(r_dot_wo, (p_n));
    return select(0.0, v, p.valid);
}
