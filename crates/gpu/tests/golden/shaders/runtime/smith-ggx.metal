// fastbrdf 0.1.0 (shadowing): smith-ggx
// Made by: fastbrdf shader --model smith-ggx --lang msl --runtime-params
//
// Formula: G1 = 1 / (1 + Lambda), Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2, i.e. G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); G = G1(v) G1(l)
// Source: Smith 1967; Walter et al. 2007, eq. 34 (GGX Lambda)
// Note: two-sided form is separable G1(v) G1(l)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_smith_ggx(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided, then p_alpha; returns f32.
// V form: fb_smith_ggx_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

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

float fb_g1_smith_ggx(
    float c_1,
    float alpha2_1
) {
    float _e2 = fb_ggx_s(c_1, alpha2_1);
    return (c_1 >= 1.0) ? 1.0 : (2.0 / (1.0 + _e2));
}

float fb_smith_ggx(
    float cos_v,
    float cos_l,
    float cos_h,
    float cos_vh,
    float p_alpha
) {
    float _e6 = fb_g1_smith_ggx(cos_v, p_alpha * p_alpha);
    float _e8 = fb_g1_smith_ggx(cos_l, p_alpha * p_alpha);
    float g = _e6 * _e8;
    return ((cos_v > 0.0) & (cos_l > 0.0)) ? g : 0.0;
}

float fb_smith_ggx_v(
    float cos_v_1,
    float cos_l_1,
    float cos_h_1,
    float cos_vh_1,
    float p_alpha_1
) {
    float _e5 = fb_smith_ggx(cos_v_1, cos_l_1, cos_h_1, cos_vh_1, p_alpha_1);
    return (_e5 > 0.0) ? (_e5 / metal::max((4.0 * cos_v_1) * cos_l_1, 0.000000000000000000000000000000000000011754944)) : 0.0;
}
