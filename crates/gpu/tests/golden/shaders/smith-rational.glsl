// fastbrdf 0.1.0 (shadowing): smith-rational
// Made by: fastbrdf shader --model smith-rational --lang glsl
//
// Formula: G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1
// Source: Walter et al. 2007, eq. 27 (used by Mitsuba 3 for Beckmann)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   smith-rational vs smith: max rel error <= 0.00313 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_smith_rational(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_smith_rational_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

float fb_g1_smith_rational(float c, float alpha) {
    float sin_ = sqrt(max(((1.0 - c) * (1.0 + c)), 0.0));
    float a = (c / (alpha * sin_));
    float a2_ = (a * a);
    float g = (((3.535 * a) + (2.181 * a2_)) / ((1.0 + (2.276 * a)) + (2.577 * a2_)));
    return (((a >= 1.6) || (c >= 1.0)) ? 1.0 : g);
}

float fb_smith_rational(float cos_v, float cos_l, float cos_h, float cos_vh) {
    float _e5 = fb_g1_smith_rational(cos_v, 0.3);
    float _e7 = fb_g1_smith_rational(cos_l, 0.3);
    float g_1 = (_e5 * _e7);
    return (((cos_v > 0.0) && (cos_l > 0.0)) ? g_1 : 0.0);
}

float fb_smith_rational_v(float cos_v_1, float cos_l_1, float cos_h_1, float cos_vh_1) {
    float _e4 = fb_smith_rational(cos_v_1, cos_l_1, cos_h_1, cos_vh_1);
    return ((_e4 > 0.0) ? (_e4 / max(((4.0 * cos_v_1) * cos_l_1), 1.1754944e-38)) : 0.0);
}
