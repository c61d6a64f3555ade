//! Fresnel terms: `fresnel-none`, `fresnel-schlick`, `fresnel-schlick-sg`,
//! `fresnel-schlick-sg-tuned`, `fresnel-dielectric`, `fresnel-conductor` (the `f` choices of
//! `cook-torrance`: the id without `fresnel-`).
//!
//! - none: `F = 1`.
//! - schlick: `F = f0 + (f90 - f0)(1 - cos)^5` (Schlick 1994; `f90`, default 1, as Filament's
//!   `F_Schlick(f0, f90, VoH)`). Cost: 4 mul, 2 add.
//! - schlick-sg: Schlick's `(1 - cos)^5` replaced by Karis's spherical-Gaussian form
//!   `2^((-5.55473 cos - 6.98316) cos)` (Karis 2013, "Real Shading in Unreal Engine 4"; Unreal's
//!   mobile path). Cost: 2 mul, 2 add, 1 exp2 (an exp2 is not cheaper than 3 multiplies on a
//!   CPU: the form is for GPUs, where exp2 is one instruction). Error against Schlick:
//!   at most 0.00378 absolute (of the peak; at f0 = 0, cos = 0.055; it scales with `f90 - f0`).
//! - schlick-sg-tuned: the same form with both constants refitted to minimise the maximum
//!   error against `(1 - cos)^5`: a = -5.551343, b = -6.996120 (`cargo run --release -p
//!   fastbrdf-analysis --example fit_fresnel_sg` prints them), at most 0.00341 (10% less than
//!   Karis's constants; the fit reaches the same optimum from two starting points); same cost.
//! - dielectric: the exact unpolarised Fresnel reflectance of a dielectric interface with
//!   relative index `eta` (`eta < 1` gives total internal reflection beyond the critical
//!   angle), as pbrt's `FrDielectric`. Cost: ~10 mul, 6 add, 3 div, 1 sqrt.
//! - conductor: the exact unpolarised reflectance for a complex index `eta + i k`, in the
//!   real-arithmetic form of pbrt-v3's `FrConductor` (tested against complex arithmetic).
//!   Cost: ~16 mul, 8 add, 2 div, 3 sqrt.
//!
//! Parameters: `f0` in [0, 1] (default 0.04), `f90` in [0, 1] (default 1), `eta` in [0.01, 10]
//! (default 1.5), `k` in [0, 20] (default 0). The cosine is that between the view and the
//! microfacet normal.

use crate::entry::Entry;
use crate::forms::FresnelForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{ParamKind, ParamSpec};
use crate::plan::Plan;
use crate::real::{K, Real, min1, pos, sqr};
use crate::wgsl::Emit;

pub const F0: ParamSpec = ParamSpec {
    name: "f0",
    kind: ParamKind::Number {
        min: 0.0,
        max: 1.0,
        default: Some(0.04),
        requires: &[],
    },
    doc: "reflectance at normal incidence (Schlick)",
};
pub const F90: ParamSpec = ParamSpec {
    name: "f90",
    kind: ParamKind::Number {
        min: 0.0,
        max: 1.0,
        default: Some(1.0),
        requires: &[],
    },
    doc: "reflectance at grazing incidence (Schlick; 1 is Schlick's own form)",
};
pub const ETA: ParamSpec = ParamSpec {
    name: "eta",
    kind: ParamKind::Number {
        min: 0.01,
        max: 10.0,
        default: Some(1.5),
        requires: &[],
    },
    doc: "relative index of refraction (real part)",
};
pub const K: ParamSpec = ParamSpec {
    name: "k",
    kind: ParamKind::Number {
        min: 0.0,
        max: 20.0,
        default: Some(0.0),
        requires: &[],
    },
    doc: "extinction coefficient (imaginary part of the index, conductors)",
};

macro_rules! info {
    ($id:literal, $params:expr, $formula:literal, $source:literal, $ops:expr) => {
        info!($id, $params, $formula, $source, $ops, &[])
    };
    ($id:literal, $params:expr, $formula:literal, $source:literal, $ops:expr, $bounds:expr) => {
        ModelInfo {
            id: $id,
            kind: Kind::Fresnel,
            params: $params,
            formula: $formula,
            source: $source,
            ops: $ops,
            bounds: $bounds,
            f32_bound: 1e-6,
            note: "",
        }
    };
}

