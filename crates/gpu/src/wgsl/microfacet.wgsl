// fastbrdf WGSL library: microfacet distributions D, shadowing G and Fresnel F.
// Twins: crates/fastbrdf/src/microfacet/* (formulas, sources, bounds) and batch/ops.rs.

/// beckmann, beckmann-ct: scale exp(-tan^2 / alpha^2) / cos^4, given cos and sin^2 of theta_h.
/// beckmann: scale = 1 / (pi alpha^2) (normalised, Walter et al. 2007); beckmann-ct:
/// scale = 1 / (4 alpha^2) (Cook & Torrance 1982 as printed in seed 000).
fn fb_d_beckmann(c: f32, s2: f32, inv_alpha2: f32, scale: f32) -> f32 {
    let inv_c2 = 1.0 / (c * c);
    return scale * exp(-(s2 * inv_c2) * inv_alpha2) * (inv_c2 * inv_c2);
}

/// beckmann-pow (seed 000): scale cos^e, e = 2 / alpha^2 - 4 (one power instead of exp;
/// fb_powr, accurate near cos = 1 where e reaches 19996 at alpha = 0.01).
fn fb_d_beckmann_pow(c: f32, e: f32, scale: f32) -> f32 {
    return scale * fb_powr(c, e);
}

/// beckmann-power4/8/16 (seed 000): scale max(1 + s (cos - 1), 0)^g, s = (2 / alpha^2 - 4) / g;
/// cos - 1 computed as -sin^2 / (1 + cos) (no cancellation).
fn fb_d_beckmann_power4(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow4(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}

fn fb_d_beckmann_power8(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow8(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}

fn fb_d_beckmann_power16(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow16(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}

/// v-cavity (Cook & Torrance 1982): min(1, 2 NH NV / VH, 2 NH NL / VH).
fn fb_g_v_cavity(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
    let k = 2.0 * cos_h / cos_vh;
    return min(min(1.0, k * cos_v), k * cos_l);
}

/// smith (Walter et al. 2007, eq. 25-27): G1 = 1 / (1 + Lambda(a)), a = 1 / (alpha tan theta),
/// Lambda = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2.
fn fb_g1_smith(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let lambda = 0.5 * (exp(-a * a) * FB_INV_SQRT_PI / a - fb_erfc(a));
    return select(1.0 / (1.0 + lambda), 1.0, c >= 1.0);
}

/// smith-rational (Walter et al. 2007, eq. 27): G1 = (3.535 a + 2.181 a^2) /
/// (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1.
fn fb_g1_smith_rational(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let a2 = a * a;
    let g = (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
    return select(g, 1.0, (a >= 1.6) | (c >= 1.0));
}

/// fresnel-schlick (Schlick 1994): f0 + (1 - f0)(1 - c)^5.
fn fb_f_schlick(c: f32, f0: f32) -> f32 {
    let m = 1.0 - fb_clamp01(c);
    let m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

/// fresnel-dielectric: the exact unpolarised Fresnel reflectance of a dielectric of relative
/// index eta (1 on total internal reflection). Twin of fresnel::dielectric, same arrangement:
/// e = (eta - 1)(eta + 1), g = sqrt(e + c^2), r_perp = -e / (c + g)^2,
/// r_par = e ((eta^2 + 1) c^2 - 1) / (eta^2 c + g)^2 (both exactly 0 at eta = 1); see the twin.
fn fb_f_dielectric(c_in: f32, eta: f32) -> f32 {
    let c = select(8.673617379884035e-19, min(c_in, 1.0), c_in >= 8.673617379884035e-19);
    let c2 = c * c;
    let e = (eta - 1.0) * (eta + 1.0);
    // Near the critical angle (eta < 1) g^2 = (c - s)(c + s), s = sqrt(1 - eta^2) (the CPU
    // holds s in two floats; here s is rounded once).
    let s = sqrt(max((1.0 - eta) * (1.0 + eta), 0.0));
    let g2 = select(e + c2, (c - s) * (c + s), eta < 1.0);
    let g = sqrt(max(g2, 0.0));
    let eta2 = eta * eta;
    let d_perp = c + g;
    let r_perp = -e / (d_perp * d_perp);
    let d_par = eta2 * c + g;
    let sin2 = (1.0 - c) * (1.0 + c);
    let brewster = select(eta2 * c2 - sin2, g2 - eta2 * sin2, eta < 1.0);
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
