// fastbrdf 0.1.0 (brdf): cook-torrance
// Made by: fastbrdf shader --model cook-torrance --param d=ggx --param alpha=0.2 --param f=conductor --param eta=0.18299,0.42108,1.3734 --param k=3.4242,2.3459,1.7704 --lang wgsl
//
// Formula: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators)
// Note: ops exclude D, G, F and the pair set-up; equals Mitsuba 3 roughconductor eval / cos_o; f32: 1e-5 except with f = dielectric/conductor at eta << 1, where F is a near-step at the critical angle and wi.h rounded once to f32 can double it (1.0 at eta = 0.01); anisotropic (alpha_x, alpha_y, d = beckmann(-ct)/ggx, a Smith g): f32 1.4e-6 measured with f = none/schlick (1e-5 documented)
// Parameters (this export: alpha = 0.2, d = ggx, denominator = 4, eta = 0.18299, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 3.4242, ms = none, remap = alpha-half):
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
// Entry: fb_cook_torrance_rgb(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns a 3-vector (R, G, B).
// Colour: per-channel parameters make three grey instances, fb_cook_torrance_r, fb_cook_torrance_g, fb_cook_torrance_b (channels R, G, B at 650, 550, 450 nm; the parameters above are the R channel's), and fb_cook_torrance_rgb with the same inputs, returning the three as a vector.
//   R (650 nm): alpha = 0.2, d = ggx, denominator = 4, eta = 0.18299, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 3.4242, ms = none, remap = alpha-half
//   G (550 nm): alpha = 0.2, d = ggx, denominator = 4, eta = 0.42108, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 2.3459, ms = none, remap = alpha-half
//   B (450 nm): alpha = 0.2, d = ggx, denominator = 4, eta = 1.3734, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 1.7704, ms = none, remap = alpha-half

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

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

/// ggx (Trowbridge & Reitz 1975; Walter et al. 2007): alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2),
/// given cos and sin^2 of theta_h; scale = alpha^2 / pi. No cancellation at small alpha.
fn fb_d_ggx(c: f32, s2: f32, alpha2: f32, scale: f32) -> f32 {
    let t = alpha2 * (c * c) + s2;
    return scale / (t * t);
}

/// sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c, for the GGX Smith terms
/// (1 + Lambda = (1 + S) / 2; no S - 1 is formed).
fn fb_ggx_s(c: f32, alpha2: f32) -> f32 {
    let s2 = (1.0 - c) * (1.0 + c);
    return sqrt(c * c + alpha2 * s2) / c;
}

/// smith-ggx (Walter et al. 2007, eq. 34): G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); 1 at c >= 1.
fn fb_g1_smith_ggx(c: f32, alpha2: f32) -> f32 {
    return select(2.0 / (1.0 + fb_ggx_s(c, alpha2)), 1.0, c >= 1.0);
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

/// cook-torrance: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
/// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators). Instance: alpha = 0.2, d = ggx, denominator = 4, eta = 0.18299, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 3.4242, ms = none, remap = alpha-half.
fn fb_cook_torrance_r(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = fb_pair(wi, wo);
    let d = select(0.0, fb_d_ggx(p.h.z, p.sin2_h, 0.04f, 0.012732396f), p.h.z >= FB_COS_MIN);
    let g = fb_g1_smith_ggx(p.cos_o, 0.04f) * fb_g1_smith_ggx(p.cos_i, 0.04f);
    let f = fb_f_conductor(p.cos_ih, 0.18299f, 3.4242f);
    let v = f * d * g * 0.25f / (p.cos_i * p.cos_o);
    return select(0.0, v, p.valid);
}

/// cook-torrance: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
/// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators). Instance: alpha = 0.2, d = ggx, denominator = 4, eta = 0.42108, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 2.3459, ms = none, remap = alpha-half.
fn fb_cook_torrance_g(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = fb_pair(wi, wo);
    let d = select(0.0, fb_d_ggx(p.h.z, p.sin2_h, 0.04f, 0.012732396f), p.h.z >= FB_COS_MIN);
    let g = fb_g1_smith_ggx(p.cos_o, 0.04f) * fb_g1_smith_ggx(p.cos_i, 0.04f);
    let f = fb_f_conductor(p.cos_ih, 0.42108f, 2.3459f);
    let v = f * d * g * 0.25f / (p.cos_i * p.cos_o);
    return select(0.0, v, p.valid);
}

/// cook-torrance: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
/// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators). Instance: alpha = 0.2, d = ggx, denominator = 4, eta = 1.3734, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 1.7704, ms = none, remap = alpha-half.
fn fb_cook_torrance_b(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = fb_pair(wi, wo);
    let d = select(0.0, fb_d_ggx(p.h.z, p.sin2_h, 0.04f, 0.012732396f), p.h.z >= FB_COS_MIN);
    let g = fb_g1_smith_ggx(p.cos_o, 0.04f) * fb_g1_smith_ggx(p.cos_i, 0.04f);
    let f = fb_f_conductor(p.cos_ih, 1.3734f, 1.7704f);
    let v = f * d * g * 0.25f / (p.cos_i * p.cos_o);
    return select(0.0, v, p.valid);
}

/// cook-torrance in colour: the R, G, B channels (650, 550, 450 nm), each one grey instance above.
fn fb_cook_torrance_rgb(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(fb_cook_torrance_r(wi, wo), fb_cook_torrance_g(wi, wo), fb_cook_torrance_b(wi, wo));
}
