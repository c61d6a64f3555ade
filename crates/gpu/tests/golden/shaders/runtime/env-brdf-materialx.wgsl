// fastbrdf 0.1.0 (env): env-brdf-materialx
// Made by: fastbrdf shader --model env-brdf-materialx --lang wgsl --runtime-params
//
// Formula: x = cos_v, y = alpha, P(x, y) = biquadratic (9 terms); scale = P_a / P_b, bias = P_c / P_d, clamped at 0
// Source: MaterialX mx_ggx_dir_albedo_analytic (libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl, main at 0aa65a1)
// Note: fitted by MaterialX to Monte Carlo data of GGX with height-correlated Smith (alpha, not perceptual roughness, is its second input)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-materialx vs env-brdf: max abs error (relative to the peak) <= 0.0864 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_materialx(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

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

/// env-brdf-materialx: x = cos_v, y = alpha, P(x, y) = biquadratic (9 terms); scale = P_a / P_b, bias = P_c / P_d, clamped at 0
/// Source: MaterialX mx_ggx_dir_albedo_analytic (libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl, main at 0aa65a1). Instance: runtime parameters none; fixed: term = scale.
fn fb_env_brdf_materialx(cos_v: f32, alpha: f32) -> f32 {
    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);
    let a = select(0.005f, min(alpha, 1.0f), alpha > 0.005f);
    return fb_env_rational(v, a, array<f32, 9>(0.10031f, -0.63301f, 9.74995f, -2.02075f, 29.38247f, -8.24713f, -26.5151f, 19.98406f, -5.41717f), array<f32, 9>(1.0f, -1.76427f, 8.26501f, 11.5484f, 28.99991f, -7.50867f, -36.16186f, 15.85408f, 33.4155f));
}
