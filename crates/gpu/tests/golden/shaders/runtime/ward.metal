// fastbrdf 0.1.0 (brdf): ward
// Made by: fastbrdf shader --model ward --lang msl --runtime-params
//
// Formula: exp(-(h_x^2/ax^2 + h_y^2/ay^2)/h_z^2) / (4 pi ax ay sqrt(cos_i cos_o))
// Source: Ward 1992, 'Measuring and modeling anisotropic reflection'
// Note: albedo <= 1 up to 85 degrees; exceeds 1 within ~0.5 degree of grazing (1.50 at 89.9 degrees, alpha = 1)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
//   alpha_x: anisotropic slope along x (with alpha_y; replaces alpha) (range [0.005, 1], default -)
//   alpha_y: anisotropic slope along y (with alpha_x; replaces alpha) (range [0.005, 1], default -)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-5 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_ward(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_alpha; returns f32.

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
    metal::float3 wi_2 = _e2 * (1.0 / metal::sqrt(li));
    metal::float3 wo_2 = _e3 * (1.0 / metal::sqrt(lo));
    metal::float3 s = wi_2 + wo_2;
    float len = metal::sqrt(metal::dot(s, s));
    metal::float3 h = s / metal::float3(len);
    bool valid = ((((li > 0.0) & (lo > 0.0)) & (wi_2.z >= FB_COS_MIN)) & (wo_2.z >= FB_COS_MIN)) & (len > 0.0);
    return FbPair {valid, {}, wi_2.z, wo_2.z, {}, h, (h.x * h.x) + (h.y * h.y), 0.5 * len, {}, wi_2, wo_2};
}

float fb_brdf_ward(
    metal::float3 wi,
    metal::float3 wo,
    float inv_ax2_,
    float inv_ay2_,
    float scale
) {
    FbPair _e5 = fb_pair(wi, wo);
    float lobe = metal::exp(-((((_e5.h[0] * _e5.h[0]) * inv_ax2_) + ((_e5.h[1] * _e5.h[1]) * inv_ay2_))) / (_e5.h[2] * _e5.h[2]));
    return _e5.valid ? ((scale * lobe) / metal::sqrt(_e5.cos_i * _e5.cos_o)) : 0.0;
}

float fb_ward(
    metal::float3 wi_1,
    metal::float3 wo_1,
    float p_alpha
) {
    float _e12 = fb_brdf_ward(wi_1, wo_1, 1.0 / (p_alpha * p_alpha), 1.0 / (p_alpha * p_alpha), 0.07957747 / (p_alpha * p_alpha));
    return _e12;
}