/// The documented maximum of `|F - F_schlick|` over `cos` and `f0` in [0, 1] (`f90 = 1`; the
/// error scales with `f90 - f0`, so `f0 = 0` is the worst case).
const fn vs_schlick(bound: f64) -> [ErrorBound; 1] {
    [ErrorBound {
        reference: "fresnel-schlick",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("f0", 0.0, 1.0),
        bound,
    }]
}

pub const INFO_NONE: ModelInfo = info!("fresnel-none", &[], "1", "-", Ops::new(0, 0, 0, 0, 0));
pub const INFO_SCHLICK: ModelInfo = info!(
    "fresnel-schlick",
    &[F0, F90],
    "f0 + (f90 - f0)(1 - cos)^5",
    "Schlick 1994 (f90: Filament's F_Schlick)",
    Ops::new(4, 2, 0, 0, 0)
);
/// Karis's constants (Unreal Engine 4's `F_Schlick` on mobile).
pub const SG_KARIS: (f64, f64) = (-5.55473, -6.98316);
/// The same form refitted: `(a, b)` minimising `max |2^((a c + b) c) - (1 - c)^5|` over
/// `c` in [0, 1] (`fit_fresnel_sg` example).
pub const SG_TUNED: (f64, f64) = (-5.551343, -6.996120);
pub const INFO_SCHLICK_SG: ModelInfo = info!(
    "fresnel-schlick-sg",
    &[F0, F90],
    "f0 + (f90 - f0) 2^((-5.55473 cos - 6.98316) cos)",
    "Karis 2013, Real Shading in Unreal Engine 4 (spherical-Gaussian Schlick)",
    Ops::new(2, 2, 0, 0, 1),
    &vs_schlick(0.00378)
);
pub const INFO_SCHLICK_SG_TUNED: ModelInfo = info!(
    "fresnel-schlick-sg-tuned",
    &[F0, F90],
    "f0 + (f90 - f0) 2^((a cos + b) cos), a, b minimax against (1 - cos)^5",
    "this project: Karis's form refitted (fit_fresnel_sg example)",
    Ops::new(2, 2, 0, 0, 1),
    &vs_schlick(0.00341)
);
pub const INFO_DIELECTRIC: ModelInfo = info!(
    "fresnel-dielectric",
    &[ETA],
    "(r_par^2 + r_perp^2) / 2, exact, with total internal reflection",
    "Fresnel equations; pbrt-v3 FrDielectric",
    Ops::new(10, 6, 3, 1, 0)
);
pub const INFO_CONDUCTOR: ModelInfo = info!(
    "fresnel-conductor",
    &[ETA, K],
    "(R_s + R_p) / 2 for complex index eta + i k, exact",
    "Fresnel equations; pbrt-v3 FrConductor",
    Ops::new(16, 8, 2, 3, 0)
);

pub const ENTRY_NONE: Entry = Entry::new(INFO_NONE, |_, _| Ok(Plan::Fresnel(NoFresnel.into())));
pub const ENTRY_SCHLICK: Entry = Entry::new(INFO_SCHLICK, |p, _| {
    Ok(Plan::Fresnel(
        Schlick {
            f0: K::new(p.num("f0")),
            f90: K::new(p.num("f90")),
        }
        .into(),
    ))
});
pub const ENTRY_SCHLICK_SG: Entry = Entry::new(INFO_SCHLICK_SG, |p, _| {
    Ok(Plan::Fresnel(SchlickSg::new(p, SG_KARIS).into()))
});
pub const ENTRY_SCHLICK_SG_TUNED: Entry = Entry::new(INFO_SCHLICK_SG_TUNED, |p, _| {
    Ok(Plan::Fresnel(SchlickSg::new(p, SG_TUNED).into()))
});
pub const ENTRY_DIELECTRIC: Entry = Entry::new(INFO_DIELECTRIC, |p, _| {
    Ok(Plan::Fresnel(
        Dielectric(Consts::new(p.num("eta"), 0.0)).into(),
    ))
});
pub const ENTRY_CONDUCTOR: Entry = Entry::new(INFO_CONDUCTOR, |p, _| {
    Ok(Plan::Fresnel(
        Conductor(Consts::new(p.num("eta"), p.num("k"))).into(),
    ))
});

