// BROKEN ON PURPOSE (a test model for `fastbrdf conform`): Lambert (f = 1/pi over the whole
// hemisphere) whose sampler only draws theta_i < 60 degrees, cosine-weighted and renormalised
// there (pdf = cos / (0.75 pi)); brdf_pdf is 0 beyond 60 degrees where f is not, so the
// estimator misses a quarter of the albedo (its mean weight is 0.75, not 1).

const PI: f32 = 3.14159265358979;

fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    return 1.0 / PI;
}

fn brdf_sample(wo: vec3<f32>, u: vec2<f32>) -> vec4<f32> {
    // sin^2 theta uniform in [0, 0.75): cosine-weighted on the cap theta < 60 degrees.
    let s2 = 0.75 * u.x;
    let r = sqrt(s2);
    let phi = 2.0 * PI * u.y;
    let wi = vec3<f32>(r * cos(phi), r * sin(phi), sqrt(1.0 - s2));
    return vec4<f32>(wi, brdf_pdf(wo, wi));
}

fn brdf_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wi.z <= 0.5 {
        return 0.0;
    }
    return wi.z / (0.75 * PI);
}
