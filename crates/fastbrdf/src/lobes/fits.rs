//! The minimax fits of the tuned lobes (`tuned.rs`: `power4/8/16-tuned`, `sg-tuned`,
//! `cubic-rational-tuned`): each family's `R(x)`, the coefficients derived from it, and the f64
//! cubic-rational used to fit them. `power`, `sg` and `rational` read their tuned coefficients
//! here and `tuned.rs` builds their plans, so `tuned` and those families do not import each
//! other (this file imports only `cubic`'s shape). `tuned` re-exports everything here
//! (`fastbrdf::lobes::tuned::power_slope` is this `power_slope`).

use super::cubic::CubicShape;

/// The generalised cubic-rational lobe at exponent `n`, junction level `level`, cosine `c`, in
/// f64 (for fitting; the models evaluate the same formula in `Real`).
pub fn cubic_rational_at(n: f64, level: f64, c: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    let xq = (level.ln() / n).exp_m1();
    let q = 1.0 + xq;
    if c >= q {
        CubicShape::hermite_at(n, level).raw(c).max(0.0)
    } else {
        let x = c - 1.0;
        level * c / (n * (xq - x) + c)
    }
}

/// `R(x)` of each family (see `tuned.rs`'s header).
pub const R_POWER4: [f64; 5] = [
    0.845_335_433_279_367_6,
    0.559_867_309_187_095_9,
    0.214_570_070_822_415_1,
    0.096_051_206_771_556_17,
    -0.054_783_826_505_451_584,
];
pub const R_POWER8: [f64; 5] = [
    0.919_956_178_174_037_4,
    0.609_703_839_919_813_8,
    0.233_146_132_280_650_26,
    0.105_353_502_679_207_22,
    -0.071_127_741_827_098_58,
];
pub const R_POWER16: [f64; 5] = [
    0.959_284_230_404_340_6,
    0.635_838_170_125_023_2,
    0.242_845_317_123_844_88,
    0.109_981_774_898_766_16,
    -0.079_461_413_863_993_32,
];
pub const R_EXP2: [f64; 5] = [
    0.999_999_763_292_658_8,
    0.662_844_946_582_466_1,
    0.252_852_961_115_901_8,
    0.114_617_347_981_534_49,
    -0.087_937_969_837_646_15,
];
pub const R_CUBIC_RATIONAL: [f64; 5] = [
    0.203_785_803_593_783_57,
    -0.354_061_769_250_445_5,
    -0.171_661_918_416_914_97,
    -1.735_324_838_165_574_4,
    2.082_652_596_938_463_5,
];

/// `R(1/n)`.
pub fn poly(r: &[f64; 5], n: f64) -> f64 {
    let x = 1.0 / n;
    r[0] + x * (r[1] + x * (r[2] + x * (r[3] + x * r[4])))
}

/// The tuned slope of `max(0, 1 + s (c - 1))^g` at exponent `n` (`g` = 4, 8 or 16).
pub fn power_slope(g: u32, n: f64) -> f64 {
    if n == f64::from(g) {
        1.0
    } else {
        n / f64::from(g) * poly(power_poly(g), n)
    }
}

/// The tuned rate of `exp2(a (c - 1))` at exponent `n`.
pub fn exp2_rate(n: f64) -> f64 {
    n / std::f64::consts::LN_2 * poly(&R_EXP2, n)
}

/// The tuned junction level of the cubic-rational lobe at exponent `n`, kept in (0.02, 0.9).
pub fn cubic_rational_level(n: f64) -> f64 {
    poly(&R_CUBIC_RATIONAL, n).clamp(0.02, 0.9)
}
pub fn power_poly(g: u32) -> &'static [f64; 5] {
    match g {
        4 => &R_POWER4,
        8 => &R_POWER8,
        _ => &R_POWER16,
    }
}

/// `R(1/n)` of a tuned family as a WGSL expression of `p_n` (Horner, like [`poly`]).
pub fn poly_expr(r: &[f64; 5]) -> String {
    let x = "(1.0 / p_n)";
    format!(
        "{} + {x} * ({} + {x} * ({} + {x} * ({} + {x} * {})))",
        r[0], r[1], r[2], r[3], r[4]
    )
}
