// fastbrdf 0.1.0 (shadowing): smith-ggx-joint-approx
// Made by: fastbrdf shader --model smith-ggx-joint-approx --lang wgsl --runtime-params
//
// Formula: G = 4 NL NV V, V = 0.5 / (NL (NV (1 - a) + a) + NV (NL (1 - a) + a)), a = alpha
// Source: Karis 2014, Unreal Engine 4's Vis_SmithJointApprox
// Note: algebraically identical to smith-ggx-correlated-fast (Hammon/Filament), differs by rounding only; two-sided max abs error against smith-ggx-correlated 0.231
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   smith-ggx-joint-approx vs smith-ggx-correlated: max abs error (relative to the peak) <= 0.162 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_smith_ggx_joint_approx(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided, then p_alpha; returns f32.
// V form: fb_smith_ggx_joint_approx_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

/// The smallest normal f32, for the fast forms' underflowed denominators (0, not NaN).
const FB_F32_MIN_NORMAL: f32 = 1.1754943508222875e-38;

/// smith-ggx-joint-approx (Unreal's Vis_SmithJointApprox, the same function as Hammon's):
/// 4 NL NV V, V = 0.5 / (NL (NV (1 - a) + a) + NV (NL (1 - a) + a)); om = 1 - a.
fn fb_g_smith_ggx_joint_approx(cos_v: f32, cos_l: f32, a: f32, om: f32) -> f32 {
    let v = min(cos_v, 1.0);
    let l = min(cos_l, 1.0);
    let vis_v = l * (v * om + a);
    let vis_l = v * (l * om + a);
    return 2.0 * (v * l) / max(vis_v + vis_l, FB_F32_MIN_NORMAL);
}

/// smith-ggx-joint-approx: G = 4 NL NV V, V = 0.5 / (NL (NV (1 - a) + a) + NV (NL (1 - a) + a)), a = alpha
/// Source: Karis 2014, Unreal Engine 4's Vis_SmithJointApprox. Instance: runtime parameters p_alpha; fixed: no parameters.
fn fb_smith_ggx_joint_approx(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32, p_alpha: f32) -> f32 {
    let g = fb_g_smith_ggx_joint_approx(cos_v, cos_l, (p_alpha), (1.0 - p_alpha));
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0));
}

/// V form of fb_smith_ggx_joint_approx: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_smith_ggx_joint_approx_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32, p_alpha: f32) -> f32 {
    let g = fb_smith_ggx_joint_approx(cos_v, cos_l, cos_h, cos_vh, p_alpha);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
