// fastbrdf 0.1.0 (lobe): power4-tuned
// Made by: fastbrdf shader --model power4-tuned --lang msl
//
// Formula: max(0, 1 + s(n)(c - 1))^4, s(n) = (n/4) R4(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power4-tuned vs pow: max abs error (relative to the peak) <= 0.117 over n in [1, 100000], whole domain
//   power4-tuned vs pow: max abs error (relative to the peak) <= 0.0333 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_power4_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_pow4_(
    float x
) {
    float x2_ = x * x;
    return x2_ * x2_;
}

float fb_lobe_power4_(
    float c_1,
    float s
) {
    float _e2 = fb_clamp01_(c_1);
    float _e10 = fb_pow4_(metal::max(1.0 - (s * (1.0 - _e2)), 0.0));
    return _e10;
}

float fb_power4_tuned(
    float c_2
) {
    float _e2 = fb_lobe_power4_(c_2, 4.3693843);
    return _e2;
}
