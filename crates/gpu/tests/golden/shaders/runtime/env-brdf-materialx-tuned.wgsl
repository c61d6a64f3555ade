// fastbrdf 0.1.0 (env): env-brdf-materialx-tuned
// Made by: fastbrdf shader --model env-brdf-materialx-tuned --lang wgsl --runtime-params
//
// Formula: env-brdf-materialx's form, its 2 x 17 free constants refitted against env-brdf (max and mean both below MaterialX's)
// Source: this project (fit_env_rational example)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-materialx-tuned vs env-brdf: max abs error (relative to the peak) <= 0.0797 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_materialx_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

/// P(x, y) = c0 + c1 x + c2 y + c3 x y + c4 x^2 + c5 y^2 + c6 x^2 y + c7 x y^2 + c8 x^2 y^2, by
/// Horner in y for each power of x, then in x (as env_rational::poly).
fn fb_env_rational_poly(x: f32, y: f32, c: array<f32, 9>) -> f32 {
    let p0 = y * (y * c[5] + c[2]) + c[0];
    let p1 = y * (y * c[7] + c[3]) + c[1];
    let p2 = y * (y * c[8] + c[6]) + c[4];
    return x * (x * p2 + p1) + p0;
}

/// env-brdf-materialx(-tuned): one term, numerator over denominator, clamped at 0.
fn fb_env_rational(cos_v: f32, alpha: f32, num: array<f32, 9>, den: array<f32, 9>) -> f32 {
    return max(fb_env_rational_poly(cos_v, alpha, num) / fb_env_rational_poly(cos_v, alpha, den), 0.0);
}

/// env-brdf-materialx-tuned: env-brdf-materialx's form, its 2 x 17 free constants refitted against env-brdf (max and mean both below MaterialX's)
/// Source: this project (fit_env_rational example). Instance: runtime parameters none; fixed: term = scale.
fn fb_env_brdf_materialx_tuned(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_env_rational(v, a, array<f32, 9>(0.085452f, -0.191066f, 10.218748f, 0.90751f, 28.483358f, -8.181671f, -24.73793f, 17.28328f, -6.033422f), array<f32, 9>(1.0f, -1.180156f, 8.80378f, 14.385899f, 27.73535f, -7.465713f, -33.963554f, 14.708145f, 34.39794f));
}
