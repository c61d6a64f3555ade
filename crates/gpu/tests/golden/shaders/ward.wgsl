// fastbrdf 0.1.0 (brdf): ward
// Made by: fastbrdf shader --model ward --lang wgsl
//
// Formula: exp(-(h_x^2/ax^2 + h_y^2/ay^2)/h_z^2) / (4 pi ax ay sqrt(cos_i cos_o))
// Source: Ward 1992, 'Measuring and modeling anisotropic reflection'
// Note: albedo <= 1 up to 85 degrees; exceeds 1 within ~0.5 degree of grazing (1.50 at 89.9 degrees, alpha = 1)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
//   alpha_x: anisotropic slope along x (with alpha_y; replaces alpha) (range [0.005, 1], default -)
//   alpha_y: anisotropic slope along y (with alpha_x; replaces alpha) (range [0.005, 1], default -)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-5 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_ward(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

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

/// ward (Ward 1992, anisotropic): scale exp(-(hx^2/ax^2 + hy^2/ay^2) / hz^2) / sqrt(ci co),
/// scale = 1 / (4 pi ax ay).
fn fb_brdf_ward(wi: vec3<f32>, wo: vec3<f32>, inv_ax2: f32, inv_ay2: f32, scale: f32) -> f32 {
    let p = fb_pair(wi, wo);
    let lobe = exp(-(p.h.x * p.h.x * inv_ax2 + p.h.y * p.h.y * inv_ay2) / (p.h.z * p.h.z));
    return select(0.0, scale * lobe / sqrt(p.cos_i * p.cos_o), p.valid);
}

/// ward: exp(-(h_x^2/ax^2 + h_y^2/ay^2)/h_z^2) / (4 pi ax ay sqrt(cos_i cos_o))
/// Source: Ward 1992, 'Measuring and modeling anisotropic reflection'. Instance: alpha = 0.3.
fn fb_ward(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    return fb_brdf_ward(wi, wo, 11.111111f, 11.111111f, 0.88419414f);
}
