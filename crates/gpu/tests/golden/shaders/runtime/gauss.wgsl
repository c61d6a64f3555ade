// fastbrdf 0.1.0 (lobe): gauss
// Made by: fastbrdf shader --model gauss --lang wgsl --runtime-params
//
// Formula: exp(-n theta^2 / 2), theta = acos(c)
// Source: seed 001 (Gauss BRDF, its reference [10])
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   gauss vs pow: max abs error (relative to the peak) <= 0.292 over n in [1, 100000], whole domain
//   gauss vs pow: max rel error <= 0.156 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_gauss(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// acos(x) for x in [0, 1], absolute error 3e-7: Abramowitz & Stegun 4.4.46, the same
/// polynomial as the CPU kernels (twin: batch::math::acos). WGSL's built-in acos may err by
/// much more (the spec allows an absolute 6.77e-5).
fn fb_acos(x: f32) -> f32 {
    let p = 1.5707963 + x * (-0.2145988 + x * (0.08897899 + x * (-0.050174303 + x * (0.03089188
        + x * (-0.017088126 + x * (0.00667009 + x * -0.0012624911))))));
    return sqrt(max(1.0 - x, 0.0)) * p;
}

/// gauss: exp(-(n/2) acos(c)^2), the Gaussian lobe. half_n = n / 2.
fn fb_lobe_gauss(c: f32, half_n: f32) -> f32 {
    let t = fb_acos(fb_clamp01(c));
    return exp(-half_n * (t * t));
}

/// gauss: exp(-n theta^2 / 2), theta = acos(c)
/// Source: seed 001 (Gauss BRDF, its reference [10]). Instance: runtime parameters p_n; fixed: no parameters.
fn fb_gauss(c: f32, p_n: f32) -> f32 {
    return fb_lobe_gauss(c, (0.5 * p_n));
}
