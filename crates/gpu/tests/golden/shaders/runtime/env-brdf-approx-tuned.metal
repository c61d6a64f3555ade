// fastbrdf 0.1.0 (env): env-brdf-approx-tuned
// Made by: fastbrdf shader --model env-brdf-approx-tuned --lang msl --runtime-params
//
// Formula: env-brdf-approx's form, its 11 constants refitted minimax against env-brdf
// Source: this project (fit_env_brdf example)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-approx-tuned vs env-brdf: max abs error (relative to the peak) <= 0.339 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_approx_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

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

float fb_env_brdf_approx_tuned(
    float cos_v_1,
    float alpha_1
) {
    float v_1 = (cos_v_1 > 0.0) ? metal::min(cos_v_1, 1.0) : 0.0;
    float a = (alpha_1 > 0.005) ? metal::min(alpha_1, 1.0) : 0.005;
    float _e27 = fb_env_approx(v_1, a, type_1 {{-1.072325, -0.028393, -0.488609, 0.023184, 1.040579, 0.040344, 1.129695, -0.038556, -9.478977, -0.965804, 1.019101}}, false);
    return _e27;
}
