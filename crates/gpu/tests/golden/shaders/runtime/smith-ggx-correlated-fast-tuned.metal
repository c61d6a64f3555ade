// fastbrdf 0.1.0 (shadowing): smith-ggx-correlated-fast-tuned
// Made by: fastbrdf shader --model smith-ggx-correlated-fast-tuned --lang msl --runtime-params
//
// Formula: Hammon's G with alpha replaced by k = alpha (0.529334 + 0.505461 alpha - 0.035766 alpha^2): G = 2 NL NV / (2 NL NV (1 - k) + k (NL + NV))
// Source: this project: Hammon 2017's form, k refitted minimax against Heitz 2014's exact term (fit_smith_fast example)
// Note: same cost as smith-ggx-correlated-fast (k is a plan constant); two-sided max abs error against smith-ggx-correlated 0.104
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   smith-ggx-correlated-fast-tuned vs smith-ggx-correlated: max abs error (relative to the peak) <= 0.104 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_smith_ggx_correlated_fast_tuned(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided, then p_alpha; returns f32.
// V form: fb_smith_ggx_correlated_fast_tuned_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

constant float FB_F32_MIN_NORMAL = 0.000000000000000000000000000000000000011754944;

float fb_g_smith_ggx_correlated_fast(
    float cos_v,
    float cos_l,
    float alpha,
    float om
) {
    float v = metal::min(cos_v, 1.0);
    float l = metal::min(cos_l, 1.0);
    float two_vl = 2.0 * (v * l);
    float den = (two_vl * om) + ((v + l) * alpha);
    return two_vl / metal::max(den, FB_F32_MIN_NORMAL);
}

float fb_smith_ggx_correlated_fast_tuned(
    float cos_v_1,
    float cos_l_1,
    float cos_h,
    float cos_vh,
    float p_alpha
) {
    float _e23 = fb_g_smith_ggx_correlated_fast(cos_v_1, cos_l_1, p_alpha * (0.529334 + (p_alpha * (0.505461 + (p_alpha * -0.035766)))), 1.0 - (p_alpha * (0.529334 + (p_alpha * (0.505461 + (p_alpha * -0.035766))))));
    return ((cos_v_1 > 0.0) & (cos_l_1 > 0.0)) ? _e23 : 0.0;
}

float fb_smith_ggx_correlated_fast_tuned_v(
    float cos_v_2,
    float cos_l_2,
    float cos_h_1,
    float cos_vh_1,
    float p_alpha_1
) {
    float _e5 = fb_smith_ggx_correlated_fast_tuned(cos_v_2, cos_l_2, cos_h_1, cos_vh_1, p_alpha_1);
    return (_e5 > 0.0) ? (_e5 / metal::max((4.0 * cos_v_2) * cos_l_2, 0.000000000000000000000000000000000000011754944)) : 0.0;
}
