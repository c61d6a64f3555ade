// fastbrdf 0.1.0 (brdf): ward-pow
// Made by: fastbrdf shader --model ward-pow --lang msl --runtime-params
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
    metal::float3 wi_2 = _e2 * (1.0 / metal::sqrt(li));
    metal::float3 wo_2 = _e3 * (1.0 / metal::sqrt(lo));
    metal::float3 s_1 = wi_2 + wo_2;
    float len = metal::sqrt(metal::dot(s_1, s_1));
    metal::float3 h = s_1 / metal::float3(len);
    bool valid = ((((li > 0.0) & (lo > 0.0)) & (wi_2.z >= FB_COS_MIN)) & (wo_2.z >= FB_COS_MIN)) & (len > 0.0);
    return FbPair {valid, {}, wi_2.z, wo_2.z, {}, h, (h.x * h.x) + (h.y * h.y), 0.5 * len, {}, wi_2, wo_2};
}

float fb_brdf_ward_pow(
    metal::float3 wi,
    metal::float3 wo,
    float e,
    float scale
) {
    FbPair _e4 = fb_pair(wi, wo);
    float _e7 = fb_powr(_e4.h[2], e);
    return _e4.valid ? ((scale * _e7) / metal::sqrt(_e4.cos_i * _e4.cos_o)) : 0.0;
}

float fb_ward_pow(
    metal::float3 wi_1,
    metal::float3 wo_1,
    float p_alpha
) {
    float _e9 = fb_brdf_ward_pow(wi_1, wo_1, 2.0 / (p_alpha * p_alpha), 0.07957747 / (p_alpha * p_alpha));
    return _e9;
}
