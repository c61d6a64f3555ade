// fastbrdf 0.1.0 (fresnel): fresnel-dielectric
// Made by: fastbrdf shader --model fresnel-dielectric --lang wgsl
//
// Formula: (r_par^2 + r_perp^2) / 2, exact, with total internal reflection
// Source: Fresnel equations; pbrt-v3 FrDielectric
// Parameters (this export: eta = 1.5):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_dielectric(cos_vh) with cos_vh = v.h; returns f32.

/// fresnel-dielectric with e = eta^2 - 1 = (eta - 1)(eta + 1) given, which the CPU computes
/// in f64 from the parameter and rounds once (exports with fixed parameters pass that number;
/// near eta = 1 the f32 eta's own rounding would move e by 1e-4 relative). Twin of
/// fresnel::dielectric, same arrangement: g = sqrt(e + c^2),
/// r_perp = -e / (c + g)^2, r_par = e ((eta^2 + 1) c^2 - 1) / (eta^2 c + g)^2 (both exactly 0
/// at eta = 1); see the twin.
fn fb_f_dielectric_e(c_in: f32, eta: f32, e: f32) -> f32 {
    let c = select(8.673617379884035e-19, min(c_in, 1.0), c_in >= 8.673617379884035e-19);
    let c2 = c * c;
    // Near the critical angle (eta < 1) g^2 = (c - s)(c + s), s = sqrt(1 - eta^2) (the CPU
    // holds s in two floats; here s is rounded once).
    let s = sqrt(max(-e, 0.0));
    let g2 = select(e + c2, (c - s) * (c + s), e < 0.0);
    let g = sqrt(max(g2, 0.0));
    let eta2 = eta * eta;
    let d_perp = c + g;
    let r_perp = -e / (d_perp * d_perp);
    let d_par = eta2 * c + g;
    let sin2 = (1.0 - c) * (1.0 + c);
    let brewster = select(eta2 * c2 - sin2, g2 - eta2 * sin2, e < 0.0);
    let r_par = e * brewster / (d_par * d_par);
    let f = min((r_par * r_par + r_perp * r_perp) * 0.5, 1.0);
    return select(f, 1.0, g2 <= 0.0);
}

/// fresnel-dielectric: (r_par^2 + r_perp^2) / 2, exact, with total internal reflection
/// Source: Fresnel equations; pbrt-v3 FrDielectric. Instance: eta = 1.5.
fn fb_fresnel_dielectric(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_dielectric_e(c, 1.5f, 1.25f);
}
