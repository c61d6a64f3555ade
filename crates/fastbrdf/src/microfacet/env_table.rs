//! The split-sum terms read from a look-up table as engines ship it (`Kind::Env`):
//! `env-brdf-table`, Filament's DFG texture at the sizes and storage formats engines use.
//!
//! The table: `N x N` texels (parameter `size`: 16, 32, 64 or 128; Filament builds its
//! `DFG.inc` at 128), texel `(i, j)` the exact `env-brdf` terms (its quadrature, f64, rounded
//! to f32) at its centre: `cos_v = (i + 0.5) / N` and perceptual roughness
//! `r = (j + 0.5) / N`, `alpha = r^2` (Filament's axes: `NoV` across, `perceptualRoughness`
//! up; `alpha` below `params::ALPHA`'s 0.005 reads the value at 0.005, as `fastbrdf lut`).
//! Stored (parameter `bits`) as 8-bit unorm (`round(255 v) / 255`), half float (IEEE binary16,
//! round to nearest even: Filament's RG16F) or float32. Read as a GPU samples it: bilinear
//! filtering with clamp-to-edge, at texture coordinates `(cos_v, sqrt(alpha))`: texel
//! coordinate `s = u N - 0.5` clamped to `[0, N - 1]`, weights `s - floor(s)`.
//!
//! Filament's own generator (`libs/ibl/src/CubemapIBL.cpp`, `CubemapIBL::DFG`, at commit
//! 13d3ade) computes image row `y` at `coord = (N - y + 0.5) / N` and `cmgen` writes image
//! row `N - 1 - y` as GL row `y`: GL row `j` then holds `r = (j + 1.5) / N` (the top row
//! clamped to 1), one texel above the centre its bilinear fetch assumes. This table holds the
//! centres (what the lookup assumes); the shift is Filament's, not the table format's.
//!
//! Design: the exact values of a size are computed once per process (`OnceLock`, one per
//! size: `N^2` texels x 2 terms of `env-brdf`'s quadrature, on all cores; 128 x 128 is 32768
//! quadratures, about a second), the storage rounding applied at each read (4 texels), in f32
//! on every target, so that f32, f64, the batch kernels and the GPU read the same numbers. The
//! WGSL twin (`env_table.wgsl`: the lookups; [`wgsl_source`]: the tables as constant arrays,
//! generated from the same f32 values, one array per size holding both terms) does the same
//! arithmetic. Cost as an engine pays it: one bilinear texture fetch; here 4 reads, 4
//! roundings and 3 lerps, about 12 mul and 10 add (the `ops`); not vectorised (gathers).
//!
//! Error: see `INFO` (the default 32 x 32 half-float table) and, for every size and storage,
//! `fastbrdf errors --model env-brdf-table --param size=N --param bits=B` and the book's DFG
//! ledger (`docs/book/src/dfg-ledger.md`). The error is interpolation (the terms bend sharply
//! at small roughness and grazing) plus storage rounding (8-bit: up to 1/510).

use crate::entry::Entry;
use crate::forms::EnvForm;
use crate::math::Math;
use crate::microfacet::env_brdf::{Dfg, TERM};
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{Options, ParamKind, ParamSpec};
use crate::plan::{GeneratedSource, Plan};
use crate::real::Real;
use crate::wgsl::Emit;
use std::sync::OnceLock;

/// The table sides offered (`size`).
pub const SIZES: [usize; 4] = [16, 32, 64, 128];

pub const SIZE: ParamSpec = ParamSpec {
    name: "size",
    kind: ParamKind::Choice {
        options: Options::List(&["16", "32", "64", "128"]),
        default: "32",
    },
    doc: "the table's side N (N x N texels; Filament ships 128)",
};

pub const BITS: ParamSpec = ParamSpec {
    name: "bits",
    kind: ParamKind::Choice {
        options: Options::List(&["8", "16", "32"]),
        default: "16",
    },
    doc: "storage per value: 8 (unorm8), 16 (half float, Filament's RG16F) or 32 (float32)",
};

