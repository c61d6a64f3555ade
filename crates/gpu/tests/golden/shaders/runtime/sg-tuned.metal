// fastbrdf 0.1.0 (lobe): sg-tuned
// Made by: fastbrdf shader --model sg-tuned --lang msl --runtime-params
//
// Formula: exp2(a(n)(c - 1)), a(n) = (n / ln 2) Re(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   sg-tuned vs pow: max abs error (relative to the peak) <= 0.144 over n in [1, 100000], whole domain
//   sg-tuned vs pow: max abs error (relative to the peak) <= 0.0162 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_sg_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_lobe_exp2_(
    float c_1,
    float k
) {
    float _e2 = fb_clamp01_(c_1);
    return metal::exp2(k * (_e2 - 1.0));
}

float fb_sg_tuned(
    float c_2,
    float p_n
) {
    float _e26 = fb_lobe_exp2_(c_2, (p_n * 1.442695) * (0.99999976 + ((1.0 / p_n) * (0.66284496 + ((1.0 / p_n) * (0.25285295 + ((1.0 / p_n) * (0.11461735 + ((1.0 / p_n) * -0.08793797)))))))));
    return _e26;
}
