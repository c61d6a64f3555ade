// fastbrdf 0.1.0 (env): env-brdf-materialx-tuned
// Made by: fastbrdf shader --model env-brdf-materialx-tuned --lang msl --runtime-params
//
// Formula: env-brdf-materialx's form, its 2 x 17 free constants refitted against env-brdf (max and mean both below MaterialX's)
// Source: this project (fit_env_rational example)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-materialx-tuned vs env-brdf: max abs error (relative to the peak) <= 0.0797 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_materialx_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct type_1 {
    float inner[9];
};

float fb_env_rational_poly(
    float x,
    float y,
    type_1 c
) {
    float p0_ = (y * ((y * c.inner[5]) + c.inner[2])) + c.inner[0];
    float p1_ = (y * ((y * c.inner[7]) + c.inner[3])) + c.inner[1];
    float p2_ = (y * ((y * c.inner[8]) + c.inner[6])) + c.inner[4];
    return (x * ((x * p2_) + p1_)) + p0_;
}

float fb_env_rational(
    float cos_v,
    float alpha,
    type_1 num,
    type_1 den
) {
    float _e4 = fb_env_rational_poly(cos_v, alpha, num);
    float _e5 = fb_env_rational_poly(cos_v, alpha, den);
    return metal::max(_e4 / _e5, 0.0);
}

float fb_env_brdf_materialx_tuned(
    float cos_v_1,
    float alpha_1
) {
    float v = (cos_v_1 > 0.0) ? metal::min(cos_v_1, 1.0) : 0.0;
    float a = (alpha_1 > 0.005) ? metal::min(alpha_1, 1.0) : 0.005;
    float _e34 = fb_env_rational(v, a, type_1 {{0.085452, -0.191066, 10.218748, 0.90751, 28.483358, -8.181671, -24.73793, 17.28328, -6.033422}}, type_1 {{1.0, -1.180156, 8.80378, 14.385899, 27.73535, -7.465713, -33.963554, 14.708145, 34.39794}});
    return _e34;
}
