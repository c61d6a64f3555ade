//! The machine's limits: lane FMAs and divisions per second on one core, measured by
//! independent chains, and the fraction of them a kernel's counted operations use.

use super::time;
use fastbrdf::batch::Isa;
use fastbrdf::{Kind, PipeOps};
use std::hint::black_box;
use std::time::Duration;

const ACC: usize = 256;

/// `ACC` independent chains of `iters` steps each: `x a + b` fused (`DIV` false), or `x / a`
/// (`DIV` true; `a` near 1 keeps every value normal).
#[inline(always)]
fn peak_body<const DIV: bool>(iters: usize, a: f32, b: f32) -> f32 {
    let mut acc = [0.0f32; ACC];
    for (i, x) in acc.iter_mut().enumerate() {
        *x = if DIV { 1.0 } else { 0.0 } + i as f32 * 1e-3;
    }
    for _ in 0..iters {
        for x in acc.iter_mut() {
            *x = if DIV { *x / a } else { x.mul_add(a, b) };
        }
    }
    acc.iter().sum()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,fma")]
unsafe fn fma_avx512<const DIV: bool>(iters: usize, a: f32, b: f32) -> f32 {
    peak_body::<DIV>(iters, a, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fma_avx2<const DIV: bool>(iters: usize, a: f32, b: f32) -> f32 {
    peak_body::<DIV>(iters, a, b)
}

/// Whether this CPU has every feature the FMA loop for `isa` is compiled with (the
/// `#[target_feature]` sets of `fma_avx512` and `fma_avx2`); the SSE2 and scalar loops need
/// nothing beyond the target's baseline.
pub fn fma_supported(isa: Isa) -> bool {
    match isa {
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => {
            std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512vl")
                && std::is_x86_feature_detected!("fma")
        }
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => {
            std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        Isa::Avx512 | Isa::Avx2Fma => false,
        Isa::Sse2 | Isa::Scalar => true,
    }
}

/// Lane FMAs per second on one core with `isa` (256 independent accumulators, so the FMA
/// pipes, not their latency, limit it). Without FMA (SSE2) it counts a multiply-add pair
/// as one. `None` when this CPU lacks `isa` ([`fma_supported`]): the loop is never run
/// with instructions the CPU does not have.
pub fn fma_per_s(isa: Isa, budget: Duration) -> Option<f64> {
    peak_per_s::<false>(isa, budget, (0.999_9, 1e-4))
}

/// Lane divisions per second on one core with `isa`: the divide unit's throughput (256
/// independent chains of `x / a`, so its latency does not enter), the limit of the kernels
/// whose formula divides (`schlick`, `rational`, GGX's D). `None` as [`fma_per_s`].
pub fn div_per_s(isa: Isa, budget: Duration) -> Option<f64> {
    peak_per_s::<true>(isa, budget, (1.000_1, 0.0))
}

fn peak_per_s<const DIV: bool>(isa: Isa, budget: Duration, (a, b): (f32, f32)) -> Option<f64> {
    if !fma_supported(isa) {
        return None;
    }
    let iters = if DIV { 4_000 } else { 20_000 };
    let (a, b) = (black_box(a), black_box(b));
    let secs = time(
        || {
            let r = match isa {
                // SAFETY: `fma_supported(isa)` checked above that the CPU has avx512f,
                // avx512vl and fma, the features `fma_avx512` is compiled with.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe { fma_avx512::<DIV>(iters, a, b) },
                // SAFETY: `fma_supported(isa)` checked above that the CPU has avx2 and fma.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2Fma => unsafe { fma_avx2::<DIV>(iters, a, b) },
                _ => {
                    let mut acc = [1.0f32; ACC];
                    for _ in 0..iters {
                        for x in acc.iter_mut() {
                            *x = if DIV { *x / a } else { *x * a + b };
                        }
                    }
                    acc.iter().sum()
                }
            };
            black_box(r);
        },
        budget,
    );
    Some((iters * ACC) as f64 / secs)
}

/// FMA-pipe slots per evaluation of a kernel of cosines whose formula is multiplies and adds
/// only (registry counts): `max(mul, add)` where the instruction set fuses them (each add
/// rides on a multiply), `mul + add` otherwise. `None` for BRDFs (their counts leave out the
/// pair set-up), for formulas with a division, square root or transcendental (the divider or
/// a polynomial of ~10-40 operations bounds those, not this count: issue 13 found `sg`
/// counted as 2 operations where it executes about 26), and for scalar fallbacks.
pub fn fma_slots(info: &fastbrdf::ModelInfo, isa: Isa) -> Option<f64> {
    let o = info.ops;
    let simple = o.div == 0 && o.sqrt == 0 && o.transcendental == 0;
    if info.kind == Kind::Brdf || !simple || isa == Isa::Scalar {
        return None;
    }
    let (m, a) = (f64::from(o.mul), f64::from(o.add));
    let slots = if isa.fma() { m.max(a) } else { m + a };
    (slots > 0.0).then_some(slots)
}

/// The machine limit a kernel of cosines is measured against, and the fraction of it that
/// `evals_per_s` evaluations use: the FMA pipes or the divider (`div` lane divisions per
/// evaluation, against `div_per_s`), whichever the kernel uses more of. The count is the
/// kernel's own where its family gives one (`kernel`, from `Kernel::pipe_ops`: its
/// multiply-pipe operations, a vectorised `exp2`'s polynomial included), else the formula's
/// (`max(mul, add)` slots per evaluation where the instruction set fuses, `mul + add`
/// otherwise). `None` for BRDFs, uncounted formulas with a square root or transcendental,
/// scalar fallbacks, and where the divider's rate is unknown but needed.
pub fn limit_fraction(
    info: &fastbrdf::ModelInfo,
    isa: Isa,
    evals_per_s: f64,
    fma_per_s: f64,
    div_per_s: Option<f64>,
    kernel: Option<PipeOps>,
) -> Option<(&'static str, f64)> {
    let o = info.ops;
    if info.kind == Kind::Brdf || isa == Isa::Scalar {
        return None;
    }
    let (slots, divs) = match kernel {
        Some(k) if isa.fma() => (f64::from(k.mul), k.div),
        _ if o.sqrt != 0 || o.transcendental != 0 => return None,
        _ => {
            let (m, a) = (f64::from(o.mul), f64::from(o.add));
            (if isa.fma() { m.max(a) } else { m + a }, o.div)
        }
    };
    let fma = evals_per_s * slots / fma_per_s;
    if divs == 0 {
        return (slots > 0.0).then_some(("fma", fma));
    }
    let div = evals_per_s * f64::from(divs) / div_per_s?;
    Some(if div >= fma {
        ("divider", div)
    } else {
        ("fma", fma)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fma_slots_count_only_what_the_registry_can_count() {
        let info = |id: &str| fastbrdf::registry::find(id).unwrap().info;
        // power16: 5 mul, 1 add; fused, the add rides on a multiply.
        assert_eq!(fma_slots(&info("power16"), Isa::Avx2Fma), Some(5.0));
        assert_eq!(fma_slots(&info("power16"), Isa::Sse2), Some(6.0));
        // Transcendentals, divisions and BRDFs have no such count.
        for id in ["sg", "pow", "schlick", "ward", "cook-torrance"] {
            assert_eq!(fma_slots(&info(id), Isa::Avx512), None, "{id}");
        }
        assert_eq!(fma_slots(&info("power16"), Isa::Scalar), None);
    }

    /// The limit is the unit the formula's counted operations load more: power16 (5 fused
    /// slots, no division) the FMA pipes; schlick (one division, two fused slots) the divider
    /// unless divisions are nearly as cheap as FMAs; nothing for transcendentals and BRDFs.
    #[test]
    fn limit_fraction_names_the_unit_the_formula_loads_most() {
        let info = |id: &str| fastbrdf::registry::find(id).unwrap().info;
        let (fma, div) = (100e9, 20e9);
        let l = limit_fraction(&info("power16"), Isa::Avx512, 10e9, fma, Some(div), None);
        assert_eq!(l, Some(("fma", 10e9 * 5.0 / fma)));
        let l = limit_fraction(&info("schlick"), Isa::Avx512, 10e9, fma, Some(div), None);
        assert_eq!(l, Some(("divider", 10e9 / div)));
        // Divisions as cheap as a third of an FMA slot: the pipes bound it again.
        let l = limit_fraction(
            &info("schlick"),
            Isa::Avx512,
            10e9,
            fma,
            Some(3.0 * fma),
            None,
        );
        assert_eq!(l.map(|l| l.0), Some("fma"));
        // Without a divider rate a dividing kernel has no stated limit.
        assert_eq!(
            limit_fraction(&info("schlick"), Isa::Avx512, 1e9, fma, None, None),
            None
        );
        for id in ["sg", "pow", "ward", "cook-torrance"] {
            assert_eq!(
                limit_fraction(&info(id), Isa::Avx512, 1e9, fma, Some(div), None),
                None
            );
        }
        assert_eq!(
            limit_fraction(&info("power16"), Isa::Scalar, 1e9, fma, Some(div), None),
            None
        );
    }

    /// A family that counts its kernel (`Kernel::pipe_ops`) is measured with that count on
    /// the FMA instruction sets: sg's exponential is a polynomial the registry's
    /// `1 mul, 1 add, 1 transcendental` cannot see; beckmann's one division against its
    /// eleven multiply-pipe operations picks whichever unit it loads more.
    #[test]
    fn limit_fraction_uses_a_kernels_own_count() {
        let info = |id: &str| fastbrdf::registry::find(id).unwrap().info;
        let (fma, div) = (100e9, 20e9);
        let sg = Some(PipeOps { mul: 7, div: 0 });
        let l = limit_fraction(&info("sg"), Isa::Avx512, 10e9, fma, Some(div), sg);
        assert_eq!(l, Some(("fma", 10e9 * 7.0 / fma)));
        // Not on SSE2 (the count is the FMA kernels') and not for scalar fallbacks.
        for isa in [Isa::Sse2, Isa::Scalar] {
            assert_eq!(
                limit_fraction(&info("sg"), isa, 1e9, fma, Some(div), sg),
                None
            );
        }
        let b = Some(PipeOps { mul: 11, div: 1 });
        let l = limit_fraction(&info("beckmann"), Isa::Avx2Fma, 5e9, fma, Some(div), b);
        assert_eq!(l, Some(("fma", 5e9 * 11.0 / fma)));
        let l = limit_fraction(&info("beckmann"), Isa::Avx2Fma, 5e9, fma, Some(4e9), b);
        assert_eq!(l, Some(("divider", 5e9 / 4e9)));
        assert_eq!(
            limit_fraction(&info("beckmann"), Isa::Avx2Fma, 5e9, fma, None, b),
            None
        );
    }

    /// `fma_per_s` is safe to call with every instruction set: a positive finite rate for
    /// those this CPU has, `None` (never an illegal instruction) for the others.
    #[test]
    fn fma_per_s_is_safe_for_every_isa() {
        let budget = Duration::from_millis(1);
        for isa in [Isa::Avx512, Isa::Avx2Fma, Isa::Sse2, Isa::Scalar] {
            let rate = fma_per_s(isa, budget);
            assert_eq!(rate.is_some(), fma_supported(isa), "{isa:?}");
            if let Some(r) = rate {
                assert!(r.is_finite() && r > 0.0, "{isa:?}: {r}");
            }
        }
        for isa in [Isa::Avx512, Isa::Avx2Fma, Isa::Sse2, Isa::Scalar] {
            let rate = div_per_s(isa, budget);
            assert_eq!(rate.is_some(), fma_supported(isa), "{isa:?}");
            // A division is never cheaper than a fused multiply-add.
            if let (Some(d), Some(f)) = (rate, fma_per_s(isa, budget)) {
                assert!(
                    d.is_finite() && d > 0.0 && d < 2.0 * f,
                    "{isa:?}: {d} vs {f}"
                );
            }
        }
        // The instruction set the benchmark picks is always measurable.
        assert!(fma_per_s(Isa::best(), budget).is_some());
        assert!(fma_supported(Isa::Sse2) && fma_supported(Isa::Scalar));
    }
}
