// fastbrdf 0.1.0 (distribution): ggx
// Made by: fastbrdf shader --model ggx --lang wgsl
//
// Formula: alpha^2 / (pi cos^4 theta_h (alpha^2 + tan^2 theta_h)^2) = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2)
// Source: Trowbridge & Reitz 1975; Walter et al. 2007, eq. 33 (GGX)
// Note: integral of D cos theta_h over the hemisphere = 1; no cancellation at small alpha (alpha^2 cos^2 + sin^2); anisotropic: cook-torrance's alpha_x, alpha_y
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_ggx(cos_h) with cos_h = n.h; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// ggx (Trowbridge & Reitz 1975; Walter et al. 2007): alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2),
/// given cos and sin^2 of theta_h; scale = alpha^2 / pi. No cancellation at small alpha.
fn fb_d_ggx(c: f32, s2: f32, alpha2: f32, scale: f32) -> f32 {
    let t = alpha2 * (c * c) + s2;
    return scale / (t * t);
}

/// ggx: alpha^2 / (pi cos^4 theta_h (alpha^2 + tan^2 theta_h)^2) = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2)
/// Source: Trowbridge & Reitz 1975; Walter et al. 2007, eq. 33 (GGX). Instance: alpha = 0.3.
fn fb_ggx(cos_h: f32) -> f32 {
    let cc = min(cos_h, 1.0);
    let d = fb_d_ggx(cc, (1.0 - cc) * (1.0 + cc), 0.09f, 0.02864789f);
    return select(0.0, d, cos_h >= FB_COS_MIN);
}