pub const INFO: ModelInfo = ModelInfo {
    id: "env-brdf-table",
    kind: Kind::Env,
    params: &[TERM, SIZE, BITS],
    formula: "bilinear clamp-to-edge fetch at (cos_v, sqrt(alpha)) of an N x N table of env-brdf at texel centres (x = cos_v, y = perceptual roughness), stored at 8, 16 or 32 bits",
    source: "Filament's DFG look-up table (cmgen --ibl-dfg, DFG.inc); Karis 2013 (split sum)",
    ops: Ops::new(12, 10, 0, 1, 0),
    bounds: &[ErrorBound {
        reference: "env-brdf",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound: 0.0701,
    }],
    f32_bound: 1e-6,
    note: "the bound is the default table's (32 x 32, half float); every size and storage: fastbrdf errors --model env-brdf-table --param size=N --param bits=B",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    let size = SIZES
        .iter()
        .position(|s| s.to_string() == p.choice("size"))
        .expect("a listed size") as u8;
    let bits = p.choice("bits").parse().expect("a listed storage");
    Ok(Plan::Env(
        Table {
            bias: p.choice("term") == "bias",
            size,
            bits,
        }
        .into(),
    ))
});

/// One term of one table: `size` indexes [`SIZES`], `bits` is 8, 16 or 32.
#[derive(Clone, Copy, Debug)]
pub struct Table {
    pub bias: bool,
    pub size: u8,
    pub bits: u8,
}

/// The exact terms of a table of side `SIZES[k]`, as f32: `[scale, bias]` of texel `(i, j)` at
/// `j * N + i` (row `j` the roughness, as `fastbrdf lut` writes it).
pub fn texels(k: usize) -> &'static [[f32; 2]] {
    static T: [OnceLock<Vec<[f32; 2]>>; 4] = [const { OnceLock::new() }; 4];
    T[k].get_or_init(|| {
        let n = SIZES[k];
        let (amin, _) = crate::params::ALPHA.range();
        let row = |j: usize| -> Vec<[f32; 2]> {
            let r = (j as f64 + 0.5) / n as f64;
            let alpha = (r * r).max(amin);
            (0..n)
                .map(|i| {
                    let v = (i as f64 + 0.5) / n as f64;
                    let e = |bias| Dfg { bias }.e::<f64, crate::math::Exact>(v, alpha) as f32;
                    [e(false), e(true)]
                })
                .collect()
        };
        let threads = std::thread::available_parallelism().map_or(1, |t| t.get());
        let mut rows: Vec<Vec<[f32; 2]>> = vec![vec![]; n];
        std::thread::scope(|s| {
            for (t, chunk) in rows.chunks_mut(n.div_ceil(threads)).enumerate() {
                let row = &row;
                s.spawn(move || {
                    let j0 = t * n.div_ceil(threads);
                    for (dj, out) in chunk.iter_mut().enumerate() {
                        *out = row(j0 + dj);
                    }
                });
            }
        });
        rows.concat()
    })
}

/// `v` as stored at `bits`, read back as f32: unorm8 `round(255 v) / 255` (as `v` times the
/// f32 of 1/255, the same product in WGSL), binary16 rounded to nearest even, or `v`.
#[inline(always)]
pub fn quantise(v: f32, bits: u8) -> f32 {
    match bits {
        8 => (v.clamp(0.0, 1.0) * 255.0).round_ties_even() * (1.0f32 / 255.0),
        16 => {
            // Below 2^-14 binary16 is subnormal: multiples of 2^-24.
            if v < 6.103_515_6e-5 {
                (v * 16_777_216.0).round_ties_even() * (1.0 / 16_777_216.0)
            } else {
                let b = v.to_bits();
                let r = (b + 0xfff + ((b >> 13) & 1)) & !0x1fff;
                f32::from_bits(r)
            }
        }
        _ => v,
    }
}

/// The texel coordinate of texture coordinate `u` on a side of `n` texels, clamped to the
/// edge texels' centres: `(index, weight)`, the index at most `n - 2`.
#[inline(always)]
fn coord<T: Real>(u: T, n: usize) -> (usize, T) {
    let s = u * T::c(n as f64) - T::c(0.5);
    let s = if s > T::zero() { s } else { T::zero() };
    let s = if s < T::c((n - 1) as f64) {
        s
    } else {
        T::c((n - 1) as f64)
    };
    let i = s.floor().to_usize().unwrap_or(0).min(n - 2);
    (i, s - T::c(i as f64))
}

impl EnvForm for Table {
    const WGSL: &'static str = include_str!("env_table.wgsl");
    const SIMD: bool = false;
    #[inline(always)]
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T {
        let k = self.size as usize;
        let n = SIZES[k];
        let tab = texels(k);
        let (i, tx) = coord(cos_v, n);
        let (j, ty) = coord(alpha.sqrt(), n);
        let b = self.bias as usize;
        let at = |i: usize, j: usize| T::c(quantise(tab[j * n + i][b], self.bits) as f64);
        let lerp = |a: T, b: T, t: T| a + (b - a) * t;
        let r0 = lerp(at(i, j), at(i + 1, j), tx);
        let r1 = lerp(at(i, j + 1), at(i + 1, j + 1), tx);
        lerp(r0, r1, ty)
    }
    fn wgsl(&self, v: &str, a: &str, _e: &Emit) -> String {
        format!(
            "fb_env_table_{}({v}, {a}, {}u, {})",
            SIZES[self.size as usize],
            self.bits,
            if self.bias { "true" } else { "false" }
        )
    }
}

