//! Batched sampling and densities of one BRDF with fixed parameters, in f32, over
//! structure-of-arrays slices ([`Sampler`]).
//!
//! Generic path (every BRDF): the per-element loop is monomorphised over the plan's concrete
//! family (`plan::with_brdf`, dispatched once per batch, as [`super::Kernel`] does): each
//! element runs exactly `forms::Scalar::<B>`'s `Brdf::<f32>::sample` / `pdf`, so the values
//! are the scalar model's bit for bit (tested), without a virtual call per element.
//!
//! SIMD path (Cook-Torrance with GGX and `vndf`, its default; `Sampler::simd` says where it
//! runs): the scalar steps branch-free in `#[target_feature]` loops and the weight's `f` from
//! the eval [`super::Kernel`], or, for inputs of near unit length, closed forms (`ggx`'s
//! header for what differs from the scalar values and by how much: `pdf` not at all but for
//! near-unit inputs, there within 1e-6 relative times a conditioning factor; drawn
//! directions within the scalar f32 sampler's own error).
//! Blocks of 512 elements; the threaded calls split into fixed chunks of 4096, so their
//! values are the sequential ones bit for bit.
//!
//! `u` outside [0, 1): every strategy first clamps it as the scalar sampler does
//! (`sample::unit_interval`: negative and NaN act as 0, 1 and above as `1 - eps`), so no
//! value of `u` is an error or gives NaN (tested on every BRDF and strategy).

mod ggx;

/// The unit tier's range of `|v|^2 - 1` (`ggx`'s header): directions whose squared length
/// is within it of 1 take the closed forms.
pub use ggx::NEAR;
pub use ggx::sincos_2pi;

use super::{Input, Isa, Kernel};
use crate::error::{Error, Result};
use crate::forms::{BrdfForm, Scalar};
use crate::model::{self, Kind};
use crate::plan::{BrdfPlan, DistForm, DistPlan, Plan, with_brdf};
use crate::sample::Strategy;
use rayon::prelude::*;

/// The outputs of [`Sampler::sample`]: `wi` (unit, components x, y, z), the weight
/// `f(wi, wo) cos_i / pdf` and the solid-angle density of `wi`.
pub struct SampleOut<'a> {
    pub wi: [&'a mut [f32]; 3],
    pub weight: &'a mut [f32],
    pub pdf: &'a mut [f32],
}

impl SampleOut<'_> {
    fn len_ok(&self, n: usize) -> bool {
        self.wi.iter().all(|s| s.len() == n) && self.weight.len() == n && self.pdf.len() == n
    }
}

/// A batch implementation, monomorphised per family.
trait Imp: Send + Sync {
    /// `s` is resolved (one of the BRDF's strategies); lengths are checked.
    fn sample(&self, s: Strategy, wo: [&[f32]; 3], u: [&[f32]; 2], out: SampleOut<'_>);
    fn pdf(&self, s: Strategy, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]);
}

/// The generic path: the scalar model's code per element, with the concrete family.
struct Generic<B>(Scalar<B>);

impl<B: BrdfForm> Imp for Generic<B> {
    fn sample(&self, s: Strategy, wo: [&[f32]; 3], u: [&[f32]; 2], out: SampleOut<'_>) {
        let n = out.weight.len();
        let SampleOut { wi, weight, pdf } = out;
        let [wx, wy, wz] = wi;
        let (wx, wy, wz) = (&mut wx[..n], &mut wy[..n], &mut wz[..n]);
        let (ox, oy, oz, u0, u1) = (
            &wo[0][..n],
            &wo[1][..n],
            &wo[2][..n],
            &u[0][..n],
            &u[1][..n],
        );
        let pdf = &mut pdf[..n];
        for i in 0..n {
            let r = model::Brdf::<f32>::sample(&self.0, [ox[i], oy[i], oz[i]], [u0[i], u1[i]], s);
            let (w, f, p) = match r {
                Some(r) => (r.wi, r.weight, r.pdf),
                None => ([0.0; 3], 0.0, 0.0),
            };
            wx[i] = w[0];
            wy[i] = w[1];
            wz[i] = w[2];
            weight[i] = f;
            pdf[i] = p;
        }
    }

