// fastbrdf 0.1.0 (lobe): cubic3
// Made by: fastbrdf shader --model cubic3 --lang msl
//
// Formula: a c^3 + b c^2 + c' c through (1, 1), (0.5^(1/n), 0.5), ((1/18)^(1/n), 1/18); 0 below its local minimum and where negative
// Source: seed 003 (three-point variant, Q = 0.5, G = 1/18)
// Note: for f32 accuracy, evaluated on the CPU by Horner in (c - 1) with coefficients from the Newton form, on the GPU in the Newton form in 1 - c (fold-proof)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.0215 over n in [4, 1000], epicentre (reference >= half its peak)
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.0217 over n in [4, 100000], epicentre (reference >= half its peak)
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.108 over n in [4, 1000], whole domain
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.109 over n in [4, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_cubic3_(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_lobe_cubic(
    float c_1,
    float d1_,
    float d2_,
    float d3_,
    float x1_,
    float x2_,
    float cut
) {
    float _e7 = fb_clamp01_(c_1);
    float y = 1.0 - _e7;
    float p = 1.0 - (y * (d1_ - ((y + x1_) * (d2_ - ((y + x2_) * d3_)))));
    return (_e7 < cut) ? 0.0 : metal::max(p, 0.0);
}

float fb_cubic3_(
    float c_2
) {
    float _e7 = fb_lobe_cubic(c_2, 14.678394, 76.217766, 71.70582, -0.03406367, -0.13456118, 0.8839193);
    return _e7;
}
