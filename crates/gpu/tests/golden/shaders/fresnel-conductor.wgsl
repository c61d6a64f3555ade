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
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_conductor(cos_vh) with cos_vh = v.h; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// fresnel-conductor: the exact unpolarised Fresnel reflectance of a conductor eta + i k,
/// clamped to [0, 1]. Twin of fresnel::conductor, same arrangement (no 1 - sin^2 and no
/// |t0| - t0 cancellation; R_s and R_p as ratios of sums of squares).
fn fb_f_conductor(c_in: f32, eta: f32, k: f32) -> f32 {
    let c = select(8.673617379884035e-19, min(c_in, 1.0), c_in >= 8.673617379884035e-19);
    let c2 = c * c;
    let s2 = (1.0 - c) * (1.0 + c);
    let p = k * k + (1.0 - eta) * (1.0 + eta);
    let sp = sqrt(max(p, 0.0));
    let t0 = select(((eta - 1.0) * (eta + 1.0) - k * k) + c2, (c - sp) * (c + sp), p > 0.0);
    let ek = 2.0 * eta * k;
    let at0 = abs(t0);
    let den = sqrt(t0 * t0 + ek * ek) + at0;
    let q = select(0.0, 0.5 * ek * ek / den, den > 0.0);
    let big = at0 + q;
    let a2 = select(q, big, t0 >= 0.0);
    let b2 = select(big, q, t0 >= 0.0);
    let a = sqrt(a2);
    let rs = ((a - c) * (a - c) + b2) / ((a + c) * (a + c) + b2);
    let bc2 = b2 * c2;
    let ac = a * c;
    let rp = rs * ((ac - s2) * (ac - s2) + bc2) / ((ac + s2) * (ac + s2) + bc2);
    return fb_clamp01((rp + rs) * 0.5);
}

/// fresnel-conductor: (R_s + R_p) / 2 for complex index eta + i k, exact
/// Source: Fresnel equations; pbrt-v3 FrConductor. Instance: eta = 1.5, k = 0.
fn fb_fresnel_conductor(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_conductor(c, 1.5f, 0.0f);
}
