// fastbrdf 0.1.0 (brdf): lambert
// Made by: fastbrdf shader --model lambert --lang msl --runtime-params
//
// Formula: albedo / pi
// Source: Lambert 1760
// Parameters (this export: albedo = 1):
//   albedo: directional-hemispherical reflectance (range [0, 1], default 1)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_albedo (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_lambert(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_albedo; returns f32.

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
    metal::float3 s = wi_1 + wo_1;
    float len = metal::sqrt(metal::dot(s, s));
    metal::float3 h = s / metal::float3(len);
    bool valid = ((((li > 0.0) & (lo > 0.0)) & (wi_1.z >= FB_COS_MIN)) & (wo_1.z >= FB_COS_MIN)) & (len > 0.0);
    return FbPair {valid, {}, wi_1.z, wo_1.z, {}, h, (h.x * h.x) + (h.y * h.y), 0.5 * len, {}, wi_1, wo_1};
}

float fb_lambert(
    metal::float3 wi,
    metal::float3 wo,
    float p_albedo
) {
    FbPair _e3 = fb_pair(wi, wo);
    return _e3.valid ? (p_albedo * 0.31830987) : 0.0;
}
