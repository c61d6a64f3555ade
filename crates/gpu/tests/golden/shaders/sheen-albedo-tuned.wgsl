// fastbrdf 0.1.0 (env): sheen-albedo-tuned
// Made by: fastbrdf shader --model sheen-albedo-tuned --lang wgsl
//
// Formula: max(0, exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha), 5 constants fitted against sheen-albedo per visibility
// Source: this project (fit_sheen_albedo example)
// Note: max abs 0.124 against sheen-albedo (charlie; mean 0.0114), 0.103 (neubelt; mean 0.0072); fastbrdf errors --model sheen-albedo-tuned --param v=V
// Parameters (this export: v = charlie):
//   v: the sheen visibility whose albedo: charlie (Estevez and Kulla's fitted Lambda) or neubelt (Neubelt and Pettineo) (one of charlie, neubelt, default charlie)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_sheen_albedo_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

/// mu in [0.001, 1] and alpha in [0.07, 1] (as sheen_albedo::clamp).
fn fb_sheen_e_clamp(mu: f32, alpha: f32) -> vec2<f32> {
    return vec2<f32>(min(max(mu, 0.001), 1.0), min(max(alpha, 0.07), 1.0));
}

/// sheen-albedo-tuned: max(0, exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha)
/// (as sheen_albedo::own).
fn fb_sheen_e_own(mu_in: f32, alpha_in: f32, k0: f32, k1: f32, k2: f32, k3: f32, k4: f32) -> f32 {
    let c = fb_sheen_e_clamp(mu_in, alpha_in);
    let inv = 1.0 / sqrt(c.y);
    return max(k4 * c.y + exp(inv * (c.x * k3 + k2) + (c.x * k1 + k0)), 0.0);
}

/// sheen-albedo-tuned: max(0, exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha), 5 constants fitted against sheen-albedo per visibility
/// Source: this project (fit_sheen_albedo example). Instance: v = charlie.
fn fb_sheen_albedo_tuned(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_sheen_e_own(v, a, -0.26377833f, -0.5087462f, 0.03881789f, -1.3130189f, 0.0497051f);
}
