// fastbrdf 0.1.0 (shadowing): smith-ggx-correlated
// Made by: fastbrdf shader --model smith-ggx-correlated --lang msl
//
// Formula: G = 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (sqrt(1 + alpha^2 tan^2 v) + sqrt(1 + alpha^2 tan^2 l))
// Source: Heitz 2014, eq. 99 (height-correlated Smith); GGX Lambda of Walter et al. 2007
// Note: one-sided (no cos_l): G1
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_smith_ggx_correlated(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_smith_ggx_correlated_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_ggx_s(
    float c,
    float alpha2_
) {
    float s2_ = (1.0 - c) * (1.0 + c);
    return metal::sqrt((c * c) + (alpha2_ * s2_)) / c;
}

float fb_g_smith_ggx_correlated(
    float cos_v,
    float cos_l,
    float alpha2_1
) {
    float v = metal::min(cos_v, 1.0);
    float l = metal::min(cos_l, 1.0);
    float _e7 = fb_ggx_s(v, alpha2_1);
    float _e8 = fb_ggx_s(l, alpha2_1);
    return 2.0 / (_e7 + _e8);
}

float fb_smith_ggx_correlated(
    float cos_v_1,
    float cos_l_1,
    float cos_h,
    float cos_vh
) {
    float _e5 = fb_g_smith_ggx_correlated(cos_v_1, cos_l_1, 0.09);
    return ((cos_v_1 > 0.0) & (cos_l_1 > 0.0)) ? _e5 : 0.0;
}

float fb_smith_ggx_correlated_v(
    float cos_v_2,
    float cos_l_2,
    float cos_h_1,
    float cos_vh_1
) {
    float _e4 = fb_smith_ggx_correlated(cos_v_2, cos_l_2, cos_h_1, cos_vh_1);
    return (_e4 > 0.0) ? (_e4 / metal::max((4.0 * cos_v_2) * cos_l_2, 0.000000000000000000000000000000000000011754944)) : 0.0;
}
