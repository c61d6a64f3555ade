//! `power4`, `power8`, `power16`: `max(0, 1 + (n/g)(c - 1))^g` with `g = 2^k`, evaluated by
//! `k` squarings (Lyon 1993; seed 000's "(1 + x/16)^16" form of `exp`).
//!
//! Since `c^n = exp(n ln c) ~ exp(n (c - 1))` near the peak and `(1 + x/g)^g -> exp(x)`, these
//! match `c^n` in value and slope at `c = 1`; they are exact when `n = g` (the base is then `c`)
//! and zero below `c = 1 - g/n`.
//! Parameters: `n` in [1, 100000] (default 20). Cost: 1 mul, 1 add (constants precomputed) and
//! `k` squarings (k = 2, 3, 4). Error bounds against `pow`: see the `INFO` constants.
//! Sampling (`lobe`): the closed-form CDF of `(1 + s (c - 1))^g` (`sample::CosDist::PowerG`), tuned forms too.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K as Coef, Real, pos, pow2k};
use crate::wgsl::Emit;

macro_rules! power_info {
    ($id:literal, $k:literal, $formula:literal, $abs:expr, $rel:expr, $abs16:expr, $rel16:expr, $f32:expr) => {
        ModelInfo {
            id: $id,
            kind: Kind::Lobe,
            params: &[params::N],
            formula: $formula,
            source: "Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000",
            ops: Ops::new(1 + $k, 1, 0, 0, 0),
            bounds: &[
                ErrorBound { reference: "pow", metric: Metric::MaxAbs, zone: Zone::All, param: ("n", 1.0, 100000.0), bound: $abs },
                ErrorBound { reference: "pow", metric: Metric::MaxRel, zone: Zone::Epicentre, param: ("n", 1.0, 100000.0), bound: $rel },
                ErrorBound { reference: "pow", metric: Metric::MaxAbs, zone: Zone::All, param: ("n", 16.0, 100000.0), bound: $abs16 },
                ErrorBound { reference: "pow", metric: Metric::MaxRel, zone: Zone::Epicentre, param: ("n", 16.0, 100000.0), bound: $rel16 },
            ],
            f32_bound: $f32,
            note: "",
        }
    };
}

pub const INFO4: ModelInfo = power_info!(
    "power4",
    2,
    "max(0, 1 + (n/4)(c - 1))^4",
    0.317,
    0.173,
    0.0738,
    0.0658,
    3e-7
);
pub const INFO8: ModelInfo = power_info!(
    "power8",
    3,
    "max(0, 1 + (n/8)(c - 1))^8",
    0.344,
    0.194,
    0.0354,
    0.0314,
    5e-7
);
pub const INFO16: ModelInfo = power_info!(
    "power16",
    4,
    "max(0, 1 + (n/16)(c - 1))^16",
    0.357,
    0.204,
    0.0173,
    0.0154,
    1e-6
);

pub const ENTRY4: Entry = Entry::new(INFO4, |p, _| {
    Ok(Plan::Lobe(Power::<2>::new(p.num("n"))?.into()))
});
pub const ENTRY8: Entry = Entry::new(INFO8, |p, _| {
    Ok(Plan::Lobe(Power::<3>::new(p.num("n"))?.into()))
});
pub const ENTRY16: Entry = Entry::new(INFO16, |p, _| {
    Ok(Plan::Lobe(Power::<4>::new(p.num("n"))?.into()))
});

/// `max(0, 1 + s (c - 1))^(2^K)`.
#[derive(Clone, Copy, Debug)]
pub struct Power<const K: u32> {
    s: Coef,
    /// `s` from the minimax fit of `lobes::tuned` rather than `n / 2^K`.
    tuned: bool,
    /// The least base whose `2^K`-th power (by squarings in f32) is a normal number
    /// ([`base_min`]).
    tmin: f32,
    /// `tmin^(2^K)` by the same squarings (about 2^-126).
    tmin_pow: f32,
}

/// The least f32 `t` whose `2^k`-th power by `k` squarings is at least 2^-126 (the smallest
/// normal f32): smaller bases make subnormal numbers on the way (see `Power::batch`).
pub fn base_min(k: u32) -> f32 {
    // Neighbouring positive floats by their bits (`next_up` needs Rust 1.86; MSRV 1.85).
    let step = |t: f32, d: i32| f32::from_bits(t.to_bits().wrapping_add_signed(d));
    let mut t = 2f64.powf(-126.0 / f64::from(1u32 << k)) as f32;
    while pow2k(t, k) < f32::MIN_POSITIVE {
        t = step(t, 1);
    }
    while pow2k(step(t, -1), k) >= f32::MIN_POSITIVE {
        t = step(t, -1);
    }
    t
}

