// fastbrdf 0.1.0 (fresnel): fresnel-dielectric
// Made by: fastbrdf shader --model fresnel-dielectric --lang wgsl
//
// Formula: (r_par^2 + r_perp^2) / 2, exact, with total internal reflection
// Source: Fresnel equations; pbrt-v3 FrDielectric
// Parameters (this export: eta = 1.5):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_fresnel_dielectric(cos_vh) with cos_vh = v.h; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// fresnel-dielectric: the exact unpolarised Fresnel reflectance of a dielectric of relative
/// index eta (1 on total internal reflection).
fn fb_f_dielectric(c_in: f32, eta: f32) -> f32 {
    let c = fb_clamp01(c_in);
    let sin2_t = (1.0 - c * c) / (eta * eta);
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let r_par = (eta * c - cos_t) / (eta * c + cos_t);
    let r_perp = (c - eta * cos_t) / (c + eta * cos_t);
    let f = (r_par * r_par + r_perp * r_perp) * 0.5;
    return select(f, 1.0, sin2_t >= 1.0);
}

/// fresnel-dielectric: (r_par^2 + r_perp^2) / 2, exact, with total internal reflection
/// Source: Fresnel equations; pbrt-v3 FrDielectric. Instance: eta = 1.5.
fn fb_fresnel_dielectric(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_dielectric(c, 1.5f);
}
