// fastbrdf 0.1.0 (fresnel): fresnel-conductor
// Made by: fastbrdf shader --model fresnel-conductor --lang wgsl
//
// Formula: (R_s + R_p) / 2 for complex index eta + i k, exact
// Source: Fresnel equations; pbrt-v3 FrConductor
// Parameters (this export: eta = 1.5, k = 0):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
//   k: extinction coefficient (imaginary part of the index, conductors) (range [0, 20], default 0)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_fresnel_conductor(cos_vh) with cos_vh = v.h; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// fresnel-conductor: the exact unpolarised Fresnel reflectance of a conductor eta + i k
/// (Mitsuba 3's fresnel_conductor arrangement), clamped to [0, 1].
fn fb_f_conductor(c_in: f32, eta: f32, k: f32) -> f32 {
    let c = fb_clamp01(c_in);
    let cos2 = c * c;
    let sin2 = 1.0 - cos2;
    let eta2 = eta * eta;
    let k2 = k * k;
    let t0 = eta2 - k2 - sin2;
    let a2b2 = sqrt(t0 * t0 + 4.0 * eta2 * k2);
    let t1 = a2b2 + cos2;
    let a = sqrt(max(0.5 * (a2b2 + t0), 0.0));
    let t2 = 2.0 * c * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = cos2 * a2b2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    return fb_clamp01((rp + rs) * 0.5);
}

/// fresnel-conductor: (R_s + R_p) / 2 for complex index eta + i k, exact
/// Source: Fresnel equations; pbrt-v3 FrConductor. Instance: eta = 1.5, k = 0.
fn fb_fresnel_conductor(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_conductor(c, 1.5f, 0.0f);
}
