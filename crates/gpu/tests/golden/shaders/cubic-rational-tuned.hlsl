// fastbrdf 0.1.0 (lobe): cubic-rational-tuned
// Made by: fastbrdf shader --model cubic-rational-tuned --lang hlsl
//
// Formula: seed 003's cubic above c^n = Q(n), its rational below, Q(n) = Rq(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 10000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.283 over n in [1, 1000], whole domain
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.0414 over n in [8, 1000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_cubic_rational_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_cubic(float c_1, float d1_, float d2_, float d3_, float x1_, float x2_, float cut)
{
    const float _e7 = fb_clamp01_(c_1);
    float x = (_e7 - 1.0);
    float p = (1.0 + (x * (d1_ + ((x - x1_) * (d2_ + ((x - x2_) * d3_))))));
    return ((_e7 < cut) ? 0.0 : max(p, 0.0));
}

float fb_lobe_rational(float c_2, float n, float xq, float level)
{
    const float _e4 = fb_clamp01_(c_2);
    float x_1 = (_e4 - 1.0);
    return ((level * _e4) / ((n * (xq - x_1)) + _e4));
}

float fb_lobe_cubic_rational(float c_3, float d1_1, float d2_1, float d3_1, float x1_1, float x2_1, float cut_1, float n_1, float xq_1, float level_1, float q)
{
    const float _e11 = fb_clamp01_(c_3);
    const float _e12 = fb_lobe_cubic(_e11, d1_1, d2_1, d3_1, x1_1, x2_1, cut_1);
    const float _e13 = fb_lobe_rational(_e11, n_1, xq_1, level_1);
    return ((_e11 >= q) ? _e12 : _e13);
}

float fb_cubic_rational_tuned(float c_4)
{
    const float _e11 = fb_lobe_cubic_rational(c_4, 10.0814085, 74.83417, 70.66397, -0.08079728, -0.08079728, 0.8885781, 20.0, -0.08079728, 0.18544966, 0.91920274);
    return _e11;
}
