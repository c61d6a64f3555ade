// fastbrdf 0.1.0 (env): env-brdf-approx
// Made by: fastbrdf shader --model env-brdf-approx --lang msl --runtime-params
//
// Formula: p = sqrt(alpha) c0 + c1, a004 = min(p.x^2, 2^(-9.28 cos_v)) p.x + p.y, scale = -1.04 a004 + p.z, bias = max(0, 1.04 a004 + p.w)
// Source: Karis 2014, Physically Based Shading on Mobile (Unreal's EnvBRDFApprox)
// Note: fitted to Unreal's table (separable Schlick-Smith G, k = alpha/2, which is darker than the height-correlated term at grazing: the error is largest there); the bias is clamped at 0
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-approx vs env-brdf: max abs error (relative to the peak) <= 0.525 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_approx(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct type_1 {
    float inner[11];
};

float fb_env_approx(
    float cos_v,
    float alpha,
    type_1 k,
    bool bias
) {
    float r = metal::sqrt(alpha);
    float px = (r * k.inner[0]) + k.inner[4];
    float py = (r * k.inner[1]) + k.inner[5];
    float a004_ = (metal::min(px * px, metal::exp2(k.inner[8] * cos_v)) * px) + py;
    float v = bias ? ((k.inner[10] * a004_) + ((r * k.inner[3]) + k.inner[7])) : ((k.inner[9] * a004_) + ((r * k.inner[2]) + k.inner[6]));
    return metal::max(v, 0.0);
}

float fb_env_brdf_approx(
    float cos_v_1,
    float alpha_1
) {
    float v_1 = (cos_v_1 > 0.0) ? metal::min(cos_v_1, 1.0) : 0.0;
    float a = (alpha_1 > 0.005) ? metal::min(alpha_1, 1.0) : 0.005;
    float _e27 = fb_env_approx(v_1, a, type_1 {{-1.0, -0.0275, -0.572, 0.022, 1.0, 0.0425, 1.04, -0.04, -9.28, -1.04, 1.04}}, false);
    return _e27;
}
