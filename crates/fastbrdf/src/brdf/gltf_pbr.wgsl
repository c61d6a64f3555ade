// WGSL twin of brdf/gltf_pbr.rs: the helpers its body calls (the body itself is written per
// instance from its parts: brdf/gltf_pbr_wgsl.rs).

/// `v` in the frame whose x axis is (c, s, 0) (as gltf_pbr::Rotated::to).
fn fb_gltf_rot(v: vec3<f32>, c: f32, s: f32) -> vec3<f32> {
    return vec3<f32>(c * v.x + s * v.y, c * v.y - s * v.x, v.z);
}

/// Burley's diffuse factor (without base_color / pi), roughness r, c = wi . h.
fn fb_gltf_burley(cos_i: f32, cos_o: f32, c: f32, r: f32) -> f32 {
    let f90 = 0.5 + 2.0 * r * c * c;
    let mi = 1.0 - cos_i;
    let mo = 1.0 - cos_o;
    let mi2 = mi * mi;
    let mo2 = mo * mo;
    return (1.0 + (f90 - 1.0) * mi2 * mi2 * mi) * (1.0 + (f90 - 1.0) * mo2 * mo2 * mo);
}
