// fastbrdf 0.1.0 (lobe): cubic
// Made by: fastbrdf shader --model cubic --lang wgsl --runtime-params
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
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_cubic(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

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

/// ln 0.5, the level of cubic, rational and cubic-rational (seed 003).
const FB_RT_LN_HALF: f32 = -0.6931471805599453;

/// exp(x) - 1 without the cancellation of exp(x) - 1 near 0: Taylor to x^9 for |x| < 0.5
/// (truncation below 6e-10 relative), exp(x) - 1 beyond (|result| > 0.39: no cancellation).
fn fb_rt_expm1(x: f32) -> f32 {
    let s = x * (1.0 + x * (0.5 + x * (0.16666667 + x * (0.041666668 + x * (0.008333334
        + x * (0.0013888889 + x * (0.0001984127 + x * (0.000024801587
        + x * 0.0000027557319))))))));
    return select(exp(x) - 1.0, s, abs(x) < 0.5);
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

/// cubic (seed 003) with a runtime n in [1, 100000]: the Hermite cubic at level 0.5, its
/// coefficients and cut computed here in f32 (twin: fastbrdf::lobes::cubic, `cubic`).
fn fb_rt_cubic(c: f32, n: f32) -> f32 {
    let s = fb_rt_hermite(n, 0.5, fb_rt_expm1(FB_RT_LN_HALF / n));
    return fb_lobe_cubic(c, s.d1, s.d2, s.d3, s.x1, s.x2, 1.0 + s.xcut);
}

/// cubic: a c^3 + b c^2 + (1 - a - b) c, Hermite fit of c^n at q = 0.5^(1/n); 0 below its local minimum and where negative
/// Source: seed 003 (Romanyuk, Chan et al., cubic approximation of Phong). Instance: runtime parameters p_n; fixed: no parameters.
fn fb_cubic(c: f32, p_n: f32) -> f32 {
    return fb_rt_cubic(c, p_n);
}
