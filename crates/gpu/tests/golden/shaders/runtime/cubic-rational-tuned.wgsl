// fastbrdf 0.1.0 (lobe): cubic-rational-tuned
// Made by: fastbrdf shader --model cubic-rational-tuned --lang wgsl --runtime-params
//
// Formula: seed 003's cubic above c^n = Q(n), its rational below, Q(n) = Rq(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.283 over n in [1, 100000], whole domain
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.0415 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_cubic_rational_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// log2(x) with a small relative error for x in [0.5, 1] too, where WGSL's built-in log2 is
/// only held to 2^-21 absolute (relative error unbounded as x -> 1): 2 atanh(t) / ln 2 with
/// t = (x - 1) / (x + 1) in [-1/3, 0], x - 1 exact (Sterbenz), series to t^13 (truncation
/// 5e-9 relative). Below 0.5 the built-in. The CPU kernels' log2 is 0.5 ulp (an f64 series).
fn fb_log2(x: f32) -> f32 {
    let t = (x - 1.0) / (x + 1.0);
    let t2 = t * t;
    let s = t * (2.0 + t2 * (0.6666667 + t2 * (0.4 + t2 * (0.2857143 + t2 * (0.22222222
        + t2 * (0.18181818 + t2 * 0.15384615))))));
    return select(log2(x), s * 1.442695, x >= 0.5);
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

/// ln 2.
const FB_RT_LN2: f32 = 0.6931471805599453;

/// exp(x) - 1 without the cancellation of exp(x) - 1 near 0: Taylor to x^9 for |x| < 0.5
/// (truncation below 6e-10 relative), exp(x) - 1 beyond (|result| > 0.39: no cancellation).
fn fb_rt_expm1(x: f32) -> f32 {
    let s = x * (1.0 + x * (0.5 + x * (0.16666667 + x * (0.041666668 + x * (0.008333334
        + x * (0.0013888889 + x * (0.0001984127 + x * (0.000024801587
        + x * 0.0000027557319))))))));
    return select(exp(x) - 1.0, s, abs(x) < 0.5);
}

/// ln(x) for finite x > 0 with a small relative error: x = 2^e f with f in [sqrt(1/2), sqrt(2)),
/// ln x = (e + fb_log2(f)) ln 2 (fb_log2's series there). Exactly 0 at x = 1.
fn fb_rt_ln(x: f32) -> f32 {
    // frexp by the bits (x positive and normal here): GLSL before 4.00 has no frexp, and
    // BRDF Explorer's shaders are GLSL 3.30.
    let bits = bitcast<u32>(x);
    let fract = bitcast<f32>((bits & 0x007fffffu) | 0x3f000000u);
    let exp = i32((bits >> 23u) & 0xffu) - 126;
    let low = fract < 0.70710677;
    let f = select(fract, 2.0 * fract, low);
    let e = f32(exp) - select(0.0, 1.0, low);
    return e * FB_RT_LN2 + fb_log2(f) * FB_RT_LN2;
}

/// A clipped cubic in Newton form in x = c - 1 (twin: fastbrdf::lobes::cubic::CubicShape),
/// with its cut as x: the local minimum in (-1, x1), or -1 (c = 0) when there is none.
struct FbRtCubic {
    d1: f32,
    d2: f32,
    d3: f32,
    x1: f32,
    x2: f32,
    xcut: f32,
}

/// The cut of the cubic (twin: CubicShape::finish): critical points of
/// 1 + al x + be x^2 + ga x^3, the local minimum in (-1, x1) kept; the stable quadratic formula.
fn fb_rt_cubic_finish(d1: f32, d2: f32, d3: f32, x1: f32, x2: f32) -> FbRtCubic {
    let al = d1 - d2 * x1 + d3 * x1 * x2;
    let be = d2 - d3 * (x1 + x2);
    let a = 3.0 * d3;
    let b = 2.0 * be;
    let disc = b * b - 4.0 * a * al;
    let q = -0.5 * (b + select(-1.0, 1.0, b >= 0.0) * sqrt(max(disc, 0.0)));
    let lin = a == 0.0;
    let r1 = select(q / select(a, 1.0, lin), -al / select(b, 1.0, b == 0.0), lin);
    let r2 = al / select(q, 1.0, q == 0.0);
    let ok1 = select(disc >= 0.0, b != 0.0, lin) && r1 > -1.0 && r1 < x1
        && b + 2.0 * a * r1 > 0.0;
    let ok2 = disc >= 0.0 && !lin && q != 0.0 && r2 > -1.0 && r2 < x1 && b + 2.0 * a * r2 > 0.0;
    let xcut = max(select(-1.0, r1, ok1), select(-1.0, r2, ok2));
    return FbRtCubic(d1, d2, d3, x1, x2, xcut);
}

/// Seed 003's Hermite cubic matched to c^n at level = q^n, xq = q - 1 (twin:
/// CubicShape::hermite_at): value level and slope n level / q at q, through (0, 0) and (1, 1).
fn fb_rt_hermite(n: f32, level: f32, xq: f32) -> FbRtCubic {
    let q = 1.0 + xq;
    let s = n * level / q;
    let f0q = (level - 1.0) / xq;
    let fqm = level / q;
    let f0qq = (s - f0q) / xq;
    let fqqm = (s - fqm) / q;
    return fb_rt_cubic_finish(f0q, f0qq, f0qq - fqqm, xq, xq);
}

/// (peak, g) of seed 003's rational at level = q^n, xq = q - 1 (see fb_lobe_rational):
/// d0 = 1 + n xq, peak = level / d0, g = (n - 1) / d0.
fn fb_rt_rational_coefs(n: f32, level: f32, xq: f32) -> vec2<f32> {
    let d0 = 1.0 + n * xq;
    return vec2<f32>(level / d0, (n - 1.0) / d0);
}

/// cubic-rational at a junction level (ln_level = ln(level)): the Hermite cubic above
/// q = level^(1/n), the rational below.
fn fb_rt_cubic_rational_at(c: f32, n: f32, level: f32, ln_level: f32) -> f32 {
    let xq = fb_rt_expm1(ln_level / n);
    let s = fb_rt_hermite(n, level, xq);
    let r = fb_rt_rational_coefs(n, level, xq);
    return fb_lobe_cubic_rational(c, s.d1, s.d2, s.d3, s.x1, s.x2, 1.0 + s.xcut, r.x, r.y,
                                  1.0 + xq);
}

/// The tuned junction level Q(n) = Rq(1/n) clamped to [0.02, 0.9] (twin:
/// fastbrdf::lobes::tuned::cubic_rational_level; constants R_CUBIC_RATIONAL).
fn fb_rt_cubic_rational_level(n: f32) -> f32 {
    let x = 1.0 / n;
    let r = 0.20378580359378357 + x * (-0.3540617692504455 + x * (-0.17166191841691497
        + x * (-1.7353248381655744 + x * 2.0826525969384635)));
    return clamp(r, 0.02, 0.9);
}

/// cubic-rational-tuned with a runtime n: junction at c^n = Q(n).
fn fb_rt_cubic_rational_tuned(c: f32, n: f32) -> f32 {
    let level = fb_rt_cubic_rational_level(n);
    return fb_rt_cubic_rational_at(c, n, level, fb_rt_ln(level));
}

/// cubic-rational-tuned: seed 003's cubic above c^n = Q(n), its rational below, Q(n) = Rq(1/n)
/// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs). Instance: runtime parameters p_n; fixed: no parameters.
fn fb_cubic_rational_tuned(c: f32, p_n: f32) -> f32 {
    return fb_rt_cubic_rational_tuned(c, p_n);
}
