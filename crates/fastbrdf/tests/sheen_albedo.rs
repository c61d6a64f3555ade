//! The sheen rows of the DFG ledger (`microfacet::sheen_albedo`) against an independent
//! evaluation of the sheen lobe's directional albedo: the Charlie distribution and both
//! visibility terms written here from KHR_materials_sheen's implementation notes (Estevez and
//! Kulla 2017; Neubelt and Pettineo 2013), integrated over the hemisphere by nested adaptive
//! Gauss-Kronrod (7-15 points) in `(cos theta_i, phi)`, f64: another rule than the rows'
//! product Gauss-Legendre. On a grid over the whole domain (`mu` in [0.001, 1], `alpha` in
//! [0.07, 1]), denser where the rows' maxima are (grazing; small and large `alpha`):
//! `sheen-albedo` within its documented 1e-4, and every configuration within its documented
//! ledger bound (`sheen_albedo::LEDGER`), which the grid also reaches to within a factor 2
//! (the bound is not loose, and this test can fail).

use fastbrdf::microfacet::sheen_albedo::LEDGER;
use fastbrdf::{Model, ModelSpec};
use std::f64::consts::PI;

/// 7-15 Gauss-Kronrod nodes on [-1, 1] (the positive half and the centre) and weights.
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
    0.209_482_141_084_727_8,
];
/// Gauss weights of the odd Kronrod nodes (1, 3, 5, 7 above).
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// The integral of `f` over [a, b] to absolute tolerance `tol`, by recursive bisection.
fn gk(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, depth: u32) -> f64 {
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    let (mut k, mut g) = (WK[7] * f(c), WG[3] * f(c));
    for i in 0..7 {
        let s = f(c - h * XK[i]) + f(c + h * XK[i]);
        k += WK[i] * s;
        if i % 2 == 1 {
            g += WG[i / 2] * s;
        }
    }
    let (k, g) = (k * h, g * h);
    if (k - g).abs() <= tol || depth == 0 {
        k
    } else {
        gk(f, a, c, 0.5 * tol, depth - 1) + gk(f, c, b, 0.5 * tol, depth - 1)
    }
}

/// The sheen lobe's albedo `E(mu, alpha)` (sheen colour 1), from the published formulas.
fn albedo(mu: f64, alpha: f64, charlie: bool) -> f64 {
    // KHR_materials_sheen: l(x) with coefficients mixed by (1 - alpha)^2.
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |x: f64, y: f64| (1.0 - t) * x + t * y;
    let (a, b, c, d, e) = (
        mix(21.5473, 25.3245),
        mix(3.82987, 3.32435),
        mix(0.19823, 0.16801),
        mix(-1.97760, -1.27393),
        mix(-4.32054, -4.85967),
    );
    let l = |x: f64| a / (1.0 + b * x.powf(c)) + d * x + e;
    let lambda = |x: f64| {
        if x < 0.5 {
            l(x).exp()
        } else {
            (2.0 * l(0.5) - l(1.0 - x)).exp()
        }
    };
    let so = (1.0 - mu * mu).sqrt();
    // D V cos_i, with the 1 / (4 cos_o cos_i) of V cancelled against cos_i where it can be.
    let f = |ci: f64, phi: f64| {
        let si = (1.0 - ci * ci).max(0.0).sqrt();
        let h = [si * phi.cos() + so, si * phi.sin(), ci + mu];
        let sin2 = (h[0] * h[0] + h[1] * h[1]) / (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        let dist = (2.0 + 1.0 / alpha) * sin2.powf(0.5 / alpha) / (2.0 * PI);
        let v_cos = if charlie {
            1.0 / ((1.0 + lambda(mu) + lambda(ci)) * 4.0 * mu)
        } else {
            ci / (4.0 * (ci + mu - ci * mu))
        };
        dist * v_cos
    };
    // phi over [0, pi] doubled (the lobe is even in phi).
    let inner = |ci: f64| 2.0 * gk(&|phi| f(ci, phi), 0.0, PI, 1e-9, 30);
    gk(&inner, 0.0, 1.0, 1e-8, 30)
}

fn e(m: &Model<f64>, mu: f64, alpha: f64) -> f64 {
    match m {
        Model::Env(x) => x.e(mu, alpha),
        _ => panic!("not an env model"),
    }
}

const MUS: [f64; 17] = [
    0.001, 0.002, 0.004, 0.0055, 0.0076, 0.0103, 0.013, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85,
    0.95, 1.0,
];
const ALPHAS: [f64; 12] = [
    0.07, 0.082, 0.1, 0.16, 0.21, 0.3, 0.43, 0.6, 0.81, 0.84, 0.94, 1.0,
];

/// The independent albedo on the grid, per visibility: `[charlie, neubelt][alpha][mu]`.
fn grid() -> Vec<Vec<Vec<f64>>> {
    std::thread::scope(|s| {
        let h: Vec<_> = [true, false]
            .into_iter()
            .flat_map(|charlie| {
                ALPHAS.iter().map(move |&a| {
                    s.spawn(move || {
                        MUS.iter()
                            .map(|&m| albedo(m, a, charlie))
                            .collect::<Vec<_>>()
                    })
                })
            })
            .collect();
        let mut rows: Vec<Vec<f64>> = h.into_iter().map(|h| h.join().unwrap()).collect();
        let neubelt = rows.split_off(ALPHAS.len());
        vec![rows, neubelt]
    })
}

#[test]
fn sheen_rows_hold_their_bounds_against_an_independent_albedo() {
    let want = grid();
    // The independent rule itself: the grazing value of Neubelt's albedo at alpha = 0.07
    // exceeds 1 (the extension's warning), Charlie's stays below.
    assert!(
        want[1][0][0] > 1.5 && want[0][0][0] < 1.0,
        "{} {}",
        want[1][0][0],
        want[0][0][0]
    );
    let max_err = |spec: &ModelSpec, v: usize| -> (f64, f64, f64) {
        let m = spec.model::<f64>().unwrap();
        let mut worst = (0.0, 0.0, 0.0);
        for (i, &a) in ALPHAS.iter().enumerate() {
            for (j, &mu) in MUS.iter().enumerate() {
                let d = (e(&m, mu, a) - want[v][i][j]).abs();
                if d > worst.0 || d.is_nan() {
                    worst = (d, mu, a);
                }
            }
        }
        worst
    };
    for (k, v) in ["charlie", "neubelt"].into_iter().enumerate() {
        let s = ModelSpec::parse("sheen-albedo", &[("v", v)]).unwrap();
        let (err, mu, a) = max_err(&s, k);
        println!("sheen-albedo v={v}: {err:.3e} at ({mu}, {a})");
        assert!(
            err <= 1e-4,
            "sheen-albedo v={v}: {err} at mu {mu} alpha {a}"
        );
    }
    for &(id, given, v, bound) in LEDGER {
        let s = ModelSpec::parse(id, given).unwrap();
        let (err, mu, a) = max_err(&s, (v == "neubelt") as usize);
        println!("{id} {given:?} vs {v}: {err:.4} at ({mu}, {a}), bound {bound}");
        // The grid's error may exceed the ledger's by the reference's 1e-4.
        assert!(
            err <= bound + 1e-4,
            "{id} {given:?} vs {v}: {err} > {bound} at mu {mu} alpha {a}"
        );
        assert!(
            err > 0.5 * bound,
            "{id} {given:?} vs {v}: the bound {bound} is loose ({err})"
        );
    }
}
