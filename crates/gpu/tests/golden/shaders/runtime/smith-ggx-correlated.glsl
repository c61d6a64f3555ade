// fastbrdf 0.1.0 (shadowing): smith-ggx-correlated
// Made by: fastbrdf shader --model smith-ggx-correlated --lang glsl --runtime-params
//
// Formula: G = 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (sqrt(1 + alpha^2 tan^2 v) + sqrt(1 + alpha^2 tan^2 l))
// Source: Heitz 2014, eq. 99 (height-correlated Smith); GGX Lambda of Walter et al. 2007
// Note: one-sided (no cos_l): G1
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_smith_ggx_correlated(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided, then p_alpha; returns f32.
// V form: fb_smith_ggx_correlated_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

float fb_ggx_s(float c, float alpha2_) {
    float s2_ = ((1.0 - c) * (1.0 + c));
    return (sqrt(((c * c) + (alpha2_ * s2_))) / c);
}

float fb_g_smith_ggx_correlated(float cos_v, float cos_l, float alpha2_1) {
    float v = min(cos_v, 1.0);
    float l = min(cos_l, 1.0);
    float _e7 = fb_ggx_s(v, alpha2_1);
    float _e8 = fb_ggx_s(l, alpha2_1);
    return (2.0 / (_e7 + _e8));
}

float fb_smith_ggx_correlated(float cos_v_1, float cos_l_1, float cos_h, float cos_vh, float p_alpha) {
    float _e6 = fb_g_smith_ggx_correlated(cos_v_1, cos_l_1, (p_alpha * p_alpha));
    return (((cos_v_1 > 0.0) && (cos_l_1 > 0.0)) ? _e6 : 0.0);
}

float fb_smith_ggx_correlated_v(float cos_v_2, float cos_l_2, float cos_h_1, float cos_vh_1, float p_alpha_1) {
    float _e5 = fb_smith_ggx_correlated(cos_v_2, cos_l_2, cos_h_1, cos_vh_1, p_alpha_1);
    return ((_e5 > 0.0) ? (_e5 / max(((4.0 * cos_v_2) * cos_l_2), 1.1754944e-38)) : 0.0);
}
