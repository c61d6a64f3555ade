//! Batch kernels: evaluate one model with fixed parameters over slices, in f32.
//!
//! Inputs are structures of arrays: one slice of cosines for lobes, distributions and Fresnel
//! terms; six slices (`wi_x, wi_y, wi_z, wo_x, wo_y, wo_z`) for full BRDFs.
//!
//! How it is fast: each model's formula is a branch-free, `#[inline(always)]` per-element op
//! (`ops`), over vectorisable elementary functions (`math`: exp2, log2, pow, acos with
//! documented accuracy, no libm calls). The loop over a slice is compiled three times, inside
//! functions with `#[target_feature]` AVX-512, AVX2+FMA, and the x86-64 baseline (SSE2), and
//! LLVM vectorises each; the best one the CPU has is chosen at run time with
//! `is_x86_feature_detected!` (tails are the same loop's remainder). Large batches are split
//! across threads with rayon (`Kernel::eval_par`).
//!
//! Results agree with the scalar models (`Model<f32>`) in meaning, inputs out of the domain
//! included (tested on every model in `tests/batch.rs`); numerically they differ only by the
//! fast elementary functions' few ulp.
//!
//! Models without a SIMD kernel (standalone shadowing terms, exact Smith inside Cook-Torrance,
//! anisotropic... none else) run the scalar model per element and say so: `Kernel::simd()` is
//! false and `Kernel::isa()` is `Isa::Scalar`.

pub mod math;
pub mod ops;

use crate::error::{Error, Result};
use crate::microfacet::beckmann_pow::exponent;
use crate::microfacet::fresnel::Consts;
use crate::model::{Kind, Model};
use crate::params::Params;
use crate::registry;
use ops::{Op1, Op6};
use rayon::prelude::*;
use serde::Serialize;

/// An instruction set a kernel can run with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Isa {
    /// AVX-512 (F, VL, DQ, BW) with FMA: 16 f32 lanes.
    Avx512,
    /// AVX2 with FMA: 8 lanes.
    Avx2Fma,
    /// The x86-64 baseline, SSE2: 4 lanes (also the only option on other architectures,
    /// where the compiler's default vector width applies).
    Sse2,
    /// No SIMD kernel: the scalar model, element by element.
    Scalar,
}

impl Isa {
    /// The best SIMD instruction set this CPU supports.
    pub fn best() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512vl")
                && std::is_x86_feature_detected!("avx512dq")
                && std::is_x86_feature_detected!("avx512bw")
                && std::is_x86_feature_detected!("fma")
            {
                return Isa::Avx512;
            }
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                return Isa::Avx2Fma;
            }
        }
        Isa::Sse2
    }

    /// Every SIMD instruction set this CPU supports, best first.
    pub fn available() -> Vec<Isa> {
        let all = [Isa::Avx512, Isa::Avx2Fma, Isa::Sse2];
        let best = all.iter().position(|i| *i == Self::best()).unwrap_or(2);
        all[best..].to_vec()
    }

    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Avx512 => "avx512",
            Isa::Avx2Fma => "avx2+fma",
            Isa::Sse2 => "sse2",
            Isa::Scalar => "scalar",
        }
    }

    /// f32 lanes per vector register.
    pub fn lanes(self) -> usize {
        match self {
            Isa::Avx512 => 16,
            Isa::Avx2Fma => 8,
            Isa::Sse2 => 4,
            Isa::Scalar => 1,
        }
    }
}

// ---------- the ISA-specific loops ----------

#[inline(always)]
fn map1_body<O: Op1>(op: &O, x: &[f32], out: &mut [f32]) {
    for (o, &c) in out.iter_mut().zip(x) {
        *o = op.f(c);
    }
}

#[inline(always)]
fn map6_body<O: Op6>(op: &O, w: [&[f32]; 6], out: &mut [f32]) {
    let n = out.len();
    let (a, b, c, d, e, f) = (
        &w[0][..n],
        &w[1][..n],
        &w[2][..n],
        &w[3][..n],
        &w[4][..n],
        &w[5][..n],
    );
    for i in 0..n {
        out[i] = op.f([a[i], b[i], c[i]], [d[i], e[i], f[i]]);
    }
}

