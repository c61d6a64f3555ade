// fastbrdf 0.1.0 (shadowing): schlick-ggx
// Made by: fastbrdf shader --model schlick-ggx --lang hlsl
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

float fb_g1_schlick_ggx(float c, float k, float om)
{
    return ((c >= 1.0) ? 1.0 : (c / ((c * om) + k)));
}

float fb_schlick_ggx(float cos_v, float cos_l, float cos_h, float cos_vh)
{
    const float _e6 = fb_g1_schlick_ggx(cos_v, 0.15, 0.85);
    const float _e9 = fb_g1_schlick_ggx(cos_l, 0.15, 0.85);
    float g = (_e6 * _e9);
    return (((cos_v > 0.0) & (cos_l > 0.0)) ? g : 0.0);
}

float fb_schlick_ggx_v(float cos_v_1, float cos_l_1, float cos_h_1, float cos_vh_1)
{
    const float _e4 = fb_schlick_ggx(cos_v_1, cos_l_1, cos_h_1, cos_vh_1);
    return ((_e4 > 0.0) ? (_e4 / max(((4.0 * cos_v_1) * cos_l_1), 1.1754944e-38)) : 0.0);
}