    fn pdf(&self, s: Strategy, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
        let n = out.len();
        let (ox, oy, oz) = (&wo[0][..n], &wo[1][..n], &wo[2][..n]);
        let (ix, iy, iz) = (&wi[0][..n], &wi[1][..n], &wi[2][..n]);
        for i in 0..n {
            out[i] =
                model::Brdf::<f32>::pdf(&self.0, [ox[i], oy[i], oz[i]], [ix[i], iy[i], iz[i]], s);
        }
    }
}

fn generic<B: BrdfForm>(b: B) -> Box<dyn Imp> {
    Box::new(Generic(Scalar(b)))
}

/// Elements per chunk of the threaded calls (fixed, so the split does not depend on the
/// thread count; the values would not either: every element is computed alone).
const PAR_CHUNK: usize = 4096;

/// Batched sampling and densities of one BRDF with fixed parameters, in f32, over
/// structure-of-arrays slices.
pub struct Sampler {
    id: &'static str,
    plan: BrdfPlan,
    imp: Box<dyn Imp>,
    /// The SIMD path of `vndf` (Cook-Torrance with GGX), where it applies.
    simd: Option<Simd>,
    /// Whether `simd` is used (`set_simd`).
    simd_on: bool,
}

/// Cook-Torrance with GGX, `vndf`: the vectorised sampler and the eval kernel of the weight.
struct Simd {
    vndf: ggx::Vndf,
    kernel: Kernel,
    isa: Isa,
}

/// Elements per block of the SIMD path (its scratch, the normalised `wo`, stays in L1).
const BLOCK: usize = 512;

/// The closed-form weight `4 k G2 / G1(wo)` of the unit tier (`ggx`'s header), where the
/// model has one: no Fresnel term, no energy compensation, G the exact separable or
/// height-correlated Smith term of GGX. Else `None`: the weight is `f cos_i / pdf` with `f`
/// from the eval kernel.
fn closed_weight(ct: &crate::brdf::cook_torrance::CookTorrance) -> Option<ggx::Weight> {
    use crate::microfacet::ms::Ms;
    use crate::plan::{FresnelPlan, ShadowPlan};
    let correlated = match ct.g {
        ShadowPlan::SmithGgx(_) => false,
        ShadowPlan::SmithGgxCorrelated(_) => true,
        _ => return None,
    };
    (matches!(ct.f, FresnelPlan::None(_)) && matches!(ct.ms, Ms::None)).then_some(ggx::Weight {
        scale: (4.0 * ct.k.x) as f32,
        correlated,
    })
}

impl Sampler {
    /// A BRDF spec (kind brdf; anything else: an error naming the kind, as `Kernel::new`
    /// does; a coloured spec: an error, build one sampler per channel).
    pub fn new(spec: &crate::spec::ModelSpec) -> Result<Self> {
        Self::from_plan(spec.id(), spec.plan()?)
    }

    /// The sampler of a plan (`id` names it in messages).
    pub fn from_plan(id: &'static str, plan: &Plan) -> Result<Self> {
        let Plan::Brdf(b) = plan else {
            return Err(Error::WrongKind {
                model: id.into(),
                expected: Kind::Brdf.name().into(),
                found: plan.kind().name().into(),
            });
        };
        let simd = match b {
            BrdfPlan::CookTorrance(ct) if matches!(ct.d, DistPlan::Ggx(_)) => {
                // `CookTorrance::micro`: D's slopes, stretched when anisotropic.
                let mut m = ct.d.sampler().micro;
                if let Some(a) = &ct.aniso {
                    m.ax *= a.x_over_y.x.sqrt();
                    m.ay *= a.y_over_x.x.sqrt();
                }
                let mut vndf = ggx::Vndf::new(&m);
                vndf.weight = closed_weight(ct);
                Some(Simd {
                    vndf,
                    kernel: Kernel::from_plan(id, plan)?,
                    isa: Isa::best(),
                })
            }
            _ => None,
        };
        Ok(Self {
            id,
            plan: *b,
            imp: with_brdf!(b, x => generic(*x)),
            simd,
            simd_on: true,
        })
    }

