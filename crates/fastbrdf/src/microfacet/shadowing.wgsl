// WGSL twin of microfacet/shadowing.rs (see microfacet/mod.wgsl).

/// v-cavity (Cook & Torrance 1982): min(1, 2 NH NV / VH, 2 NH NL / VH), each side as
/// 2 NH (NV / VH) (the ratio of cosines first, as the CPU's v_cavity_side; its fallback for a
/// ratio that overflows needs a subnormal VH, which GPUs flush to 0).
fn fb_g_v_cavity(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let two_h = 2.0 * cos_h;
    return min(min(1.0, two_h * (cos_v / cos_vh)), two_h * (cos_l / cos_vh));
}

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

/// smith (Walter et al. 2007, eq. 25-27): G1 = 1 / (1 + Lambda(a)), a = 1 / (alpha tan theta),
/// Lambda = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2.
fn fb_g1_smith(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let lambda = 0.5 * (exp(-a * a) * FB_INV_SQRT_PI / a - fb_erfc(a));
    return select(1.0 / (1.0 + lambda), 1.0, c >= 1.0);
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

/// smith-rational (Walter et al. 2007, eq. 27): G1 = (3.535 a + 2.181 a^2) /
/// (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1.
fn fb_g1_smith_rational(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let a2 = a * a;
    let g = (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
    return select(g, 1.0, (a >= 1.6) | (c >= 1.0));
}
