// WGSL twin of microfacet/fresnel.rs (see microfacet/mod.wgsl).

/// fresnel-schlick (Schlick 1994): f0 + (f90 - f0)(1 - c)^5.
fn fb_f_schlick(c: f32, f0: f32, f90: f32) -> f32 {
    let m = 1.0 - fb_clamp01(c);
    let m2 = m * m;
    return f0 + (f90 - f0) * (m2 * m2 * m);
}

/// fresnel-schlick-sg(-tuned) (Karis 2013): f0 + (f90 - f0) 2^((a c + b) c), a, b fixed by
/// the id (Karis's -5.55473, -6.98316, or their minimax refit).
fn fb_f_schlick_sg(c_in: f32, f0: f32, f90: f32, a: f32, b: f32) -> f32 {
    let c = fb_clamp01(c_in);
    return f0 + (f90 - f0) * exp2((a * c + b) * c);
}

/// fresnel-dielectric: the exact unpolarised Fresnel reflectance of a dielectric of relative
/// index eta (1 on total internal reflection), from e = eta^2 - 1 (see fb_f_dielectric_e).
fn fb_f_dielectric(c_in: f32, eta: f32) -> f32 {
    return fb_f_dielectric_e(c_in, eta, (eta - 1.0) * (eta + 1.0));
}

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
