// fastbrdf 0.1.0 (lobe): sg
// Made by: fastbrdf shader --model sg --lang wgsl
//
// Formula: exp2((n / ln 2)(c - 1))
// Source: Lagarde 2012, 'Spherical Gaussian approximation for Blinn-Phong, Phong and Fresnel'
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   sg vs pow: max abs error (relative to the peak) <= 0.368 over n in [1, 100000], whole domain
//   sg vs pow: max abs error (relative to the peak) <= 0.0173 over n in [16, 100000], whole domain
//   sg vs pow: max rel error <= 0.214 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_sg(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// sg, sg-tuned, ue4-phong-approx: 2^(k (c - 1)), the spherical Gaussian. sg: k = n / ln 2;
/// ue4-phong-approx: k = 1.4427 (n + 0.775) (Karis 2013). Cost: 1 mul, 1 add, 1 exp2.
fn fb_lobe_exp2(c: f32, k: f32) -> f32 {
    return exp2(k * (fb_clamp01(c) - 1.0));
}

/// sg: exp2((n / ln 2)(c - 1))
/// Source: Lagarde 2012, 'Spherical Gaussian approximation for Blinn-Phong, Phong and Fresnel'. Instance: n = 20.
fn fb_sg(c: f32) -> f32 {
    return fb_lobe_exp2(c, 28.8539f);
}
