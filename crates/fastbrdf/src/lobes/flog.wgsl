// WGSL twin of lobes/flog.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// flog family (seed 001): coef * (1 - log2(1 - n log2 c) / 2), clipped at 0, and at 1 when
/// clamp_to_one (the seed's GLSL). flog: coef = 1; flog-normalized: coef = 0.197 (n + 1.24) +
/// 0.068 / (0.64 + n). The inner log2 is fb_log2: near c = 1 the lobe's slope is ~n / ln 2
/// per unit of log2 c, so the built-in's absolute error would cost 9% at n = 10000.
fn fb_lobe_flog(c: f32, n: f32, coef: f32, clamp_to_one: bool) -> f32 {
    let x = fb_clamp01(c);
    let f = 1.0 - 0.5 * log2(1.0 - n * fb_log2(max(x, 1e-30)));
    var v = max(coef * f, 0.0);
    if clamp_to_one {
        v = min(v, 1.0);
    }
    return select(0.0, v, x > 0.0);
}
