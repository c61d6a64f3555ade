// fastbrdf 0.1.0 (lobe): sg
// Made by: fastbrdf shader --model sg --lang hlsl
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

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_exp2_(float c_1, float k)
{
    const float _e2 = fb_clamp01_(c_1);
    return exp2((k * (_e2 - 1.0)));
}

float fb_sg(float c_2)
{
    const float _e2 = fb_lobe_exp2_(c_2, 28.8539);
    return _e2;
}
