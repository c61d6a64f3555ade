// WGSL twin of brdf/cook_torrance.rs (see brdf/mod.wgsl): the anisotropic stretch. The body
// itself is assembled per instance by CookTorrance::wgsl_body from its D, G and F.

/// sin^2 theta_h of the isotropic D at sqrt(ax ay) that gives the anisotropic D:
/// h.x^2 ay/ax + h.y^2 ax/ay (xy = ax/ay, yx = ay/ax).
fn fb_aniso_sin2(h: vec3<f32>, xy: f32, yx: f32) -> f32 {
    return h.x * h.x * yx + (h.y * h.y) * xy;
}

/// The cosine of w the isotropic Smith term at sqrt(ax ay) needs to give the anisotropic
/// one: w.z / sqrt(w.z^2 + w.x^2 ax/ay + w.y^2 ay/ax).
fn fb_aniso_cos(w: vec3<f32>, xy: f32, yx: f32) -> f32 {
    let q = w.x * w.x * xy + (w.y * w.y) * yx;
    return w.z / sqrt(w.z * w.z + q);
}
