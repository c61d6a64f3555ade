// fastbrdf 0.1.0 (brdf): phong
// Made by: fastbrdf shader --model phong --lang msl
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
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_phong(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct FbPair {
    bool valid;
    char _pad1[3];
    float cos_i;
    float cos_o;
    char _pad3[4];
    metal::packed_float3 h;
    float sin2_h;
    float cos_ih;
    char _pad6[12];
    metal::float3 wi;
    metal::float3 wo;
};
constant float FB_COS_MIN = 0.0000009536743;

float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_log2_(
    float x
) {
    float t = (x - 1.0) / (x + 1.0);
    float t2_ = t * t;
    float s = t * (2.0 + (t2_ * (0.6666667 + (t2_ * (0.4 + (t2_ * (0.2857143 + (t2_ * (0.22222222 + (t2_ * (0.18181819 + (t2_ * 0.15384614))))))))))));
    return (x >= 0.5) ? (s * 1.442695) : metal::log2(x);
}

float fb_powr(
    float x_1,
    float y
) {
    float _e4 = fb_log2_(metal::max(x_1, 0.000000000000000000000000000001));
    return (x_1 > 0.0) ? metal::exp2(y * _e4) : 0.0;
}

metal::float3 fb_rescale(
    metal::float3 v
) {
    float l = metal::dot(v, v);
    float m = metal::max(metal::max(metal::abs(v.x), metal::abs(v.y)), metal::abs(v.z));
    bool safe = (l >= 0.0000000000000000000000000000007888609) & (l <= 1267650600000000000000000000000.0);
    return (safe | (m == 0.0)) ? v : (v / metal::float3(m));
}

FbPair fb_pair(
    metal::float3 wi_raw,
    metal::float3 wo_raw
) {
    metal::float3 _e2 = fb_rescale(wi_raw);
    metal::float3 _e3 = fb_rescale(wo_raw);
    float li = metal::dot(_e2, _e2);
    float lo = metal::dot(_e3, _e3);
    metal::float3 wi_1 = _e2 * (1.0 / metal::sqrt(li));
    metal::float3 wo_1 = _e3 * (1.0 / metal::sqrt(lo));
    metal::float3 s_1 = wi_1 + wo_1;
    float len = metal::sqrt(metal::dot(s_1, s_1));
    metal::float3 h = s_1 / metal::float3(len);
    bool valid = ((((li > 0.0) & (lo > 0.0)) & (wi_1.z >= FB_COS_MIN)) & (wo_1.z >= FB_COS_MIN)) & (len > 0.0);
    return FbPair {valid, {}, wi_1.z, wo_1.z, {}, h, (h.x * h.x) + (h.y * h.y), 0.5 * len, {}, wi_1, wo_1};
}

float fb_lobe_pow(
    float c_1,
    float n
) {
    float _e2 = fb_clamp01_(c_1);
    float _e3 = fb_powr(_e2, n);
    return _e3;
}

float fb_phong(
    metal::float3 wi,
    metal::float3 wo
) {
    FbPair _e2 = fb_pair(wi, wo);
    float r_dot_wo = ((-(_e2.wi.x) * _e2.wo.x) - (_e2.wi.y * _e2.wo.y)) + (_e2.wi.z * _e2.wo.z);
    float _e23 = fb_lobe_pow(r_dot_wo, 20.0);
    float v_1 = 3.5014088 * _e23;
    return _e2.valid ? v_1 : 0.0;
}
