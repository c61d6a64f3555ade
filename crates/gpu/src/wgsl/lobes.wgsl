// fastbrdf WGSL library: specular lobes f(c), c = cos of the angle to the lobe's axis (n.h for
// Blinn-Phong, r.v for Phong). Argument clamped to [0, 1]. Twins: crates/fastbrdf/src/lobes/*
// (formulas, sources, error bounds in their headers) and batch/ops.rs (this arrangement).
// Precision on the GPU: shader compilers reassociate. Mesa's NIR (lavapipe) recognises
// `1 + t (c - 1)` as the lerp a + t (b - a) and lowers it to (1 - t) + t c, which cancels when
// t ~ n (the power lobes and the cubics' Newton form erred by about n ulp of c absolute, 4.8e-4
// at n = 10000 on lavapipe; fma() does not stop it), and with literal coefficients it folds
// `(y + #a) * #k` into `y #k + #(a k)` and sums of literals (seed 003's rational: 2.6e-4 at
// c = 1). So the lobes here are written in y = 1 - c (exact for c >= 0.5): no lerp shape, the
// constant term exactly 1 or exactly the peak, every other term a multiple of y, so that at
// c = 1 any such folding still gives the peak (tests/fold.rs models the folding, tests/exact.rs
// runs lavapipe). The CPU twins keep the seed's arrangements; tests/parity.rs compares them.
// Coefficients that need care (cubic shapes, rational nodes, tuned slopes, normalisation) are
// computed once on the CPU in f64 and passed in, as the CPU kernels do.

/// pow: c^n, the Phong/Blinn-Phong reference (Phong 1975), as fb_powr (exp2 of n fb_log2(c),
/// not WGSL's pow, whose log2 near 1 cost about 2n ulp: 6.4e-4 at n = 10000 on lavapipe, and
/// issue 11 reported the same on real GPUs). Cost: 1 exp2, 1 log2 (fb_log2's branch below
/// 0.5, evaluated by the select), 1 div, 10 mul, 8 add.
fn fb_lobe_pow(c: f32, n: f32) -> f32 {
    return fb_powr(fb_clamp01(c), n);
}

/// schlick: c / (n - n c + c) (Schlick 1994). Cost: 1 mul, 2 add, 1 div.
fn fb_lobe_schlick(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    return x / (n * (1.0 - x) + x);
}

/// schlick-modified: 2 c / (1.25 (n - n c + 1.25 c)^2), as printed in seed 003 (peak 1.024).
fn fb_lobe_schlick_modified(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    let d = n * (1.0 - x) + 1.25 * x;
    return 2.0 * x / (1.25 * (d * d));
}

/// gauss: exp(-(n/2) acos(c)^2), the Gaussian lobe. half_n = n / 2.
fn fb_lobe_gauss(c: f32, half_n: f32) -> f32 {
    let t = fb_acos(fb_clamp01(c));
    return exp(-half_n * (t * t));
}

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

/// rational (seed 003): level c / (n (xq - x) + c), x = c - 1, xq = level^(1/n) - 1, written
/// fold-proof as peak c / (1 + g y) with y = 1 - c (exact for c >= 0.5), d0 = 1 + n xq,
/// peak = level / d0 and g = (n - 1) / d0 (computed in f64, xq with expm1); level = 0.5 for
/// `rational`. The constant term is exactly 1 and the only other term multiplies y: a compiler
/// that expands g (1 - c) into g - g c and folds 1 + g (Mesa does, with literals) still gets
/// exactly 1 at c = 1 ((1 + g) - g is exact for g >= 1), where the seed's arrangement folded
/// into n xq + n, a constant of size n with a fraction: 3.4e-4 off at c = 1, n = 5000 (issue 11).
/// Cost: 2 mul, 2 add, 1 div.
fn fb_lobe_rational(c: f32, peak: f32, g: f32) -> f32 {
    let cc = fb_clamp01(c);
    let y = 1.0 - cc;
    return peak * cc / (1.0 + g * y);
}

/// cubic-rational (seed 003): the cubic above q = level^(1/n), the rational below.
fn fb_lobe_cubic_rational(c: f32, d1: f32, d2: f32, d3: f32, x1: f32, x2: f32, cut: f32,
                          peak: f32, g: f32, q: f32) -> f32 {
    let cc = fb_clamp01(c);
    let a = fb_lobe_cubic(cc, d1, d2, d3, x1, x2, cut);
    let b = fb_lobe_rational(cc, peak, g);
    return select(b, a, cc >= q);
}

/// power4/8/16 (seed 000's (1 + x/g)^g): max(1 + s (c - 1), 0)^g with s = n / g (tuned: s
/// from a minimax fit, fastbrdf::lobes::tuned), written 1 - s (1 - c): not the lerp shape
/// `1 + t (c - 1)` (see the header), and exactly 1 at c = 1. Cost: 1 mul, 2 add, log2(g) mul.
fn fb_lobe_power4(c: f32, s: f32) -> f32 {
    return fb_pow4(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

fn fb_lobe_power8(c: f32, s: f32) -> f32 {
    return fb_pow8(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

fn fb_lobe_power16(c: f32, s: f32) -> f32 {
    return fb_pow16(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

/// sg, sg-tuned, ue4-phong-approx: 2^(k (c - 1)), the spherical Gaussian. sg: k = n / ln 2;
/// ue4-phong-approx: k = 1.4427 (n + 0.775) (Karis 2013). Cost: 1 mul, 1 add, 1 exp2.
fn fb_lobe_exp2(c: f32, k: f32) -> f32 {
    return exp2(k * (fb_clamp01(c) - 1.0));
}
