// fastbrdf 0.1.0 (env): env-brdf-approx
// Made by: fastbrdf shader --model env-brdf-approx --lang wgsl
//
// Formula: p = sqrt(alpha) c0 + c1, a004 = min(p.x^2, 2^(-9.28 cos_v)) p.x + p.y, scale = -1.04 a004 + p.z, bias = max(0, 1.04 a004 + p.w)
// Source: Karis 2014, Physically Based Shading on Mobile (Unreal's EnvBRDFApprox)
// Note: fitted to Unreal's table (separable Schlick-Smith G, k = alpha/2, which is darker than the height-correlated term at grazing: the error is largest there); the bias is clamped at 0
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-approx vs env-brdf: max abs error (relative to the peak) <= 0.525 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_env_brdf_approx(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

/// env-brdf-approx(-tuned) (Karis 2014, EnvBRDFApprox): k = c0 (4), c1 (4), the exp2 rate,
/// the two output slopes; r = sqrt(alpha); the bias clamped at 0.
fn fb_env_approx(cos_v: f32, alpha: f32, k: array<f32, 11>, bias: bool) -> f32 {
    let r = sqrt(alpha);
    let px = r * k[0] + k[4];
    let py = r * k[1] + k[5];
    let a004 = min(px * px, exp2(k[8] * cos_v)) * px + py;
    let v = select(k[9] * a004 + (r * k[2] + k[6]), k[10] * a004 + (r * k[3] + k[7]), bias);
    return max(v, 0.0);
}

/// env-brdf-approx: p = sqrt(alpha) c0 + c1, a004 = min(p.x^2, 2^(-9.28 cos_v)) p.x + p.y, scale = -1.04 a004 + p.z, bias = max(0, 1.04 a004 + p.w)
/// Source: Karis 2014, Physically Based Shading on Mobile (Unreal's EnvBRDFApprox). Instance: term = scale.
fn fb_env_brdf_approx(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_env_approx(v, a, array<f32, 11>(-1.0f, -0.0275f, -0.572f, 0.022f, 1.0f, 0.0425f, 1.04f, -0.04f, -9.28f, -1.04f, 1.04f), false);
}