macro_rules! isa_variants {
    ($body:ident, $avx512:ident, $avx2:ident, $plain:ident, $bound:ident, $input:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
        unsafe fn $avx512<O: $bound>(op: &O, x: $input, out: &mut [f32]) {
            $body(op, x, out)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn $avx2<O: $bound>(op: &O, x: $input, out: &mut [f32]) {
            $body(op, x, out)
        }
        fn $plain<O: $bound>(op: &O, x: $input, out: &mut [f32]) {
            $body(op, x, out)
        }
    };
}

isa_variants!(map1_body, map1_avx512, map1_avx2, map1_plain, Op1, &[f32]);
isa_variants!(
    map6_body,
    map6_avx512,
    map6_avx2,
    map6_plain,
    Op6,
    [&[f32]; 6]
);

fn run1<O: Op1>(isa: Isa, op: &O, x: &[f32], out: &mut [f32]) {
    match isa {
        // SAFETY: `Kernel` only passes an ISA that `Isa::available` reported.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { map1_avx512(op, x, out) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { map1_avx2(op, x, out) },
        _ => map1_plain(op, x, out),
    }
}

fn run6<O: Op6>(isa: Isa, op: &O, w: [&[f32]; 6], out: &mut [f32]) {
    match isa {
        // SAFETY: as in `run1`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { map6_avx512(op, w, out) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { map6_avx2(op, w, out) },
        _ => map6_plain(op, w, out),
    }
}

// ---------- kernels ----------

/// The inputs of one batch.
#[derive(Clone, Copy, Debug)]
pub enum Input<'a> {
    /// Cosines (lobes: `cos`; distributions: `cos_h`; Fresnel: `cos_vh`).
    Cos(&'a [f32]),
    /// Direction components `wi_x, wi_y, wi_z, wo_x, wo_y, wo_z` (full BRDFs).
    Dirs([&'a [f32]; 6]),
}

impl Input<'_> {
    fn len(&self) -> usize {
        match self {
            Input::Cos(x) => x.len(),
            Input::Dirs(w) => w[0].len(),
        }
    }
    fn slice(&self, lo: usize, hi: usize) -> Self {
        match *self {
            Input::Cos(x) => Input::Cos(&x[lo..hi]),
            Input::Dirs(w) => Input::Dirs(w.map(|s| &s[lo..hi])),
        }
    }
}

trait Imp: Send + Sync {
    fn run(&self, isa: Isa, input: Input, out: &mut [f32]);
    fn simd(&self) -> bool {
        true
    }
}

struct Map1<O>(O);
impl<O: Op1> Imp for Map1<O> {
    fn run(&self, isa: Isa, input: Input, out: &mut [f32]) {
        if let Input::Cos(x) = input {
            run1(isa, &self.0, x, out)
        }
    }
}

struct Map6<O>(O);
impl<O: Op6> Imp for Map6<O> {
    fn run(&self, isa: Isa, input: Input, out: &mut [f32]) {
        if let Input::Dirs(w) = input {
            run6(isa, &self.0, w, out)
        }
    }
}

/// The scalar model, element by element (models without a SIMD kernel).
struct Fallback(Model<f32>);
impl Imp for Fallback {
    fn run(&self, _isa: Isa, input: Input, out: &mut [f32]) {
        match input {
            Input::Cos(x) => {
                for (o, &c) in out.iter_mut().zip(x) {
                    *o = self.0.eval_row(&[Some(c), None, None, None]);
                }
            }
            Input::Dirs(w) => {
                for (i, o) in out.iter_mut().enumerate() {
                    *o = self.0.eval_row(&[
                        Some(w[0][i]),
                        Some(w[1][i]),
                        Some(w[2][i]),
                        Some(w[3][i]),
                        Some(w[4][i]),
                        Some(w[5][i]),
                    ]);
                }
            }
        }
    }
    fn simd(&self) -> bool {
        false
    }
}

/// A model compiled for batch evaluation.
pub struct Kernel {
    id: &'static str,
    kind: Kind,
    imp: Box<dyn Imp>,
}

impl Kernel {
    /// Builds the kernel of model `id` with parameters given as text (validated like
    /// `registry::build`). Shadowing terms take several cosines: they are not batchable and
    /// are an error here.
    pub fn new(id: &str, given: &[(&str, &str)]) -> Result<Self> {
        let e = registry::find(id)?;
        let p = Params::resolve(e.info.id, e.info.params, given)?;
        if e.info.kind == Kind::Shadowing {
            return Err(Error::WrongKind {
                model: id.into(),
                expected: "lobe, distribution, fresnel or brdf".into(),
                found: "shadowing".into(),
            });
        }
        let imp = match build(e.info.id, &p)? {
            Some(imp) => imp,
            None => Box::new(Fallback(registry::build_resolved::<f32>(e, &p)?)) as Box<dyn Imp>,
        };
        Ok(Self {
            id: e.info.id,
            kind: e.info.kind,
            imp,
        })
    }

    /// The model id.
    pub fn id(&self) -> &'static str {
        self.id
    }

    /// The kind of input it takes.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// Whether a SIMD kernel exists (else the scalar model runs per element).
    pub fn simd(&self) -> bool {
        self.imp.simd()
    }

    /// The instruction set `eval` uses.
    pub fn isa(&self) -> Isa {
        if self.simd() {
            Isa::best()
        } else {
            Isa::Scalar
        }
    }

    fn check(&self, input: &Input, out: &[f32]) -> Result<()> {
        let ok_kind = matches!(
            (self.kind, input),
            (Kind::Brdf, Input::Dirs(_))
                | (
                    Kind::Lobe | Kind::Distribution | Kind::Fresnel,
                    Input::Cos(_)
                )
        );
        if !ok_kind {
            return Err(Error::WrongKind {
                model: self.id.into(),
                expected: if self.kind == Kind::Brdf {
                    "six direction slices".into()
                } else {
                    "one slice of cosines".into()
                },
                found: "the other input shape".into(),
            });
        }
        let lens_ok = match input {
            Input::Cos(x) => x.len() == out.len(),
            Input::Dirs(w) => w.iter().all(|s| s.len() == out.len()),
        };
        if !lens_ok {
            return Err(Error::Domain {
                input: "batch".into(),
                reason: format!("input and output lengths differ (output {})", out.len()),
            });
        }
        Ok(())
    }

    /// Evaluates with the best instruction set, on this thread.
    pub fn eval(&self, input: Input, out: &mut [f32]) -> Result<()> {
        self.eval_with(self.isa(), input, out)
    }

    /// Evaluates with a given instruction set (one of `Isa::available()`, or `Isa::Scalar`,
    /// which runs the baseline loop). Errors if the CPU lacks it.
    pub fn eval_with(&self, isa: Isa, input: Input, out: &mut [f32]) -> Result<()> {
        self.check(&input, out)?;
        if isa != Isa::Scalar && !Isa::available().contains(&isa) {
            return Err(Error::Domain {
                input: "isa".into(),
                reason: format!("this CPU does not support {}", isa.name()),
            });
        }
        self.imp
            .run(if isa == Isa::Scalar { Isa::Sse2 } else { isa }, input, out);
        Ok(())
    }

    /// Evaluates with the best instruction set, split across rayon's threads in chunks of
    /// 16384 elements.
    pub fn eval_par(&self, input: Input, out: &mut [f32]) -> Result<()> {
        self.check(&input, out)?;
        const CHUNK: usize = 16384;
        let isa = if self.simd() { Isa::best() } else { Isa::Sse2 };
        let n = input.len();
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(i, o)| {
            let lo = i * CHUNK;
            self.imp.run(isa, input.slice(lo, (lo + o.len()).min(n)), o);
        });
        Ok(())
    }
}

