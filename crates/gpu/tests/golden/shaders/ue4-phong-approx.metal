// fastbrdf 0.1.0 (lobe): ue4-phong-approx
// Made by: fastbrdf shader --model ue4-phong-approx --lang msl
//
// Formula: exp2(1.4427 (n + 0.775)(c - 1))
// Source: Unreal Engine 4 mobile shading (PhongApprox), Karis 2014
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   ue4-phong-approx vs pow: max abs error (relative to the peak) <= 0.17 over n in [1, 100000], whole domain
//   ue4-phong-approx vs pow: max abs error (relative to the peak) <= 0.0097 over n in [16, 100000], whole domain
//   ue4-phong-approx vs pow: max rel error <= 0.183 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_ue4_phong_approx(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

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

float fb_ue4_phong_approx(
    float c_2
) {
    float _e2 = fb_lobe_exp2_(c_2, 29.972092);
    return _e2;
}
