// fastbrdf 0.1.0 (env): sheen-albedo-khronos
// Made by: fastbrdf shader --model sheen-albedo-khronos --lang wgsl --runtime-params
//
// Formula: 0.65584461 (1 - mu)^3 + 1 / (4.16526551 + exp(-7.97291361 sqrt(alpha) + 6.33516894))
// Source: Enterprise PBR 2022x (directional_albedo_sheen); the Khronos reference renderers
// Note: max abs 0.329 against sheen-albedo (charlie; mean 0.031) at grazing, alpha 0.07; 0.894 against neubelt's (gltf-pbr's sheen_albedo = fit reads it with either visibility); fastbrdf errors --model sheen-albedo-khronos
// Parameters (this export: no parameters):
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_sheen_albedo_khronos(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

/// mu in [0.001, 1] and alpha in [0.07, 1] (as sheen_albedo::clamp).
fn fb_sheen_e_clamp(mu: f32, alpha: f32) -> vec2<f32> {
    return vec2<f32>(min(max(mu, 0.001), 1.0), min(max(alpha, 0.07), 1.0));
}

/// sheen-albedo-khronos: k0 (1 - mu)^3 + 1 / (k1 + exp(k2 sqrt(alpha) + k3)).
fn fb_sheen_e_fit(mu_in: f32, alpha_in: f32, k0: f32, k1: f32, k2: f32, k3: f32) -> f32 {
    let c = fb_sheen_e_clamp(mu_in, alpha_in);
    let m = 1.0 - c.x;
    return k0 * (m * m * m) + 1.0 / (k1 + exp(k2 * sqrt(c.y) + k3));
}

/// sheen-albedo-khronos: 0.65584461 (1 - mu)^3 + 1 / (4.16526551 + exp(-7.97291361 sqrt(alpha) + 6.33516894))
/// Source: Enterprise PBR 2022x (directional_albedo_sheen); the Khronos reference renderers. Instance: runtime parameters none; fixed: no parameters.
fn fb_sheen_albedo_khronos(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_sheen_e_fit(v, a, 0.6558446f, 4.1652656f, -7.9729137f, 6.335169f);
}