// ---------- building ops from ids ----------

/// Calls back with the op of lobe `id` at exponent `n` (one generic instantiation per lobe).
trait LobeVisitor {
    fn visit<L: Op1>(self, l: L) -> Box<dyn Imp>;
}

fn lobe_op<V: LobeVisitor>(id: &str, n: f64, v: V) -> Option<Box<dyn Imp>> {
    use crate::lobes::cubic::CubicShape;
    use crate::lobes::flog::{seed_coef, zero_cos};
    use crate::lobes::tuned;
    let _ = zero_cos;
    let cubic = |s: CubicShape| ops::Cubic {
        d1: s.d1 as f32,
        d2: s.d2 as f32,
        d3: s.d3 as f32,
        x1: s.x1 as f32,
        x2: s.x2 as f32,
        cut: s.cut as f32,
    };
    let rational_at = |level: f64| ops::Rational {
        n: n as f32,
        xq: ((level.ln() / n).exp_m1()) as f32,
        level: level as f32,
    };
    let rational = || rational_at(0.5);
    let cubic_rational = |level: f64| ops::CubicRational {
        cubic: cubic(CubicShape::hermite_at(n, level)),
        rational: rational_at(level),
        q: level.powf(1.0 / n) as f32,
    };
    Some(match id {
        "pow" => v.visit(ops::Pow { n: n as f32 }),
        "schlick" => v.visit(ops::Schlick { n: n as f32 }),
        "schlick-modified" => v.visit(ops::SchlickModified { n: n as f32 }),
        "gauss" => v.visit(ops::Gauss {
            half_n: (0.5 * n) as f32,
        }),
        "flog" => v.visit(ops::Flog {
            n: n as f32,
            coef: 1.0,
            clamp: false,
        }),
        "flog-normalized" => v.visit(ops::Flog {
            n: n as f32,
            coef: seed_coef(n) as f32,
            clamp: false,
        }),
        "flog-normalized-clamped" => v.visit(ops::Flog {
            n: n as f32,
            coef: seed_coef(n) as f32,
            clamp: true,
        }),
        "cubic" => v.visit(cubic(CubicShape::hermite(n))),
        "cubic3" => v.visit(cubic(CubicShape::three_point(n, 0.5, 1.0 / 18.0))),
        "rational" => v.visit(rational()),
        "cubic-rational" => v.visit(cubic_rational(0.5)),
        "cubic-rational-tuned" => v.visit(cubic_rational(tuned::cubic_rational_level(n))),
        "power4-tuned" => v.visit(ops::Power::<2> {
            s: tuned::power_slope(4, n) as f32,
        }),
        "power8-tuned" => v.visit(ops::Power::<3> {
            s: tuned::power_slope(8, n) as f32,
        }),
        "power16-tuned" => v.visit(ops::Power::<4> {
            s: tuned::power_slope(16, n) as f32,
        }),
        "sg-tuned" => v.visit(ops::Exp2Lobe {
            k: tuned::exp2_rate(n) as f32,
        }),
        "power4" => v.visit(ops::Power::<2> {
            s: (n / 4.0) as f32,
        }),
        "power8" => v.visit(ops::Power::<3> {
            s: (n / 8.0) as f32,
        }),
        "power16" => v.visit(ops::Power::<4> {
            s: (n / 16.0) as f32,
        }),
        "sg" => v.visit(ops::Exp2Lobe {
            k: (n / std::f64::consts::LN_2) as f32,
        }),
        #[allow(clippy::approx_constant)]
        "ue4-phong-approx" => v.visit(ops::Exp2Lobe {
            k: (1.4427 * (n + 0.775)) as f32,
        }),
        _ => return None,
    })
}

