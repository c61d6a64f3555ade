// A GGX microfacet BRDF (Walter et al. 2007) with the uncorrelated Smith shadowing term and no
// Fresnel, one channel, sampled by its distribution of normals: an example of fastbrdf's WGSL
// function format (docs/book/src/user-shaders.md).
//
// param alpha 0.01 1 0.3
// param float scale 0 2 1

const PI: f32 = 3.14159265358979;

fn ggx_d(c: f32) -> f32 {
    let a2 = alpha * alpha;
    let t = c * c * (a2 - 1.0) + 1.0;
    return a2 / (PI * t * t);
}

fn smith_g1(c: f32) -> f32 {
    let a2 = alpha * alpha;
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

// Directions with a NaN or infinite component give 0, tested on the bits: a GPU may assume
// that floats are never NaN and fold a comparison with one (lavapipe does).
fn non_finite(v: vec3<f32>) -> bool {
    let b = bitcast<vec3<u32>>(v) & vec3<u32>(0x7fffffffu);
    return any(b >= vec3<u32>(0x7f800000u));
}

fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if non_finite(wi) || non_finite(wo) || wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = normalize(wi + wo);
    return scale * ggx_d(h.z) * smith_g1(wi.z) * smith_g1(wo.z) / (4.0 * wi.z * wo.z);
}

// The half vector from D(h) cos(theta_h) (tan^2 theta_h = alpha^2 u / (1 - u)), reflected.
fn brdf_sample(wo: vec3<f32>, u: vec2<f32>) -> vec4<f32> {
    let phi = 2.0 * PI * u.y;
    let t2 = alpha * alpha * u.x / (1.0 - u.x);
    let c = 1.0 / sqrt(1.0 + t2);
    let s = sqrt(max(0.0, 1.0 - c * c));
    let h = vec3<f32>(s * cos(phi), s * sin(phi), c);
    let wi = 2.0 * dot(wo, h) * h - wo;
    if wi.z <= 0.0 || dot(wo, h) <= 0.0 {
        return vec4<f32>(wi, 0.0);
    }
    return vec4<f32>(wi, brdf_pdf(wo, wi));
}

fn brdf_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = normalize(wi + wo);
    return ggx_d(h.z) * h.z / (4.0 * abs(dot(wo, h)));
}
