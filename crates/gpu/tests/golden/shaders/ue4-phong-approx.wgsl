// fastbrdf 0.1.0 (lobe): ue4-phong-approx
// Made by: fastbrdf shader --model ue4-phong-approx --lang wgsl
//
// Formula: exp2(1.4427 (n + 0.775)(c - 1))
// Source: Unreal Engine 4 mobile shading (PhongApprox), Karis 2014
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   ue4-phong-approx vs pow: max abs error (relative to the peak) <= 0.17 over n in [1, 100000], whole domain
//   ue4-phong-approx vs pow: max abs error (relative to the peak) <= 0.0097 over n in [16, 100000], whole domain
//   ue4-phong-approx vs pow: max rel error <= 0.183 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_ue4_phong_approx(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// sg, sg-tuned, ue4-phong-approx: 2^(k (c - 1)), the spherical Gaussian. sg: k = n / ln 2;
/// ue4-phong-approx: k = 1.4427 (n + 0.775) (Karis 2013). Cost: 1 mul, 1 add, 1 exp2.
fn fb_lobe_exp2(c: f32, k: f32) -> f32 {
    return exp2(k * (fb_clamp01(c) - 1.0));
}

/// ue4-phong-approx: exp2(1.4427 (n + 0.775)(c - 1))
/// Source: Unreal Engine 4 mobile shading (PhongApprox), Karis 2014. Instance: n = 20.
fn fb_ue4_phong_approx(c: f32) -> f32 {
    return fb_lobe_exp2(c, 29.972092f);
}
