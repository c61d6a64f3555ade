// fastbrdf 0.1.0 (lobe): power4
// Made by: fastbrdf shader --model power4 --lang msl --runtime-params
//
// Formula: max(0, 1 + (n/4)(c - 1))^4
// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power4 vs pow: max abs error (relative to the peak) <= 0.317 over n in [1, 100000], whole domain
//   power4 vs pow: max rel error <= 0.173 over n in [1, 100000], epicentre (reference >= half its peak)
//   power4 vs pow: max abs error (relative to the peak) <= 0.0738 over n in [16, 100000], whole domain
//   power4 vs pow: max rel error <= 0.0658 over n in [16, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 3e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_power4_(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_pow4_(
    float x
) {
    float x2_ = x * x;
    return x2_ * x2_;
}

float fb_lobe_power4_(
    float c_1,
    float s
) {
    float _e2 = fb_clamp01_(c_1);
    float _e10 = fb_pow4_(metal::max(1.0 - (s * (1.0 - _e2)), 0.0));
    return _e10;
}

float fb_power4_(
    float c_2,
    float p_n
) {
    float _e4 = fb_lobe_power4_(c_2, p_n / 4.0);
    return _e4;
}