struct AsMap1;
impl LobeVisitor for AsMap1 {
    fn visit<L: Op1>(self, l: L) -> Box<dyn Imp> {
        Box::new(Map1(l))
    }
}

struct AsLobeBrdf {
    zero: f64,
    coef: f32,
    blinn: bool,
    normalized: bool,
}
impl LobeVisitor for AsLobeBrdf {
    fn visit<L: Op1>(self, lobe: L) -> Box<dyn Imp> {
        Box::new(Map6(ops::LobeBrdf {
            lobe,
            zero: self.zero,
            coef: self.coef,
            blinn: self.blinn,
            normalized: self.normalized,
        }))
    }
}

/// Calls back with the distribution op `id` at slope `alpha`.
trait DistVisitor {
    fn visit<D: ops::DOp>(self, d: D) -> Option<Box<dyn Imp>>;
}

fn dist_op<V: DistVisitor>(id: &str, alpha: f64, v: V) -> Option<Box<dyn Imp>> {
    let a2 = alpha * alpha;
    let ct = (1.0 / (4.0 * a2)) as f32;
    let power = |g: f64| (exponent(alpha) / g) as f32;
    match id {
        "beckmann" => v.visit(ops::Beckmann {
            inv_alpha2: (1.0 / a2) as f32,
            scale: (1.0 / (std::f64::consts::PI * a2)) as f32,
        }),
        "beckmann-ct" => v.visit(ops::Beckmann {
            inv_alpha2: (1.0 / a2) as f32,
            scale: ct,
        }),
        "beckmann-pow" => v.visit(ops::BeckmannPow {
            e: exponent(alpha) as f32,
            scale: ct,
        }),
        "beckmann-power4" => v.visit(ops::BeckmannPower::<2> {
            s: power(4.0),
            scale: ct,
        }),
        "beckmann-power8" => v.visit(ops::BeckmannPower::<3> {
            s: power(8.0),
            scale: ct,
        }),
        "beckmann-power16" => v.visit(ops::BeckmannPower::<4> {
            s: power(16.0),
            scale: ct,
        }),
        _ => None,
    }
}

struct AsDist;
impl DistVisitor for AsDist {
    fn visit<D: ops::DOp>(self, d: D) -> Option<Box<dyn Imp>> {
        Some(Box::new(Map1(ops::Dist(d))))
    }
}

