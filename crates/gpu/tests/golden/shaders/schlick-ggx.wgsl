// fastbrdf 0.1.0 (shadowing): schlick-ggx
// Made by: fastbrdf shader --model schlick-ggx --lang wgsl
//
// Formula: G1 = NV / (NV (1 - k) + k), k = alpha / 2 (alpha-half) or (sqrt(alpha) + 1)^2 / 8 (ue4); G = G1(v) G1(l)
// Source: Schlick 1994; Karis 2013 (k = alpha / 2 for GGX, and Unreal's remapping)
// Note: bound for remap = alpha-half (two-sided 0.261); ue4 (a hotter k, by design) errs against smith-ggx by up to 0.882 one-sided, 0.958 two-sided
// Parameters (this export: alpha = 0.3, remap = alpha-half):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
//   remap: Schlick's k: alpha / 2, or Unreal's (sqrt(alpha) + 1)^2 / 8 (one of alpha-half, ue4, default alpha-half)
// Documented error bounds (measured by `fastbrdf check`):
//   schlick-ggx vs smith-ggx: max abs error (relative to the peak) <= 0.162 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_schlick_ggx(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_schlick_ggx_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

/// schlick-ggx (Schlick 1994; Karis 2013): G1 = c / (c (1 - k) + k); om = 1 - k; 1 at c >= 1.
fn fb_g1_schlick_ggx(c: f32, k: f32, om: f32) -> f32 {
    return select(c / (c * om + k), 1.0, c >= 1.0);
}

/// schlick-ggx: G1 = NV / (NV (1 - k) + k), k = alpha / 2 (alpha-half) or (sqrt(alpha) + 1)^2 / 8 (ue4); G = G1(v) G1(l)
/// Source: Schlick 1994; Karis 2013 (k = alpha / 2 for GGX, and Unreal's remapping). Instance: alpha = 0.3, remap = alpha-half.
fn fb_schlick_ggx(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_g1_schlick_ggx(cos_v, 0.15f, 0.85f) * fb_g1_schlick_ggx(cos_l, 0.15f, 0.85f);
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0));
}

/// V form of fb_schlick_ggx: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_schlick_ggx_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_schlick_ggx(cos_v, cos_l, cos_h, cos_vh);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
