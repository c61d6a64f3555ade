// fastbrdf 0.1.0 (lobe): cubic
// Made by: fastbrdf shader --model cubic --lang wgsl
//
// Formula: a c^3 + b c^2 + (1 - a - b) c, Hermite fit of c^n at q = 0.5^(1/n); 0 below its local minimum and where negative
// Source: seed 003 (Romanyuk, Chan et al., cubic approximation of Phong)
// Note: q = 0.5^(1/n) exactly (the seed rounds ln 2); for f32 accuracy, evaluated on the CPU by Horner in (c - 1) with coefficients from the Newton form, on the GPU in the Newton form in 1 - c (fold-proof)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic vs pow: max abs error (relative to the peak) <= 0.00552 over n in [4, 1000], epicentre (reference >= half its peak)
//   cubic vs pow: max abs error (relative to the peak) <= 0.00555 over n in [4, 100000], epicentre (reference >= half its peak)
//   cubic vs pow: max abs error (relative to the peak) <= 0.228 over n in [4, 1000], whole domain
//   cubic vs pow: max abs error (relative to the peak) <= 0.23 over n in [4, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_cubic(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// cubic and cubic3 (seed 003): the clipped cubic in Newton form in x = c - 1,
/// p = 1 + x (d1 + (x - x1)(d2 + (x - x2) d3)), 0 below `cut` (its local minimum) and where
/// negative. Coefficients: fastbrdf::lobes::cubic::CubicShape (f64). Cost: 3 mul, 4 add.
fn fb_lobe_cubic(c: f32, d1: f32, d2: f32, d3: f32, x1: f32, x2: f32, cut: f32) -> f32 {
    let cc = fb_clamp01(c);
    // In y = 1 - c = -x: p = 1 - y (d1 - (y + x1)(d2 - (y + x2) d3)). No `1 + t (c - 1)`
    // shape for a compiler to take for a lerp (Mesa lowers those to (1 - t) + t c, which
    // cancels when t ~ n), and exactly 1 at c = 1 whatever it reassociates.
    let y = 1.0 - cc;
    let p = 1.0 - y * (d1 - (y + x1) * (d2 - (y + x2) * d3));
    return select(max(p, 0.0), 0.0, cc < cut);
}

/// cubic: a c^3 + b c^2 + (1 - a - b) c, Hermite fit of c^n at q = 0.5^(1/n); 0 below its local minimum and where negative
/// Source: seed 003 (Romanyuk, Chan et al., cubic approximation of Phong). Instance: n = 20.
fn fb_cubic(c: f32) -> f32 {
    return fb_lobe_cubic(c, 14.678394f, 126.98999f, 116.80814f, -0.03406367f, -0.03406367f, 0.92097706f);
}
