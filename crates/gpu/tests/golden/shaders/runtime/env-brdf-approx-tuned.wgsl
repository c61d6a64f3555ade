// fastbrdf 0.1.0 (env): env-brdf-approx-tuned
// Made by: fastbrdf shader --model env-brdf-approx-tuned --lang wgsl --runtime-params
//
// Formula: env-brdf-approx's form, its 11 constants refitted minimax against env-brdf
// Source: this project (fit_env_brdf example)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-approx-tuned vs env-brdf: max abs error (relative to the peak) <= 0.339 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_approx_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

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

/// env-brdf-approx-tuned: env-brdf-approx's form, its 11 constants refitted minimax against env-brdf
/// Source: this project (fit_env_brdf example). Instance: runtime parameters none; fixed: term = scale.
fn fb_env_brdf_approx_tuned(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_env_approx(v, a, array<f32, 11>(-1.072325f, -0.028393f, -0.488609f, 0.023184f, 1.040579f, 0.040344f, 1.129695f, -0.038556f, -9.478977f, -0.965804f, 1.019101f), false);
}
