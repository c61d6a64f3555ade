//! Shadowing terms without a roughness parameter: `kelemen`, `neumann`.
//!
//! - `kelemen`: Kelemen & Szirmay-Kalos 2001, `G / (4 NL NV) = 1 / (4 VH^2)`, i.e.
//!   `G = NL NV / VH^2`, computed as `min(1, (NV / VH) (NL / VH))`. For a consistent direction
//!   pair `VH^2 = (1 + v.l) / 2 >= NL NV`, so the clamp binds only on inconsistent inputs (it
//!   keeps hostile ones finite). One-sided (no `cos_l`): `NL = 1`, with the given `VH` (as the
//!   V-cavity's one-sided term keeps its given half vector). Needs the half vector. Cost: 1 mul,
//!   2 div.
//! - `neumann`: Neumann, Neumann & Szirmay-Kalos 1999, `G = NL NV / max(NL, NV)`, which is
//!   exactly `min(NL, NV)` (computed so: no rounding). One-sided: `NV`. Cost: 0 operations.
//!
//! Both approximate the product `G(v, l)` of a fairly rough surface without a slope
//! parameter, so neither has an exact twin at a given alpha and neither has an `ErrorBound`.
//! Cosines that are NaN or `<= 0` give 0 (and, for `kelemen`, a `VH` or `NH` that is).
//! f32 against f64 (`tests/precision.rs`): `kelemen` 1.05e-7 measured, also with `fastbrdf check --full` (documented 1e-6);
//! `neumann` is exact (measured 0; documented 1e-7).

use crate::entry::Entry;
use crate::forms::ShadowForm;
use crate::math::Math;
use crate::model::{Kind, ModelInfo, Ops};
use crate::plan::Plan;
use crate::real::{Real, min1};
use crate::wgsl::Emit;

pub const INFO_KELEMEN: ModelInfo = ModelInfo {
    id: "kelemen",
    kind: Kind::Shadowing,
    params: &[],
    formula: "G = NL NV / VH^2 (G / (4 NL NV) = 1 / (4 VH^2)), at most 1",
    source: "Kelemen & Szirmay-Kalos 2001, \"A Microfacet Based Coupled Specular-Matte BRDF Model with Importance Sampling\"",
    ops: Ops::new(1, 0, 2, 0, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "input columns cos_v, cos_h, cos_vh and optional cos_l (two-sided; cos_h only for the domain rule); no roughness parameter, so no exact twin",
};

pub const INFO_NEUMANN: ModelInfo = ModelInfo {
    id: "neumann",
    kind: Kind::Shadowing,
    params: &[],
    formula: "G = NL NV / max(NL, NV) = min(NL, NV)",
    source: "Neumann, Neumann & Szirmay-Kalos 1999, \"Compact Metallic Reflectance Models\"",
    ops: Ops::new(0, 0, 0, 0, 0),
    bounds: &[],
    f32_bound: 1e-7,
    note: "one-sided (no cos_l): NV; no roughness parameter, so no exact twin",
};

pub const ENTRY_KELEMEN: Entry =
    Entry::new(INFO_KELEMEN, |_, _| Ok(Plan::Shadowing(Kelemen.into())));
pub const ENTRY_NEUMANN: Entry =
    Entry::new(INFO_NEUMANN, |_, _| Ok(Plan::Shadowing(Neumann.into())));

/// Kelemen and Szirmay-Kalos's term.
#[derive(Clone, Copy, Debug, Default)]
pub struct Kelemen;

impl ShadowForm for Kelemen {
    const HALF_VECTOR: bool = true;
    const WGSL: &'static str = include_str!("kelemen_neumann.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, cos_vh: T) -> T {
        // Each quotient is positive (no 0 * inf); an infinite one gives 1.
        min1((min1(cos_v) / cos_vh) * (min1(cos_l) / cos_vh))
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, vh: &str, _e: &Emit) -> String {
        format!("fb_g_kelemen({v}, {l}, {vh})")
    }
}

/// Neumann et al.'s term.
#[derive(Clone, Copy, Debug, Default)]
pub struct Neumann;

impl ShadowForm for Neumann {
    const WGSL: &'static str = include_str!("kelemen_neumann.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        min1(cos_v.min(cos_l))
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, _e: &Emit) -> String {
        format!("fb_g_neumann({v}, {l})")
    }
}