    /// The model id.
    pub fn id(&self) -> &'static str {
        self.id
    }

    /// Whether strategy `s` runs a SIMD path (Cook-Torrance with GGX and `vndf`, or `auto`
    /// there): its directions and weights then agree with the scalar sampler within the
    /// documented tolerance instead of bit for bit (module header). Else the generic path.
    pub fn simd(&self, s: Strategy) -> bool {
        self.simd_on && self.simd.is_some() && self.resolve(s).ok() == Some(Strategy::Vndf)
    }

    /// Turns the SIMD path off (the generic path everywhere: the scalar values bit for bit)
    /// or back on; for tests and measurements.
    #[doc(hidden)]
    pub fn set_simd(&mut self, on: bool) {
        self.simd_on = on;
    }

    /// The SIMD path for the resolved `s`, if it runs.
    fn simd_for(&self, s: Strategy) -> Option<&Simd> {
        self.simd
            .as_ref()
            .filter(|_| self.simd_on && s == Strategy::Vndf)
    }

    /// `sample` on this thread with the resolved strategy, lengths checked.
    fn sample_seq(&self, s: Strategy, wo: [&[f32]; 3], u: [&[f32]; 2], out: SampleOut<'_>) {
        let Some(simd) = self.simd_for(s) else {
            return self.imp.sample(s, wo, u, out);
        };
        let n = out.weight.len();
        let SampleOut { wi, weight, pdf } = out;
        let [wx, wy, wz] = wi;
        let mut won = [[0.0f32; BLOCK]; 3];
        let mut f_buf = [0.0f32; BLOCK];
        for lo in (0..n).step_by(BLOCK) {
            let hi = (lo + BLOCK).min(n);
            let m = hi - lo;
            let [nx, ny, nz] = &mut won;
            ggx::sample_block(
                simd.isa,
                &simd.vndf,
                ggx::SampleBlock {
                    wo: wo.map(|x| &x[lo..hi]),
                    u: u.map(|x| &x[lo..hi]),
                    won: [&mut nx[..m], &mut ny[..m], &mut nz[..m]],
                    wi: [&mut wx[lo..hi], &mut wy[lo..hi], &mut wz[lo..hi]],
                    pdf: &mut pdf[lo..hi],
                    weight: &mut weight[lo..hi],
                },
            );
            let w = &mut weight[lo..hi];
            if !w.iter().fold(false, |a, x| a | x.is_nan()) {
                continue; // every weight in closed form (the unit tier)
            }
            let f = &mut f_buf[..m];
            let input = Input::Dirs([
                &wx[lo..hi],
                &wy[lo..hi],
                &wz[lo..hi],
                &won[0][..m],
                &won[1][..m],
                &won[2][..m],
            ]);
            // Lengths are equal by construction: the kernel cannot refuse them.
            if simd.kernel.eval(input, f).is_err() {
                f.fill(0.0);
            }
            ggx::weight_block(simd.isa, &wz[lo..hi], &pdf[lo..hi], f, w);
        }
    }

    /// `pdf` on this thread with the resolved strategy, lengths checked.
    fn pdf_seq(&self, s: Strategy, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
        match self.simd_for(s) {
            Some(simd) => ggx::pdf_block(simd.isa, &simd.vndf, wo, wi, out),
            None => self.imp.pdf(s, wo, wi, out),
        }
    }

    /// The strategies the BRDF supports, its default first (as `Brdf::strategies`).
    pub fn strategies(&self) -> &'static [Strategy] {
        self.plan.strategies()
    }

    /// `s` with `auto` replaced by the default, or `Brdf::resolve`'s message as an error.
    fn resolve(&self, s: Strategy) -> Result<Strategy> {
        model::Brdf::<f32>::resolve(&Scalar(self.plan), s).map_err(|reason| Error::Domain {
            input: "strategy".into(),
            reason: format!("{reason} ({})", self.id),
        })
    }

    fn lengths(n: usize, ins: &[&[f32]], outs_ok: bool) -> Result<()> {
        if outs_ok && ins.iter().all(|s| s.len() == n) {
            Ok(())
        } else {
            Err(Error::Domain {
                input: "batch".into(),
                reason: format!(
                    "slice lengths differ (inputs {:?}, output {n})",
                    ins.iter().map(|s| s.len()).collect::<Vec<_>>()
                ),
            })
        }
    }

    fn check_sample(
        &self,
        s: Strategy,
        wo: &[&[f32]; 3],
        u: &[&[f32]; 2],
        out: &SampleOut<'_>,
    ) -> Result<Strategy> {
        let n = out.weight.len();
        Self::lengths(n, &[wo[0], wo[1], wo[2], u[0], u[1]], out.len_ok(n))?;
        self.resolve(s)
    }

    fn check_pdf(
        &self,
        s: Strategy,
        wo: &[&[f32]; 3],
        wi: &[&[f32]; 3],
        out: &[f32],
    ) -> Result<Strategy> {
        Self::lengths(out.len(), &[wo[0], wo[1], wo[2], wi[0], wi[1], wi[2]], true)?;
        self.resolve(s)
    }

    /// Per element `i`: draws `wi` given `wo = (wo[0][i], wo[1][i], wo[2][i])` and
    /// `u = (u[0][i], u[1][i])` by `s` (`Strategy::Auto`: the default), with the meaning of
    /// `Brdf::<f32>::sample`; no sample there (`None`: `wo` zero, NaN or below `COS_MIN`, or
    /// the draw below the horizon or of density 0) gives `wi = 0`, `weight = 0`, `pdf = 0`.
    /// `u` outside [0, 1) is clamped as the scalar sampler does (NaN as 0). Errors: unequal
    /// lengths, or a strategy the BRDF does not support (`Brdf::resolve`'s message).
    pub fn sample(
        &self,
        s: Strategy,
        wo: [&[f32]; 3],
        u: [&[f32]; 2],
        out: SampleOut<'_>,
    ) -> Result<()> {
        let s = self.check_sample(s, &wo, &u, &out)?;
        self.sample_seq(s, wo, u, out);
        Ok(())
    }

    /// Per element: `Brdf::<f32>::pdf(wo, wi, s)` (0 out of the domain). Errors as
    /// [`Self::sample`].
    pub fn pdf(
        &self,
        s: Strategy,
        wo: [&[f32]; 3],
        wi: [&[f32]; 3],
        out: &mut [f32],
    ) -> Result<()> {
        let s = self.check_pdf(s, &wo, &wi, out)?;
        self.pdf_seq(s, wo, wi, out);
        Ok(())
    }

    /// [`Self::sample`] split over rayon's threads in fixed chunks of 4096 elements: the
    /// same values, bit for bit, whatever the thread count.
    pub fn sample_par(
        &self,
        s: Strategy,
        wo: [&[f32]; 3],
        u: [&[f32]; 2],
        out: SampleOut<'_>,
    ) -> Result<()> {
        let s = self.check_sample(s, &wo, &u, &out)?;
        let SampleOut { wi, weight, pdf } = out;
        let [wx, wy, wz] = wi;
        let c = PAR_CHUNK;
        wx.par_chunks_mut(c)
            .zip(wy.par_chunks_mut(c))
            .zip(wz.par_chunks_mut(c))
            .zip(weight.par_chunks_mut(c))
            .zip(pdf.par_chunks_mut(c))
            .enumerate()
            .for_each(|(k, ((((x, y), z), f), p))| {
                let (lo, hi) = (k * c, k * c + x.len());
                let out = SampleOut {
                    wi: [x, y, z],
                    weight: f,
                    pdf: p,
                };
                self.sample_seq(s, wo.map(|w| &w[lo..hi]), u.map(|w| &w[lo..hi]), out);
            });
        Ok(())
    }

    /// [`Self::pdf`] split over rayon's threads in fixed chunks of 4096 elements: the same
    /// values, bit for bit, whatever the thread count.
    pub fn pdf_par(
        &self,
        s: Strategy,
        wo: [&[f32]; 3],
        wi: [&[f32]; 3],
        out: &mut [f32],
    ) -> Result<()> {
        let s = self.check_pdf(s, &wo, &wi, out)?;
        out.par_chunks_mut(PAR_CHUNK)
            .enumerate()
            .for_each(|(k, o)| {
                let lo = k * PAR_CHUNK;
                let hi = lo + o.len();
                self.pdf_seq(s, wo.map(|x| &x[lo..hi]), wi.map(|x| &x[lo..hi]), o);
            });
        Ok(())
    }
}