impl<const K: u32> Power<K> {
    /// `g = 2^K`.
    pub const G: u32 = 1 << K;

    /// The lobe with `s = n / 2^K`; `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        let n = params::check("power", &params::N, n)?;
        Ok(Self::with_slope(n / f64::from(Self::G), false))
    }

    /// The tuned lobe at exponent `n` (slope `tuned::power_slope`).
    pub fn tuned(n: f64) -> Result<Self> {
        let n = params::check("power-tuned", &params::N, n)?;
        Ok(Self::with_slope(super::fits::power_slope(Self::G, n), true))
    }

    fn with_slope(s: f64, tuned: bool) -> Self {
        let tmin = base_min(K);
        Self {
            s: Coef::new(s),
            tuned,
            tmin,
            tmin_pow: pow2k(tmin, K),
        }
    }
}

impl<const K: u32> LobeForm for Power<K> {
    // NaN: `pos` (power, cubic) or the `c > 0` select (flog) gives 0.
    const NAN_TO_ZERO: bool = true;
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("power.wgsl");
    fn id(&self) -> &'static str {
        match (K, self.tuned) {
            (2, false) => "power4",
            (3, false) => "power8",
            (4, false) => "power16",
            (2, true) => "power4-tuned",
            (3, true) => "power8-tuned",
            _ => "power16-tuned",
        }
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        pow2k(pos(M::madd(self.s.t::<T>(), c - T::one(), T::one())), K)
    }
    /// The kernel folds `Lobe::eval`'s clamp into the base where `s >= 1` on the FMA
    /// instruction sets: `t = fma(s, c, 1 - s)` (one rounding; `1 - s` is exact for an f32 `s`
    /// in [1, 2^24]), `min(t, 1)` (t increases with c, so this is c's clamp at 1; NaN kept)
    /// and `max(t, 0)` (c below `1 - 1/s`, every c < 0, and NaN): one subtraction and one
    /// clamp fewer than clamping c first, the C loop's operation count (issue 13).
    /// Elsewhere (`s < 1`, where the base at c = 0 is positive, or SSE2, where the product
    /// would round alone) c is clamped first.
    ///
    /// Subnormals: bases in (0, `tmin`) make subnormal squarings, cosines in a band
    /// `tmin / s` wide above the zero `1 - 1/s`. For `power4` and `power8` that band is under
    /// 1.5e-4 of [0, 1] at every n >= 1 (`tmin` 3.3e-10 and 1.8e-5): rare, left alone. For
    /// `power16` (`tmin` 4.3e-3: 3.4e-3 of [0, 1] at n = 20, which cost 1.3x) the base is
    /// clamped at `tmin` instead of 0 (`t > tmin ? t : tmin`, NaN and c < 0 included) and
    /// `tmin^16` (1.2e-38) subtracted at the end: 0 exactly below `tmin`, 1.2e-38 less
    /// elsewhere (1 stays 1), no subnormal squaring, and no compare; the subtraction runs
    /// beside the five multiplies that bound the kernel (a compare and select ran slower;
    /// on `power4`, whose multiplies do not dominate, the subtraction would not be free). So
    /// no kernel of the family needs the flush-to-zero switch.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let s = self.s.t::<f32>();
        let t = if M::FMA && s >= 1.0 {
            let t = M::madd(s, c, 1.0 - s);
            if 1.0 < t { 1.0 } else { t }
        } else {
            let x = if 0.0 > c { 0.0 } else { c };
            let x = if 1.0 < x { 1.0 } else { x };
            M::madd(s, x - 1.0, 1.0)
        };
        if K >= 4 {
            pow2k(if t > self.tmin { t } else { self.tmin }, K) - self.tmin_pow
        } else {
            pow2k(pos(t), K)
        }
    }
    fn batch_ftz(&self) -> bool {
        false
    }
    fn zero_below(&self) -> f64 {
        (1.0 - 1.0 / self.s.x).max(0.0)
    }
    fn cos_dist(&self) -> Option<crate::sample::CosDist> {
        Some(crate::sample::CosDist::PowerG {
            s: self.s.x,
            g: f64::from(Self::G),
        })
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        let g = Self::G;
        let expr = if self.tuned {
            format!(
                "select(p_n / {g}.0 * ({}), 1.0, p_n == {g}.0)",
                super::fits::poly_expr(super::fits::power_poly(g))
            )
        } else {
            format!("p_n / {g}.0")
        };
        format!("fb_lobe_power{g}({c}, {})", e.kx(self.s, &expr, &["n"]))
    }
}
