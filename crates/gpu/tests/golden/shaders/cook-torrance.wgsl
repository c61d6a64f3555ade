// fastbrdf 0.1.0 (brdf): cook-torrance
// Made by: fastbrdf shader --model cook-torrance --lang wgsl
//
// Formula: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators)
// Note: ops exclude D, G, F and the pair set-up; equals Mitsuba 3 roughconductor eval / cos_o; f32: 1e-5 except with f = dielectric/conductor at eta << 1, where F is a near-step at the critical angle and wi.h rounded once to f32 can double it (1.0 at eta = 0.01); anisotropic (alpha_x, alpha_y, d = beckmann(-ct)/ggx, a Smith g): f32 1.4e-6 measured with f = none/schlick (1e-5 documented)
// Parameters (this export: alpha = 0.3, d = beckmann, denominator = 4, eta = 1.5, f = none, f0 = 0.04, f90 = 1, g = smith, k = 0, ms = none, remap = alpha-half):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
//   d: microfacet distribution id (one of beckmann, beckmann-ct, beckmann-pow, beckmann-power4, beckmann-power8, beckmann-power16, ggx, default beckmann)
//   g: shadowing-masking term; when not given, the Smith term of d (smith for the Beckmann family, smith-ggx for ggx) (one of v-cavity, smith, smith-rational, smith-beckmann-correlated, smith-ggx, smith-ggx-correlated, smith-ggx-correlated-fast, smith-ggx-correlated-fast-tuned, smith-ggx-joint-approx, schlick-ggx, kelemen, neumann, default smith)
//   f: Fresnel term (one of none, schlick, schlick-sg, schlick-sg-tuned, dielectric, conductor, default none)
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
//   k: extinction coefficient (imaginary part of the index, conductors) (range [0, 20], default 0)
//   denominator: 4 cos_i cos_o (microfacet theory), cos_i cos_o (seed 000), pi cos_i cos_o (seed 001) (one of 4, seed-000, seed-001, default 4)
//   ms: energy compensation for multiple scattering: none, kulla-conty (Kulla and Conty 2017), filament (Filament's, view direction wo only; not reciprocal); needs d = ggx, g = smith-ggx-correlated (one of none, kulla-conty, filament, default none)
//   alpha_x: anisotropic slope along x (with alpha_y; replaces alpha); needs d = beckmann(-ct) or ggx, a Smith g, ms = none (range [0.005, 1], default -)
//   alpha_y: anisotropic slope along y (with alpha_x; replaces alpha); needs d = beckmann(-ct) or ggx, a Smith g, ms = none (range [0.005, 1], default -)
//   remap: Schlick's k: alpha / 2, or Unreal's (sqrt(alpha) + 1)^2 / 8 (needs g = schlick-ggx) (one of alpha-half, ue4, default alpha-half)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 3e0 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_cook_torrance(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// The geometry of a direction pair (twin: ops::pair and fastbrdf::vec3::Pair::new).
struct FbPair {
    /// Both directions non-zero, above the surface (cos >= FB_COS_MIN), not opposite.
    valid: bool,
    /// cos theta_i (wi . n) and cos theta_o (wo . n), n = +z.
    cos_i: f32,
    cos_o: f32,
    /// The half vector, normalised.
    h: vec3<f32>,
    /// sin^2 theta_h = h.x^2 + h.y^2.
    sin2_h: f32,
    /// wi . h, computed as |wi + wo| / 2 (exactly symmetric in wi and wo).
    cos_ih: f32,
    /// The normalised directions.
    wi: vec3<f32>,
    wo: vec3<f32>,
}

/// v divided by its largest component when |v|^2 leaves [2^-100, 2^100] (where it would
/// underflow to 0 or overflow in f32, and a finite direction such as (1e-30, 0, 1e-30) would
/// read as zero-length), else v: the normalisation is then scale-safe, as the CPU's
/// (twin: fastbrdf::vec3::unit).
fn fb_rescale(v: vec3<f32>) -> vec3<f32> {
    let l = dot(v, v);
    let m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    let safe = (l >= 7.888609052210118e-31) & (l <= 1.2676506002282294e30);
    return select(v / m, v, safe | (m == 0.0));
}

/// Normalises wi and wo (local frame, normal +z, any finite length) and builds their half vector.
fn fb_pair(wi_raw: vec3<f32>, wo_raw: vec3<f32>) -> FbPair {
    let wi_in = fb_rescale(wi_raw);
    let wo_in = fb_rescale(wo_raw);
    let li = dot(wi_in, wi_in);
    let lo = dot(wo_in, wo_in);
    let wi = wi_in * (1.0 / sqrt(li));
    let wo = wo_in * (1.0 / sqrt(lo));
    let s = wi + wo;
    let len = sqrt(dot(s, s));
    let h = s / len;
    let valid = (li > 0.0) & (lo > 0.0) & (wi.z >= FB_COS_MIN) & (wo.z >= FB_COS_MIN) & (len > 0.0);
    return FbPair(valid, wi.z, wo.z, h, h.x * h.x + h.y * h.y, 0.5 * len, wi, wo);
}

/// beckmann, beckmann-ct: scale exp(-tan^2 / alpha^2) / cos^4, given cos and sin^2 of theta_h.
/// beckmann: scale = 1 / (pi alpha^2) (normalised, Walter et al. 2007); beckmann-ct:
/// scale = 1 / (4 alpha^2) (Cook & Torrance 1982 as printed in seed 000).
fn fb_d_beckmann(c: f32, s2: f32, inv_alpha2: f32, scale: f32) -> f32 {
    let inv_c2 = 1.0 / (c * c);
    return scale * exp(-(s2 * inv_c2) * inv_alpha2) * (inv_c2 * inv_c2);
}

/// 1 / sqrt(pi), for the Smith term.
const FB_INV_SQRT_PI: f32 = 0.5641895835477563;

/// erfc(x) for x >= 0, relative error below 1.2e-7 (Numerical Recipes' erfcc, a Chebyshev
/// fit). WGSL has no erf; the CPU uses libm's erfc.
fn fb_erfc(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.5 * x);
    let p = -1.26551223 + t * (1.00002368 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806
        + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223
        + t * 0.17087277))))))));
    return t * exp(-x * x + p);
}

/// smith (Walter et al. 2007, eq. 25-27): G1 = 1 / (1 + Lambda(a)), a = 1 / (alpha tan theta),
/// Lambda = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2.
fn fb_g1_smith(c: f32, alpha: f32) -> f32 {
    let sin = sqrt(max((1.0 - c) * (1.0 + c), 0.0));
    let a = c / (alpha * sin);
    let lambda = 0.5 * (exp(-a * a) * FB_INV_SQRT_PI / a - fb_erfc(a));
    return select(1.0 / (1.0 + lambda), 1.0, c >= 1.0);
}

/// cook-torrance: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
/// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators). Instance: alpha = 0.3, d = beckmann, denominator = 4, eta = 1.5, f = none, f0 = 0.04, f90 = 1, g = smith, k = 0, ms = none, remap = alpha-half.
fn fb_cook_torrance(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = fb_pair(wi, wo);
    let d = select(0.0, fb_d_beckmann(p.h.z, p.sin2_h, 11.111111f, 3.5367765f), p.h.z >= FB_COS_MIN);
    let g = fb_g1_smith(p.cos_o, 0.3f) * fb_g1_smith(p.cos_i, 0.3f);
    let f = 1.0f;
    let v = f * d * g * 0.25f / (p.cos_i * p.cos_o);
    return select(0.0, v, p.valid);
}
