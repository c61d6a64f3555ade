// fastbrdf 0.1.0 (distribution): beckmann
// Made by: fastbrdf shader --model beckmann --lang wgsl --runtime-params
//
// Formula: exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)
// Source: Beckmann & Spizzichino 1963; Walter et al. 2007 (normalisation of Mitsuba 3, pbrt)
// Note: integral of D cos theta_h over the hemisphere = 1; f32: 1.4e-6 at alpha = 0.01; anisotropic: cook-torrance's alpha_x, alpha_y
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 3e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_beckmann(cos_h) with cos_h = n.h, then p_alpha; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// beckmann, beckmann-ct: scale exp(-tan^2 / alpha^2) / cos^4, given cos and sin^2 of theta_h.
/// beckmann: scale = 1 / (pi alpha^2) (normalised, Walter et al. 2007); beckmann-ct:
/// scale = 1 / (4 alpha^2) (Cook & Torrance 1982 as printed in seed 000).
fn fb_d_beckmann(c: f32, s2: f32, inv_alpha2: f32, scale: f32) -> f32 {
    let inv_c2 = 1.0 / (c * c);
    return scale * exp(-(s2 * inv_c2) * inv_alpha2) * (inv_c2 * inv_c2);
}

/// beckmann: exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)
/// Source: Beckmann & Spizzichino 1963; Walter et al. 2007 (normalisation of Mitsuba 3, pbrt). Instance: runtime parameters p_alpha; fixed: no parameters.
fn fb_beckmann(cos_h: f32, p_alpha: f32) -> f32 {
    let cc = min(cos_h, 1.0);
    let d = fb_d_beckmann(cc, (1.0 - cc) * (1.0 + cc), (1.0 / (p_alpha * p_alpha)), (0.3183098861837907 / (p_alpha * p_alpha)));
    return select(0.0, d, cos_h >= FB_COS_MIN);
}
