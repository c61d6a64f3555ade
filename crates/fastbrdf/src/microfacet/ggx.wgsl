// WGSL twin of microfacet/ggx.rs (see microfacet/mod.wgsl).

/// ggx (Trowbridge & Reitz 1975; Walter et al. 2007): alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2),
/// given cos and sin^2 of theta_h; scale = alpha^2 / pi. No cancellation at small alpha.
fn fb_d_ggx(c: f32, s2: f32, alpha2: f32, scale: f32) -> f32 {
    let t = alpha2 * (c * c) + s2;
    return scale / (t * t);
}
