// fastbrdf 0.1.0 (lobe): pow
// Made by: fastbrdf shader --model pow --lang wgsl
//
// Formula: c^n
// Source: Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 10000], default 20)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_pow(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// pow: c^n, the Phong/Blinn-Phong reference (Phong 1975). Cost: 1 pow (exp2 + log2).
fn fb_lobe_pow(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    return select(0.0, pow(x, n), x > 0.0);
}

/// pow: c^n
/// Source: Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003). Instance: n = 20.
fn fb_pow(c: f32) -> f32 {
    return fb_lobe_pow(c, 20.0f);
}