/// No Fresnel factor (1).
#[derive(Clone, Copy, Debug)]
pub struct NoFresnel;

impl FresnelForm for NoFresnel {
    const WGSL: &'static str = include_str!("fresnel.wgsl");
    #[inline(always)]
    fn f<T: Real, M: Math<T>>(&self, _cos: T) -> T {
        T::one()
    }
    fn wgsl(&self, _c: &str, _e: &Emit) -> String {
        "1.0f".into()
    }
}

/// Schlick's approximation `f0 + (f90 - f0)(1 - cos)^5`.
#[derive(Clone, Copy, Debug)]
pub struct Schlick {
    pub f0: K,
    pub f90: K,
}

impl FresnelForm for Schlick {
    const WGSL: &'static str = include_str!("fresnel.wgsl");
    #[inline(always)]
    fn f<T: Real, M: Math<T>>(&self, cos: T) -> T {
        let one = T::one();
        // NaN and negative cosines act as 0 (`max` then `min` maps NaN to 0).
        let c = min1(pos(cos));
        let f0 = self.f0.t::<T>();
        let m = one - c;
        let m2 = m * m;
        M::madd(self.f90.t::<T>() - f0, m2 * m2 * m, f0)
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        format!(
            "fb_f_schlick({c}, {}, {})",
            e.kx(self.f0, "p_f0", &["f0"]),
            e.kx(self.f90, "p_f90", &["f90"])
        )
    }
}

/// Schlick's form with `(1 - cos)^5` replaced by `2^((a cos + b) cos)` (Karis's constants or
/// their refit).
#[derive(Clone, Copy, Debug)]
pub struct SchlickSg {
    pub f0: K,
    pub f90: K,
    pub a: K,
    pub b: K,
}

impl SchlickSg {
    fn new(p: &crate::params::Params, (a, b): (f64, f64)) -> Self {
        Self {
            f0: K::new(p.num("f0")),
            f90: K::new(p.num("f90")),
            a: K::new(a),
            b: K::new(b),
        }
    }
}

impl FresnelForm for SchlickSg {
    const WGSL: &'static str = include_str!("fresnel.wgsl");
    #[inline(always)]
    fn f<T: Real, M: Math<T>>(&self, cos: T) -> T {
        // NaN and negative cosines act as 0; the exponent is <= 0 on [0, 1].
        let c = min1(pos(cos));
        let f0 = self.f0.t::<T>();
        let x = M::madd(self.a.t::<T>(), c, self.b.t::<T>()) * c;
        M::madd(self.f90.t::<T>() - f0, M::exp2_nonpos_tail(x), f0)
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        // `a`, `b` are fixed by the id, never runtime parameters.
        format!(
            "fb_f_schlick_sg({c}, {}, {}, {}, {})",
            e.kx(self.f0, "p_f0", &["f0"]),
            e.kx(self.f90, "p_f90", &["f90"]),
            e.constant(self.a),
            e.constant(self.b),
        )
    }
}

/// The exact dielectric term (see [`dielectric`]).
#[derive(Clone, Copy, Debug)]
pub struct Dielectric(pub Consts);

impl FresnelForm for Dielectric {
    const WGSL: &'static str = include_str!("fresnel.wgsl");
    #[inline(always)]
    fn f<T: Real, M: Math<T>>(&self, cos: T) -> T {
        dielectric(cos, &self.0)
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        // `eta^2 - 1` as the CPU holds it: computed in f64 from the parameter and rounded
        // once (literal and storage forms), or from the f32 argument (runtime form).
        format!(
            "fb_f_dielectric_e({c}, {}, {})",
            e.kx(self.0.eta, "p_eta", &["eta"]),
            e.kx(self.0.e, "(p_eta - 1.0) * (p_eta + 1.0)", &["eta"])
        )
    }
}

/// The exact conductor term (see [`conductor`]).
#[derive(Clone, Copy, Debug)]
pub struct Conductor(pub Consts);

impl FresnelForm for Conductor {
    const WGSL: &'static str = include_str!("fresnel.wgsl");
    #[inline(always)]
    fn f<T: Real, M: Math<T>>(&self, cos: T) -> T {
        conductor(cos, &self.0)
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        format!(
            "fb_f_conductor({c}, {}, {})",
            e.kx(self.0.eta, "p_eta", &["eta"]),
            e.kx(self.0.k, "p_k", &["k"])
        )
    }
}

