// fastbrdf 0.1.0 (lobe): schlick
// Made by: fastbrdf shader --model schlick --lang wgsl
//
// Formula: c / (n - n c + c)
// Source: Schlick 1994, 'A fast alternative to Phong's specular model'; seeds 001, 003
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   schlick vs pow: max abs error (relative to the peak) <= 0.204 over n in [1, 1000], whole domain
//   schlick vs pow: max abs error (relative to the peak) <= 0.204 over n in [1, 100000], whole domain
//   schlick vs pow: max rel error <= 0.182 over n in [1, 1000], epicentre (reference >= half its peak)
//   schlick vs pow: max rel error <= 0.182 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_schlick(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// schlick: c / (n - n c + c) (Schlick 1994). Cost: 1 mul, 2 add, 1 div.
fn fb_lobe_schlick(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    return x / (n * (1.0 - x) + x);
}

/// schlick: c / (n - n c + c)
/// Source: Schlick 1994, 'A fast alternative to Phong's specular model'; seeds 001, 003. Instance: n = 20.
fn fb_schlick(c: f32) -> f32 {
    return fb_lobe_schlick(c, 20.0f);
}
