// fastbrdf 0.1.0 (shadowing): smith-rational
// Made by: fastbrdf shader --model smith-rational --lang wgsl
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

/// smith-rational (Walter et al. 2007, eq. 27): G1 = (3.535 a + 2.181 a^2) /
/// (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1.
fn fb_g1_smith_rational(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let a2 = a * a;
    let g = (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
    return select(g, 1.0, (a >= 1.6) | (c >= 1.0));
}

/// smith-rational: G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1
/// Source: Walter et al. 2007, eq. 27 (used by Mitsuba 3 for Beckmann). Instance: alpha = 0.3.
fn fb_smith_rational(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_g1_smith_rational(cos_v, 0.3f) * fb_g1_smith_rational(cos_l, 0.3f);
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0));
}

/// V form of fb_smith_rational: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_smith_rational_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_smith_rational(cos_v, cos_l, cos_h, cos_vh);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
