// fastbrdf 0.1.0 (shadowing): smith-beckmann-correlated
// Made by: fastbrdf shader --model smith-beckmann-correlated --lang msl --runtime-params
//
// Formula: G = 1 / (1 + Lambda(v) + Lambda(l)), Lambda as smith's (Beckmann, exact)
// Source: Heitz 2014, eq. 99 (height-correlated Smith); Walter et al. 2007 (Beckmann Lambda)
// Note: one-sided (no cos_l): G1, as smith
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_smith_beckmann_correlated(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided, then p_alpha; returns f32.
// V form: fb_smith_beckmann_correlated_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

constant float FB_INV_SQRT_PI = 0.5641896;

float fb_erfc(
    float x
) {
    float t = 1.0 / (1.0 + (0.5 * x));
    float p = -1.2655122 + (t * (1.0000237 + (t * (0.37409195 + (t * (0.09678418 + (t * (-0.18628806 + (t * (0.27886808 + (t * (-1.135204 + (t * (1.4885159 + (t * (-0.82215226 + (t * 0.17087276)))))))))))))))));
    return t * metal::exp((-(x) * x) + p);
}

float fb_lambda_beckmann(
    float c,
    float alpha
) {
    float sin = metal::sqrt(metal::max((1.0 - c) * (1.0 + c), 0.0));
    float a = c / (alpha * sin);
    float _e18 = fb_erfc(a);
    float lambda = 0.5 * (((metal::exp(-(a) * a) * FB_INV_SQRT_PI) / a) - _e18);
    return (c >= 1.0) ? 0.0 : lambda;
}

float fb_g_smith_beckmann_correlated(
    float cos_v,
    float cos_l,
    float alpha_1
) {
    float _e3 = fb_lambda_beckmann(cos_v, alpha_1);
    float _e4 = fb_lambda_beckmann(cos_l, alpha_1);
    return 1.0 / (1.0 + (_e3 + _e4));
}

float fb_smith_beckmann_correlated(
    float cos_v_1,
    float cos_l_1,
    float cos_h,
    float cos_vh,
    float p_alpha
) {
    float _e5 = fb_g_smith_beckmann_correlated(cos_v_1, cos_l_1, p_alpha);
    return ((cos_v_1 > 0.0) & (cos_l_1 > 0.0)) ? _e5 : 0.0;
}

float fb_smith_beckmann_correlated_v(
    float cos_v_2,
    float cos_l_2,
    float cos_h_1,
    float cos_vh_1,
    float p_alpha_1
) {
    float _e5 = fb_smith_beckmann_correlated(cos_v_2, cos_l_2, cos_h_1, cos_vh_1, p_alpha_1);
    return (_e5 > 0.0) ? (_e5 / metal::max((4.0 * cos_v_2) * cos_l_2, 0.000000000000000000000000000000000000011754944)) : 0.0;
}
