// fastbrdf 0.1.0 (shadowing): v-cavity
// Made by: fastbrdf shader --model v-cavity --lang wgsl
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

/// v-cavity (Cook & Torrance 1982): min(1, 2 NH NV / VH, 2 NH NL / VH), each side as
/// 2 NH (NV / VH) (the ratio of cosines first, as the CPU's v_cavity_side; its fallback for a
/// ratio that overflows needs a subnormal VH, which GPUs flush to 0).
fn fb_g_v_cavity(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let two_h = 2.0 * cos_h;
    return min(min(1.0, two_h * (cos_v / cos_vh)), two_h * (cos_l / cos_vh));
}

/// v-cavity: min(1, 2 NH NV / VH, 2 NH NL / VH)
/// Source: Cook & Torrance 1982 (after Torrance & Sparrow 1967). Instance: no parameters.
fn fb_v_cavity(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_g_v_cavity(cos_v, cos_l, cos_h, cos_vh);
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0) & (cos_h > 0.0) & (cos_vh > 0.0));
}

/// V form of fb_v_cavity: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_v_cavity_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let g = fb_v_cavity(cos_v, cos_l, cos_h, cos_vh);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