struct AsCookTorrance<'a> {
    p: &'a Params,
    k: f32,
}
impl DistVisitor for AsCookTorrance<'_> {
    fn visit<D: ops::DOp>(self, d: D) -> Option<Box<dyn Imp>> {
        let p = self.p;
        let k = self.k;
        macro_rules! with_f {
            ($g:expr) => {{
                let g = $g;
                Some(match p.choice("f") {
                    "none" => Box::new(Map6(ops::CookTorrance {
                        d,
                        g,
                        fr: ops::FNone,
                        k,
                    })) as Box<dyn Imp>,
                    "schlick" => Box::new(Map6(ops::CookTorrance {
                        d,
                        g,
                        fr: ops::FSchlick {
                            f0: p.num("f0") as f32,
                        },
                        k,
                    })),
                    "dielectric" => Box::new(Map6(ops::CookTorrance {
                        d,
                        g,
                        fr: ops::FDielectric {
                            p: Consts::new(p.num("eta"), 0.0),
                        },
                        k,
                    })),
                    _ => Box::new(Map6(ops::CookTorrance {
                        d,
                        g,
                        fr: ops::FConductor {
                            p: Consts::new(p.num("eta"), p.num("k")),
                        },
                        k,
                    })),
                })
            }};
        }
        match p.choice("g") {
            "v-cavity" => with_f!(ops::VCavity),
            "smith-rational" => with_f!(ops::SmithRational {
                alpha: p.num("alpha") as f32
            }),
            // The exact Smith term needs erfc: no vectorised version; the scalar model runs.
            _ => None,
        }
    }
}

fn build(id: &str, p: &Params) -> Result<Option<Box<dyn Imp>>> {
    let fres = |f: Box<dyn Imp>| Ok(Some(f));
    match id {
        _ if crate::lobes::IDS.contains(&id) => Ok(lobe_op(id, p.num("n"), AsMap1)),
        _ if crate::microfacet::DISTRIBUTION_IDS.contains(&id) => {
            Ok(dist_op(id, p.num("alpha"), AsDist))
        }
        "fresnel-none" => fres(Box::new(Map1(ops::Fres(ops::FNone)))),
        "fresnel-schlick" => fres(Box::new(Map1(ops::Fres(ops::FSchlick {
            f0: p.num("f0") as f32,
        })))),
        "fresnel-dielectric" => fres(Box::new(Map1(ops::Fres(ops::FDielectric {
            p: Consts::new(p.num("eta"), 0.0),
        })))),
        "fresnel-conductor" => fres(Box::new(Map1(ops::Fres(ops::FConductor {
            p: Consts::new(p.num("eta"), p.num("k")),
        })))),
        "cook-torrance" => {
            let k = match p.choice("denominator") {
                "4" => 0.25,
                "seed-000" => 1.0,
                _ => std::f32::consts::FRAC_1_PI,
            };
            Ok(dist_op(
                p.choice("d"),
                p.num("alpha"),
                AsCookTorrance { p, k },
            ))
        }
        "ward" | "ward-pow" | "ward-power16" => {
            let (nx, ny) = crate::brdf::ward::slope_params(p)?;
            let (ax, ay) = (p.num(nx), p.num(ny));
            let scale = (1.0 / (4.0 * std::f64::consts::PI * ax * ay)) as f32;
            let (inv_ax2, inv_ay2) = ((1.0 / (ax * ax)) as f32, (1.0 / (ay * ay)) as f32);
            let e = 2.0 / (ax * ax);
            Ok(Some(match id {
                "ward" => Box::new(Map6(ops::Ward::<0> {
                    inv_ax2,
                    inv_ay2,
                    e: 0.0,
                    scale,
                })) as Box<dyn Imp>,
                "ward-pow" => Box::new(Map6(ops::Ward::<1> {
                    inv_ax2,
                    inv_ay2,
                    e: e as f32,
                    scale,
                })),
                _ => Box::new(Map6(ops::Ward::<2> {
                    inv_ax2,
                    inv_ay2,
                    e: (e / 16.0) as f32,
                    scale,
                })),
            }))
        }
        "lambert" => Ok(Some(Box::new(Map6(ops::Lambert {
            value: (p.num("albedo") / std::f64::consts::PI) as f32,
        })))),
        "phong" | "blinn-phong" => {
            let normalized = p.choice("norm") == "energy";
            let n = p.num("n");
            let coef = if normalized {
                1.0 / (2.0
                    * std::f64::consts::PI
                    * crate::brdf::phong::lobe_integral(p.choice("lobe"), n)?)
            } else {
                1.0
            };
            Ok(lobe_op(
                p.choice("lobe"),
                n,
                AsLobeBrdf {
                    zero: crate::brdf::phong::build_lobe::<f32>(p.choice("lobe"), n)?.zero_below(),
                    coef: coef as f32,
                    blinn: id == "blinn-phong",
                    normalized,
                },
            ))
        }
        _ => Ok(None),
    }
}
