// fastbrdf 0.1.0 (lobe): flog
// Made by: fastbrdf shader --model flog --lang msl --runtime-params
//
// Formula: max(0, 1 - 0.5 log2(1 - n log2 c))
// Source: seed 001 (Romanyuk, Zavalniuk et al., ACIT 2023), its reference [10]
// Note: zero at c = 2^(-3/n) = exp(-2.0794/n); the seed rounds the constant to 2.08
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   flog vs pow: max abs error (relative to the peak) <= 0.126 over n in [1, 1000], whole domain
//   flog vs pow: max abs error (relative to the peak) <= 0.126 over n in [1, 100000], whole domain
//   flog vs pow: max rel error <= 0.00292 over n in [1, 1000], epicentre (reference >= half its peak)
//   flog vs pow: max rel error <= 0.00292 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_flog(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


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

float fb_lobe_flog(
    float c_1,
    float n,
    float coef,
    bool clamp_to_one
) {
    float v = {};
    float _e4 = fb_clamp01_(c_1);
    float _e7 = fb_log2_(metal::max(_e4, 0.000000000000000000000000000001));
    float f = 1.0 - (0.5 * metal::log2(1.0 - (n * _e7)));
    v = metal::max(coef * f, 0.0);
    if (clamp_to_one) {
        float _e20 = v;
        v = metal::min(_e20, 1.0);
    }
    float _e23 = v;
    return (_e4 > 0.0) ? _e23 : 0.0;
}

float fb_flog(
    float c_2,
    float p_n
) {
    float _e4 = fb_lobe_flog(c_2, p_n, 1.0, false);
    return _e4;
}
