// fastbrdf 0.1.0 (shadowing): smith-ggx-correlated-fast
// Made by: fastbrdf shader --model smith-ggx-correlated-fast --lang glsl
//
// Formula: G = 4 NL NV V, V = 0.5 / mix(2 NL NV, NL + NV, alpha)
// Source: Hammon 2017 (GDC, "PBR Diffuse Lighting for GGX+Smith Microsurfaces"), as Filament's V_SmithGGXCorrelated_Fast
// Note: the same function as smith-ggx-joint-approx (Unreal); one-sided it is schlick-ggx (alpha-half); two-sided max abs error against smith-ggx-correlated 0.231
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   smith-ggx-correlated-fast vs smith-ggx-correlated: max abs error (relative to the peak) <= 0.162 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_smith_ggx_correlated_fast(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_smith_ggx_correlated_fast_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

const float FB_F32_MIN_NORMAL = 1.1754944e-38;


float fb_g_smith_ggx_correlated_fast(float cos_v, float cos_l, float alpha, float om) {
    float v = min(cos_v, 1.0);
    float l = min(cos_l, 1.0);
    float two_vl = (2.0 * (v * l));
    float den = ((two_vl * om) + ((v + l) * alpha));
    return (two_vl / max(den, FB_F32_MIN_NORMAL));
}

float fb_smith_ggx_correlated_fast(float cos_v_1, float cos_l_1, float cos_h, float cos_vh) {
    float _e6 = fb_g_smith_ggx_correlated_fast(cos_v_1, cos_l_1, 0.3, 0.7);
    return (((cos_v_1 > 0.0) && (cos_l_1 > 0.0)) ? _e6 : 0.0);
}

float fb_smith_ggx_correlated_fast_v(float cos_v_2, float cos_l_2, float cos_h_1, float cos_vh_1) {
    float _e4 = fb_smith_ggx_correlated_fast(cos_v_2, cos_l_2, cos_h_1, cos_vh_1);
    return ((_e4 > 0.0) ? (_e4 / max(((4.0 * cos_v_2) * cos_l_2), 1.1754944e-38)) : 0.0);
}
