// BROKEN ON PURPOSE (a test model for `fastbrdf conform`): Lambert sampled by the cosine with
// the right pdf (cos/pi), but the weight it reports (brdf_weight) is f / pdf, without the
// cosine: 1 / cos instead of 1.

const PI: f32 = 3.14159265358979;

fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    return 1.0 / PI;
}

fn brdf_sample(wo: vec3<f32>, u: vec2<f32>) -> vec4<f32> {
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let wi = vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
    return vec4<f32>(wi, brdf_pdf(wo, wi));
}

fn brdf_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wi.z <= 0.0 {
        return 0.0;
    }
    return wi.z / PI;
}

fn brdf_weight(wo: vec3<f32>, wi: vec3<f32>, pdf: f32) -> f32 {
    return brdf(wi, wo) / pdf;
}
