// WGSL twin of brdf/ward.rs (see brdf/mod.wgsl).

/// ward (Ward 1992, anisotropic): scale exp(-(hx^2/ax^2 + hy^2/ay^2) / hz^2) / sqrt(ci co),
/// scale = 1 / (4 pi ax ay).
fn fb_brdf_ward(wi: vec3<f32>, wo: vec3<f32>, inv_ax2: f32, inv_ay2: f32, scale: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let lobe = exp(-(p.h.x * p.h.x * inv_ax2 + p.h.y * p.h.y * inv_ay2) / (p.h.z * p.h.z));
    return select(0.0, scale * lobe / sqrt(p.cos_i * p.cos_o), p.valid);
}

/// ward-pow (seed 000): the exponential replaced by cos^e theta_h, e = 2 / alpha^2 (fb_powr).
fn fb_brdf_ward_pow(wi: vec3<f32>, wo: vec3<f32>, e: f32, scale: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let lobe = fb_powr(p.h.z, e);
    return select(0.0, scale * lobe / sqrt(p.cos_i * p.cos_o), p.valid);
}

/// ward-power16 (seed 000): the exponential replaced by max(1 + s (cos theta_h - 1), 0)^16,
/// s = (2 / alpha^2) / 16.
fn fb_brdf_ward_power16(wi: vec3<f32>, wo: vec3<f32>, s: f32, scale: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let lobe = fb_pow16(max(1.0 + s * (-p.sin2_h / (1.0 + p.h.z)), 0.0));
    return select(0.0, scale * lobe / sqrt(p.cos_i * p.cos_o), p.valid);
}
