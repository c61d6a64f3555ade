// fastbrdf 0.1.0 (lobe): sg-tuned
// Made by: fastbrdf shader --model sg-tuned --lang wgsl --runtime-params
//
// Formula: exp2(a(n)(c - 1)), a(n) = (n / ln 2) Re(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   sg-tuned vs pow: max abs error (relative to the peak) <= 0.144 over n in [1, 100000], whole domain
//   sg-tuned vs pow: max abs error (relative to the peak) <= 0.0162 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_sg_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// sg, sg-tuned, ue4-phong-approx: 2^(k (c - 1)), the spherical Gaussian. sg: k = n / ln 2;
/// ue4-phong-approx: k = 1.4427 (n + 0.775) (Karis 2013). Cost: 1 mul, 1 add, 1 exp2.
fn fb_lobe_exp2(c: f32, k: f32) -> f32 {
    return exp2(k * (fb_clamp01(c) - 1.0));
}

/// sg-tuned: exp2(a(n)(c - 1)), a(n) = (n / ln 2) Re(1/n)
/// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs). Instance: runtime parameters p_n; fixed: no parameters.
fn fb_sg_tuned(c: f32, p_n: f32) -> f32 {
    return fb_lobe_exp2(c, (p_n * 1.4426950408889634 * (0.9999997632926588 + (1.0 / p_n) * (0.6628449465824661 + (1.0 / p_n) * (0.2528529611159018 + (1.0 / p_n) * (0.11461734798153449 + (1.0 / p_n) * -0.08793796983764615))))));
}