/// The WGSL table of side `SIZES[k]`, `FB_ENV_TABLE_<N>`, both terms interleaved
/// (`2 (j N + i) + term`), the same f32 numbers as [`texels`] (generated once): one source per
/// size, since the quadrature is the costly part and a shader reads one size.
fn table_source(k: usize) -> &'static str {
    static SRC: [OnceLock<String>; 4] = [const { OnceLock::new() }; 4];
    SRC[k].get_or_init(|| {
        let n = SIZES[k];
        let list: Vec<String> = texels(k)
            .iter()
            .flat_map(|t| t.iter().map(|x| format!("{x:?}f")))
            .collect();
        format!(
            "// WGSL twin of microfacet/env_table.rs's texels, generated from it.\n\
             \n/// env-brdf's terms on the {n} x {n} table: (scale, bias) of texel (i, j) at 2 (j {n} + i).\n\
             const FB_ENV_TABLE_{n} = array<f32, {}>({});\n",
            2 * n * n,
            list.join(", ")
        )
    })
}

/// The four tables as the library's generated sources, one per size.
pub const WGSL_TABLES: [GeneratedSource; 4] = [
    table(
        "microfacet/env_table_data.wgsl (16)",
        &["FB_ENV_TABLE_16"],
        || table_source(0),
    ),
    table(
        "microfacet/env_table_data.wgsl (32)",
        &["FB_ENV_TABLE_32"],
        || table_source(1),
    ),
    table(
        "microfacet/env_table_data.wgsl (64)",
        &["FB_ENV_TABLE_64"],
        || table_source(2),
    ),
    table(
        "microfacet/env_table_data.wgsl (128)",
        &["FB_ENV_TABLE_128"],
        || table_source(3),
    ),
];

const fn table(
    file: &'static str,
    items: &'static [&'static str],
    source: fn() -> &'static str,
) -> GeneratedSource {
    GeneratedSource {
        file,
        items,
        source,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The storage rounding against an independent rounding in f64: unorm8 to the nearest of
    /// 255 steps; binary16 to the nearest multiple of its spacing at the value's exponent.
    #[test]
    fn quantise_rounds_to_the_nearest_stored_value() {
        let mut x = 1e-7f32;
        while x <= 1.0 {
            for v in [x, 1.0 - x] {
                let q8 = quantise(v, 8) as f64;
                assert!(
                    (q8 * 255.0 - (v as f64 * 255.0).round()).abs() < 1e-4,
                    "{v}"
                );
                let e = (v as f64).log2().floor().max(-14.0);
                let ulp = (e - 10.0).exp2();
                let want = ((v as f64) / ulp).round() * ulp;
                let q16 = quantise(v, 16) as f64;
                // Ties (never hit by these values) would round to even; otherwise nearest.
                assert!(
                    (q16 - want).abs() <= 1e-12 * want.max(1e-30),
                    "{v}: {q16} vs {want}"
                );
                assert_eq!(quantise(v, 32), v);
            }
            x *= 1.37;
        }
    }

    /// At a texel centre the fetch returns the texel (stored), and the texels are env-brdf's.
    #[test]
    fn fetch_at_a_texel_centre_is_the_texel() {
        let k = 0;
        let n = SIZES[k];
        let tab = texels(k);
        for (i, j) in [(0, 0), (3, 7), (15, 15), (8, 2)] {
            let (v, r) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            for bias in [false, true] {
                let t = Table {
                    bias,
                    size: 0,
                    bits: 16,
                };
                let got = t.e::<f64, crate::math::Exact>(v, r * r);
                let want = quantise(tab[j * n + i][bias as usize], 16) as f64;
                assert!(
                    (got - want).abs() < 1e-12,
                    "({i}, {j}) {bias}: {got} vs {want}"
                );
                let alpha = (r * r).max(0.005);
                let exact = Dfg { bias }.e::<f64, crate::math::Exact>(v, alpha);
                assert!((tab[j * n + i][bias as usize] as f64 - exact).abs() < 1e-7);
            }
        }
    }
}
