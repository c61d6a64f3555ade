// fastbrdf 0.1.0 (shadowing): smith-beckmann-correlated
// Made by: fastbrdf shader --model smith-beckmann-correlated --lang wgsl --runtime-params
//
// Formula: G = 1 / (1 + Lambda(v) + Lambda(l)), Lambda as smith's (Beckmann, exact)
// Source: Heitz 2014, eq. 99 (height-correlated Smith); Walter et al. 2007 (Beckmann Lambda)
// Note: one-sided (no cos_l): G1, as smith
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_smith_beckmann_correlated(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided, then p_alpha; returns f32.
// V form: fb_smith_beckmann_correlated_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

/// 1 / sqrt(pi), for the Smith term.
const FB_INV_SQRT_PI: f32 = 0.5641895835477563;

/// erfc(x) for x >= 0, relative error below 1.2e-7 (Numerical Recipes' erfcc, a Chebyshev
/// fit). WGSL has no erf; the CPU uses libm's erfc.
fn fb_erfc(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.5 * x);
    let p = -1.26551223 + t * (1.00002368 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806
        + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223
        + t * 0.17087277))))))));
    return t * exp(-x * x + p);
}

/// Beckmann's Smith Lambda (Walter et al. 2007): (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2,
/// a = 1 / (alpha tan theta); 0 at c >= 1.
fn fb_lambda_beckmann(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let lambda = 0.5 * (exp(-a * a) * FB_INV_SQRT_PI / a - fb_erfc(a));
    return select(lambda, 0.0, c >= 1.0);
}

/// smith-beckmann-correlated (Heitz 2014, eq. 99): 1 / (1 + Lambda(v) + Lambda(l)).
fn fb_g_smith_beckmann_correlated(cos_v: f32, cos_l: f32, alpha: f32) -> f32 {
    return 1.0 / (1.0 + (fb_lambda_beckmann(cos_v, alpha) + fb_lambda_beckmann(cos_l, alpha)));
}

/// smith-beckmann-correlated: G = 1 / (1 + Lambda(v) + Lambda(l)), Lambda as smith's (Beckmann, exact)
/// Source: Heitz 2014, eq. 99 (height-correlated Smith); Walter et al. 2007 (Beckmann Lambda). Instance: runtime parameters p_alpha; fixed: no parameters.
fn fb_smith_beckmann_correlated(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32, p_alpha: f32) -> f32 {
    let g = fb_g_smith_beckmann_correlated(cos_v, cos_l, (p_alpha));
    return select(0.0, g, (cos_v > 0.0) & (cos_l > 0.0));
}

/// V form of fb_smith_beckmann_correlated: V = G / (4 cos_v cos_l), as engines write the visibility term
/// (multiply by D and F only; 0 wherever G is 0).
fn fb_smith_beckmann_correlated_v(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32, p_alpha: f32) -> f32 {
    let g = fb_smith_beckmann_correlated(cos_v, cos_l, cos_h, cos_vh, p_alpha);
    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);
}
