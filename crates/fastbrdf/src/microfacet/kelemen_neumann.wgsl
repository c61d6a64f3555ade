// WGSL twin of microfacet/kelemen_neumann.rs (see microfacet/mod.wgsl).

/// kelemen (Kelemen & Szirmay-Kalos 2001): min(1, NL NV / VH^2), as (NV / VH) (NL / VH).
fn fb_g_kelemen(cos_v: f32, cos_l: f32, cos_vh: f32) -> f32 {
    return min(1.0, (min(cos_v, 1.0) / cos_vh) * (min(cos_l, 1.0) / cos_vh));
}

/// neumann (Neumann et al. 1999): NL NV / max(NL, NV) = min(NL, NV).
fn fb_g_neumann(cos_v: f32, cos_l: f32) -> f32 {
    return min(min(cos_v, cos_l), 1.0);
}
