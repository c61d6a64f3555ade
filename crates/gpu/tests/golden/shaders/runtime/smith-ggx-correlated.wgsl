// fastbrdf 0.1.0 (shadowing): smith-ggx-correlated
// Made by: fastbrdf shader --model smith-ggx-correlated --lang wgsl --runtime-params
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

/// sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c, for the GGX Smith terms
/// (1 + Lambda = (1 + S) / 2; no S - 1 is formed).
fn fb_ggx_s(c: f32, alpha2: f32) -> f32 {
    let s2 = (1.0 - c) * (1.0 + c);
    return sqrt(c * c + alpha2 * s2) / c;
}

/// smith-ggx-correlated (Heitz 2014, eq. 99): 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (S(v) + S(l)).
fn fb_g_smith_ggx_correlated(cos_v: f32, cos_l: f32, alpha2: f32) -> f32 {
    let v = min(cos_v, 1.0);
    let l = min(cos_l, 1.0);
    return 2.0 / (fb_ggx_s(v, alpha2) + fb_ggx_s(l, alpha2));
}

/// smith-ggx-correlated: G = 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (sqrt(1 + alpha^2 tan^2 v) + sqrt(1 + alpha^2 tan^2 l))
/// Source: Heitz 2014, eq. 99 (height-correlated Smith); GGX Lambda of Walter et al. 2007. Instance: runtime parameters p_alpha; fixed: no parameters.
fn fb_smith_ggx_correlated(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32, p_alpha: f32) -> f32 {
    let g = fb_g_smith_ggx_correlated(cos_v, cos_l, (p_alpha * p_alpha));
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0));
}

/// V form of fb_smith_ggx_correlated: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_smith_ggx_correlated_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32, p_alpha: f32) -> f32 {
    let g = fb_smith_ggx_correlated(cos_v, cos_l, cos_h, cos_vh, p_alpha);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
