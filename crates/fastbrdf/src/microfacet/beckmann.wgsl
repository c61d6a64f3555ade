// WGSL twin of microfacet/beckmann.rs (see microfacet/mod.wgsl).

/// beckmann, beckmann-ct: scale exp(-tan^2 / alpha^2) / cos^4, given cos and sin^2 of theta_h.
/// beckmann: scale = 1 / (pi alpha^2) (normalised, Walter et al. 2007); beckmann-ct:
/// scale = 1 / (4 alpha^2) (Cook & Torrance 1982 as printed in seed 000).
fn fb_d_beckmann(c: f32, s2: f32, inv_alpha2: f32, scale: f32) -> f32 {
    let inv_c2 = 1.0 / (c * c);
    return scale * exp(-(s2 * inv_c2) * inv_alpha2) * (inv_c2 * inv_c2);
}
