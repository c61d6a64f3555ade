// fastbrdf 0.1.0 (shadowing): smith-ggx
// Made by: fastbrdf shader --model smith-ggx --lang wgsl
//
// Formula: G1 = 1 / (1 + Lambda), Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2, i.e. G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); G = G1(v) G1(l)
// Source: Smith 1967; Walter et al. 2007, eq. 34 (GGX Lambda)
// Note: two-sided form is separable G1(v) G1(l)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_smith_ggx(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_smith_ggx_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

/// sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c, for the GGX Smith terms
/// (1 + Lambda = (1 + S) / 2; no S - 1 is formed).
fn fb_ggx_s(c: f32, alpha2: f32) -> f32 {
    let s2 = (1.0 - c) * (1.0 + c);
    return sqrt(c * c + alpha2 * s2) / c;
}

/// smith-ggx (Walter et al. 2007, eq. 34): G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); 1 at c >= 1.
fn fb_g1_smith_ggx(c: f32, alpha2: f32) -> f32 {
    return select(2.0 / (1.0 + fb_ggx_s(c, alpha2)), 1.0, c >= 1.0);
}

/// smith-ggx: G1 = 1 / (1 + Lambda), Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2, i.e. G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); G = G1(v) G1(l)
/// Source: Smith 1967; Walter et al. 2007, eq. 34 (GGX Lambda). Instance: alpha = 0.3.
fn fb_smith_ggx(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_g1_smith_ggx(cos_v, 0.09f) * fb_g1_smith_ggx(cos_l, 0.09f);
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0));
}

/// V form of fb_smith_ggx: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_smith_ggx_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_smith_ggx(cos_v, cos_l, cos_h, cos_vh);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
