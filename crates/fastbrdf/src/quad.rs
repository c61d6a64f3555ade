//! Adaptive Gauss-Kronrod (G7/K15) quadrature in f64, with caller-supplied breakpoints.
//!
//! Written by hand (see ARCHITECTURE.md): the integrands here are lobes with kinks and
//! zero crossings at known places (`Lobe::zero_below`, `Lobe::kinks`), so the integrator must
//! accept breakpoints and a relative tolerance near 1e-10; it is 60 lines.

const XK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728_8,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One G7/K15 panel: (Kronrod estimate, |Kronrod - Gauss|).
fn panel(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = WK[7] * fc;
    let mut g = WG[3] * fc;
    for i in 0..7 {
        let x = h * XK[i];
        let s = f(c - x) + f(c + x);
        k += WK[i] * s;
        if i % 2 == 1 {
            g += WG[i / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// `a`, the `breaks` strictly inside `(a, b)` in order, `b`: the pieces' ends.
fn pieces(a: f64, b: f64, breaks: &[f64]) -> Vec<f64> {
    let mut pts = vec![a];
    let mut inner: Vec<f64> = breaks
        .iter()
        .copied()
        .filter(|x| *x > a && *x < b)
        .collect();
    inner.sort_by(f64::total_cmp);
    pts.extend(inner);
    pts.push(b);
    pts
}

/// The integral of `f` over `[a, b]` to relative tolerance `rel_tol` (absolute floor 1e-300),
/// splitting first at `breaks` (points outside `(a, b)` are ignored).
/// Returns `(value, error estimate)`.
pub fn integrate(
    f: impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    breaks: &[f64],
    rel_tol: f64,
) -> (f64, f64) {
    let pts = pieces(a, b, breaks);
    // Start every interval with 8 panels so that narrow peaks are seen.
    let mut work: Vec<(f64, f64, f64, f64)> = Vec::new();
    for w in pts.windows(2) {
        let n = 8;
        for i in 0..n {
            let lo = w[0] + (w[1] - w[0]) * i as f64 / n as f64;
            let hi = w[0] + (w[1] - w[0]) * (i + 1) as f64 / n as f64;
            let (v, e) = panel(&f, lo, hi);
            work.push((lo, hi, v, e));
        }
    }
    for _ in 0..2000 {
        let total: f64 = work.iter().map(|w| w.2).sum();
        let err: f64 = work.iter().map(|w| w.3).sum();
        if err <= rel_tol * total.abs() || err < 1e-300 {
            return (total, err);
        }
        // Split the panel with the largest error.
        let (i, _) = work
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.3.total_cmp(&y.1.3))
            .unwrap();
        let (lo, hi, _, _) = work.swap_remove(i);
        let mid = 0.5 * (lo + hi);
        let (v1, e1) = panel(&f, lo, mid);
        let (v2, e2) = panel(&f, mid, hi);
        work.push((lo, mid, v1, e1));
        work.push((mid, hi, v2, e2));
    }
    (
        work.iter().map(|w| w.2).sum(),
        work.iter().map(|w| w.3).sum(),
    )
}

/// Directional albedo `integral over the hemisphere of f(wo) cos theta_o dwo` for a BRDF
/// slice `f` whose lobe peaks around the unit direction `peak` (the mirror direction of `wi`,
/// or the normal). Integrates over the whole sphere in polar coordinates centred on `peak`
/// (so a narrow lobe is a narrow band in the outer variable `u = cos angle(wo, peak)`), with
/// the integrand zero below the horizon; nested adaptive Gauss-Kronrod to `rel_tol`.
/// `u_breaks` are values of `u` where the integrand jumps or kinks (Gauss-Kronrod's error
/// estimate does not see a jump that falls between its nodes).
/// Returns `(albedo, error estimate)`.
pub fn albedo(
    f: impl Fn([f64; 3]) -> f64,
    peak: [f64; 3],
    u_breaks: &[f64],
    rel_tol: f64,
) -> (f64, f64) {
    let polar = Polar::new(peak);
    let ring = |u: f64| {
        let g = |phi: f64| polar.value(&f, u, phi);
        integrate(g, 0.0, TAU, &polar.horizon(u), rel_tol * 0.1).0
    };
    integrate(ring, -1.0, 1.0, &outer_breaks(u_breaks), rel_tol)
}

/// [`albedo`]'s integral (the same coordinates and breakpoints) by a fixed rule: Gauss-Legendre
/// 7 points on `outer_panels` panels per `u` interval and `inner_panels` per ring interval.
/// No error estimate and no guarantee: an interactive preview (the explorer's albedo estimate,
/// measured against [`albedo`] in its tests).
pub fn albedo_fixed(
    f: impl Fn([f64; 3]) -> f64,
    peak: [f64; 3],
    u_breaks: &[f64],
    outer_panels: usize,
    inner_panels: usize,
) -> f64 {
    let polar = Polar::new(peak);
    let ring = |u: f64| {
        let g = |phi: f64| polar.value(&f, u, phi);
        fixed(g, 0.0, TAU, &polar.horizon(u), inner_panels)
    };
    fixed(ring, -1.0, 1.0, &outer_breaks(u_breaks), outer_panels)
}

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// The outer variable's breakpoints: `1 - 10^-k` (k = 1..7, where narrow lobes live) and the
/// caller's.
fn outer_breaks(u_breaks: &[f64]) -> Vec<f64> {
    let mut breaks: Vec<f64> = (1..=7).map(|k| 1.0 - 10f64.powi(-k)).collect();
    breaks.extend_from_slice(u_breaks);
    breaks
}

/// Polar coordinates around `peak`: an orthonormal frame (t, b, peak). Public for the batched
/// quadrature of `fastbrdf conform` (the analysis crate), which integrates the same way.
pub struct Polar {
    p: [f64; 3],
    t: [f64; 3],
    b: [f64; 3],
}

impl Polar {
    pub fn new(p: [f64; 3]) -> Self {
        let t = if p[2].abs() < 0.9 {
            [p[1], -p[0], 0.0]
        } else {
            [0.0, p[2], -p[1]]
        };
        let tl = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        let t = [t[0] / tl, t[1] / tl, t[2] / tl];
        let b = [
            p[1] * t[2] - p[2] * t[1],
            p[2] * t[0] - p[0] * t[2],
            p[0] * t[1] - p[1] * t[0],
        ];
        Self { p, t, b }
    }

    /// The direction of the ring `u` (cosine to the peak) at angle `phi`.
    pub fn direction(&self, u: f64, phi: f64) -> [f64; 3] {
        let (p, t, b) = (self.p, self.t, self.b);
        let s = (1.0 - u * u).max(0.0).sqrt();
        let (sp, cp) = phi.sin_cos();
        std::array::from_fn(|i| s * (cp * t[i] + sp * b[i]) + u * p[i])
    }

    /// `f(w) cos theta_w` at the direction `w` of the ring `u` (cosine to the peak) at angle
    /// `phi`; 0 below the horizon.
    fn value(&self, f: &impl Fn([f64; 3]) -> f64, u: f64, phi: f64) -> f64 {
        let w = self.direction(u, phi);
        if w[2] > 0.0 { f(w) * w[2] } else { 0.0 }
    }

    /// The angles where the horizon cuts the ring `u`: s (cos phi t_z + sin phi b_z) + u p_z = 0.
    pub fn horizon(&self, u: f64) -> Vec<f64> {
        let s = (1.0 - u * u).max(0.0).sqrt();
        let mut breaks = vec![];
        let (a, bb, c) = (s * self.t[2], s * self.b[2], u * self.p[2]);
        let r = (a * a + bb * bb).sqrt();
        if r > 0.0 && (c / r).abs() < 1.0 {
            let base = bb.atan2(a);
            let d = (-c / r).acos();
            for x in [base + d, base - d] {
                breaks.push(x.rem_euclid(TAU));
            }
        }
        breaks
    }
}

/// Gauss-Legendre 7 points on [-1, 1]: (node, weight), the non-negative nodes.
const GL7: [(f64, f64); 4] = [
    (0.0, 0.417_959_183_673_469_4),
    (0.405_845_151_377_397_2, 0.381_830_050_505_118_9),
    (0.741_531_185_599_394_4, 0.279_705_391_489_276_7),
    (0.949_107_912_342_758_5, 0.129_484_966_168_869_7),
];

/// `f` over `[a, b]` split at `breaks`, `panels` Gauss-Legendre 7 panels per piece.
fn fixed(f: impl Fn(f64) -> f64, a: f64, b: f64, breaks: &[f64], panels: usize) -> f64 {
    let pts = pieces(a, b, breaks);
    let mut sum = 0.0;
    for w in pts.windows(2) {
        for i in 0..panels {
            let lo = w[0] + (w[1] - w[0]) * i as f64 / panels as f64;
            let hi = w[0] + (w[1] - w[0]) * (i + 1) as f64 / panels as f64;
            let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            let mut s = GL7[0].1 * f(c);
            for &(x, wt) in &GL7[1..] {
                s += wt * (f(c - h * x) + f(c + h * x));
            }
            sum += s * h;
        }
    }
    sum
}