/// The per-parameter constants of the exact Fresnel terms, computed in f64 at construction.
/// Near the critical angle (`cos^2 = p = k^2 + 1 - eta^2`, `eta < 1`), `t0 = c^2 - p`
/// cancels: it is computed as `(c - s)(c + s)` with `s = sqrt(p)` held as an unevaluated sum
/// `s_hi + s_lo` of two `T` (split where it is used, in the evaluation precision), so that
/// `c - s_hi` is exact (Sterbenz) and the f32 result keeps its relative accuracy instead of
/// the absolute `2^-24` of a rounded `c^2 - p`.
///
/// The terms that depend on `eta` alone (`e = eta^2 - 1`, `eta^2`, `e - k^2`) are computed
/// here in f64 from the parameter as given and rounded once (issue 27): near `eta = 1`, `e`
/// computed in f32 from `eta`'s f32 rounding is off by that rounding's relative `1e-4` (at
/// `eta = 1.0001`: `eta - 1` carries an error of 1.7e-8 in 1e-4), which moved `F` by 3e-5 at
/// grazing, 30 times the f32 bound, where the f64 value is the parameter's own.
#[derive(Clone, Copy, Debug)]
pub struct Consts {
    pub eta: K,
    pub k: K,
    /// `eta^2 - 1 = (eta - 1)(eta + 1)`.
    pub e: K,
    /// `eta^2`.
    pub eta2: K,
    /// `eta^2 - 1 - k^2` (`t0` at `c = 0`).
    pub ek: K,
    /// `s_hi + s_lo = sqrt(p)` when `p > 0` (else 0): in f64 `s_hi` is `sqrt(p)` and `s_lo`
    /// 0; in f32 `s_hi` is its rounding and `s_lo` the rest, rounded.
    pub s_hi: K,
    pub s_lo: K,
    /// `p > 0`.
    pub edge: bool,
}

impl Consts {
    /// The constants for the index `eta + i k` (`k = 0` for dielectrics).
    pub fn new(eta: f64, k: f64) -> Self {
        let p = k * k + (1.0 - eta) * (1.0 + eta);
        let s = if p > 0.0 { p.sqrt() } else { 0.0 };
        let e = (eta - 1.0) * (eta + 1.0);
        Self {
            eta: K::new(eta),
            k: K::new(k),
            e: K::new(e),
            eta2: K::new(eta * eta),
            ek: K::new(e - k * k),
            s_hi: K::new(s),
            s_lo: K::pair(0.0, (s - f64::from(s as f32)) as f32),
            edge: p > 0.0,
        }
    }

    /// `t0 = eta^2 - k^2 - sin^2 = c^2 - p`, without cancellation.
    #[inline(always)]
    fn t0<T: Real>(&self, c: T) -> T {
        if self.edge {
            let (s_hi, s_lo) = (self.s_hi.t::<T>(), self.s_lo.t::<T>());
            ((c - s_hi) - s_lo) * ((c + s_hi) + s_lo)
        } else {
            self.ek.t::<T>() + c * c
        }
    }
}

/// The smallest cosine the exact Fresnel terms evaluate at (`2^-60`): smaller cosines (and
/// NaN or negative ones) act as this one. Its square is a normal number in f32, so no
/// product below underflows; the value it replaces differs from it by less than `2^-48`
/// (`F -> 1` at grazing, except for `eta = 1, k = 0` where `F = 0` for every cosine).
pub const COS_LO: f64 = 8.673_617_379_884_035e-19;

#[inline(always)]
fn clamp_lo<T: Real>(c: T) -> T {
    if c >= T::c(COS_LO) {
        c.min(T::one())
    } else {
        T::c(COS_LO)
    }
}

