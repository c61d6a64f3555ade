// BROKEN ON PURPOSE (a test model for `fastbrdf conform`): Lambert sampled by the cosine, but
// brdf_pdf and the pdf the sampler reports are both 1.05 times the true density cos/pi. The
// weight is consistent with them (fastbrdf computes f cos / pdf = 1/1.05), so only a check of
// the pdf against the sample histogram (chi-square) or of the mean weight sees it.

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
    return 1.05 * wi.z / PI;
}
