// fastbrdf 0.1.0 (shadowing): v-cavity
// Made by: fastbrdf shader --model v-cavity --lang msl
//
// Formula: min(1, 2 NH NV / VH, 2 NH NL / VH)
// Source: Cook & Torrance 1982 (after Torrance & Sparrow 1967)
// Note: input columns cos_v, cos_h, cos_vh and optional cos_l (two-sided)
// Parameters (this export: no parameters):
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_v_cavity(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_v_cavity_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_g_v_cavity(
    float cos_v,
    float cos_l,
    float cos_h,
    float cos_vh
) {
    float two_h = 2.0 * cos_h;
    return metal::min(metal::min(1.0, two_h * (cos_v / cos_vh)), two_h * (cos_l / cos_vh));
}

float fb_v_cavity(
    float cos_v_1,
    float cos_l_1,
    float cos_h_1,
    float cos_vh_1
) {
    float _e4 = fb_g_v_cavity(cos_v_1, cos_l_1, cos_h_1, cos_vh_1);
    return ((((cos_v_1 > 0.0) & (cos_l_1 > 0.0)) & (cos_h_1 > 0.0)) & (cos_vh_1 > 0.0)) ? _e4 : 0.0;
}

float fb_v_cavity_v(
    float cos_v_2,
    float cos_l_2,
    float cos_h_2,
    float cos_vh_2
) {
    float _e4 = fb_v_cavity(cos_v_2, cos_l_2, cos_h_2, cos_vh_2);
    return (_e4 > 0.0) ? (_e4 / metal::max((4.0 * cos_v_2) * cos_l_2, 0.000000000000000000000000000000000000011754944)) : 0.0;
}