/// The exact dielectric reflectance, arranged for f32 (twins: the batch kernel of [`Dielectric`],
/// `fb_f_dielectric_e` in the WGSL library). With `e = eta^2 - 1 = (eta - 1)(eta + 1)` (and
/// `eta^2`, `e - k^2`: [`Consts`], in f64 from the parameter, rounded once) and
/// `g = eta cos_t = sqrt(e + c^2)`:
/// `r_perp = (c - g) / (c + g) = -e / (c + g)^2` and
/// `r_par = (eta^2 c - g) / (eta^2 c + g) = e ((eta^2 + 1) c^2 - 1) / (eta^2 c + g)^2`,
/// so neither subtracts nearly equal numbers: both vanish exactly at `eta = 1`; `g^2` is
/// [`Consts`]'s `t0`, exact near the critical angle too. (pbrt's form
/// `1 - (1 - c^2) / eta^2` rounds to 1 in f32 for `c < 1.7e-4` at `eta = 1`, giving `F = 1`
/// where the exact value is 0.) Total internal reflection (`e + c^2 <= 0`) gives 1.
#[inline(always)]
pub fn dielectric<T: Real>(cos: T, p: &Consts) -> T {
    let one = T::one();
    let c = clamp_lo(cos);
    let c2 = c * c;
    let e = p.e.t::<T>();
    let g2 = p.t0(c);
    let g = pos(g2).sqrt();
    let eta2 = p.eta2.t::<T>();
    let d_perp = c + g;
    let r_perp = -e / (d_perp * d_perp);
    let d_par = eta2 * c + g;
    // (eta^2 + 1) c^2 - 1, as g^2 - eta^2 sin^2 for eta < 1 (both terms vanish together at
    // the critical angle, where the difference is accurate because g^2 is) and as
    // eta^2 c^2 - sin^2 for eta >= 1 (where g^2 and eta^2 sin^2 approach eta^2 at grazing).
    let s2 = (one - c) * (one + c);
    let brewster = if p.edge {
        g2 - eta2 * s2
    } else {
        eta2 * c2 - s2
    };
    let r_par = e * brewster / (d_par * d_par);
    let f = (r_par * r_par + r_perp * r_perp) * T::c(0.5);
    if g2 <= T::zero() { one } else { f.min(one) }
}

/// The exact conductor reflectance for the index `eta + i k`, arranged for f32 (twins:
/// the batch kernel of [`Conductor`], `fb_f_conductor`). pbrt-v3's `FrConductor` with
/// `t0 = eta^2 - k^2 - sin^2 = (eta - 1)(eta + 1) - k^2 + c^2` (no `1 - sin^2`
/// cancellation), `a^2 + b^2 = |t0 + 2 i eta k|` split into `a^2`, `b^2` without
/// cancellation (see below), and
/// `R_s = ((a - c)^2 + b^2) / ((a + c)^2 + b^2)`,
/// `R_p = R_s ((a c - s^2)^2 + (b c)^2) / ((a c + s^2)^2 + (b c)^2)`: sums of squares, which
/// equal pbrt's `t1 -/+ t2`, `t3 -/+ t4` without their cancellation.
#[inline(always)]
pub fn conductor<T: Real>(cos: T, p: &Consts) -> T {
    let one = T::one();
    let half = T::c(0.5);
    let c = clamp_lo(cos);
    let c2 = c * c;
    let s2 = (one - c) * (one + c);
    let t0 = p.t0(c);
    let ek = T::c(2.0) * p.eta.t::<T>() * p.k.t::<T>();
    // a^2 + b^2 = r = |t0 + i ek|; the larger of a^2, b^2 is (r + |t0|) / 2 = |t0| + q and the
    // smaller (r - |t0|) / 2 = q = ek^2 / (2 (r + |t0|)), so that with k = 0 they are exactly
    // |t0| and 0 even where t0^2 underflows.
    let at0 = t0.abs();
    let den = (t0 * t0 + ek * ek).sqrt() + at0;
    let q = if den > T::zero() {
        half * ek * ek / den
    } else {
        T::zero()
    };
    let (big, small) = (at0 + q, q);
    let (a2, b2) = if t0 >= T::zero() {
        (big, small)
    } else {
        (small, big)
    };
    let a = a2.sqrt();
    let rs = (sqr(a - c) + b2) / (sqr(a + c) + b2);
    let bc2 = b2 * c2;
    let rp = rs * (sqr(a * c - s2) + bc2) / (sqr(a * c + s2) + bc2);
    let f = (rp + rs) * half;
    if f.is_finite() { min1(pos(f)) } else { one }
}
