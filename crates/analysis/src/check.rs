//! `fastbrdf check`: every documented bound of the registry re-measured on this machine.
//! Four families of checks:
//! - error against the reference model: a dense grid plus golden-section refinement over the
//!   bound's parameter range (`fastbrdf::accuracy::worst`) and an adversarial search over the
//!   parameter as a continuum and the input together (`accuracy::worst_search`); the larger
//!   maximum counts;
//! - f32 against f64 on the same inputs over the whole documented domain, mixed metric
//!   `|v32 - v64| / max(1, |v64|)`: a grid of parameter sets (`accuracy::f32_worst` over
//!   `accuracy::domain_configs`) and an adversarial search (`accuracy::f32_search`, seeded, so
//!   reproducible). The search also fails a model that returns a non-finite or negative
//!   value in either precision.
//! - the corners of the domain (issue 27, [`corners`]): every model at its domain
//!   configurations (and, for `eta`, at decimals near 1 that f32 does not hold, as a user
//!   types them) evaluated at the ends of the input ranges, where a random search seldom
//!   lands: zero, subnormal and tiny cosines, grazing and normal incidence, the issue's
//!   points. Its maximum counts in the f32 row like the grid's and the search's.
//! - the batch kernels (the SIMD code `eval` runs) against f64 on every instruction set of
//!   this CPU ([`kernel_bound`], `accuracy::kernel_worst`): the f32 grid at every domain
//!   configuration and at the one where the f32 search found its worst, the ends of the input
//!   ranges, and invalid inputs (which must give finite, non-negative values), held to the
//!   model's f32 bound.

use fastbrdf::entry::Entry;
use fastbrdf::{ErrorBound, Given, Metric, ModelSpec, Zone, accuracy};
use rayon::prelude::*;
use serde::Serialize;

/// One documented error bound against its reference, re-measured.
#[derive(Clone, Debug, Serialize)]
pub struct BoundRow {
    pub model: &'static str,
    pub reference: &'static str,
    pub metric: Metric,
    pub zone: Zone,
    pub param: (&'static str, f64, f64),
    pub documented: f64,
    pub measured: f64,
    pub at_param: f64,
    pub at_x: f64,
    pub samples: usize,
    pub ok: bool,
}

/// One model's f32 against f64 bound, re-measured.
#[derive(Clone, Debug, Serialize)]
pub struct F32Row {
    pub model: &'static str,
    pub documented: f64,
    /// The larger of the grid's and the search's maximum (`null` in JSON if infinite).
    pub measured: f64,
    pub configurations: usize,
    /// Evaluations (each in both precisions) of the adversarial search.
    pub evaluations: usize,
    /// Evaluations (each in both precisions) at the domain's corners ([`corners`]).
    pub corners: usize,
    pub at: String,
    /// Every value found finite and non-negative in both precisions.
    pub finite: bool,
    /// Where a non-finite or negative value was found ("" when none).
    pub invalid: String,
    pub ok: bool,
}

/// One model's batch kernel against f64 on every instruction set of this CPU, re-measured
/// (no row for a shadowing term: it has no kernel of its own).
#[derive(Clone, Debug, Serialize)]
pub struct KernelRow {
    pub model: &'static str,
    /// The model's f32 bound: its kernels are held to it as its scalar f32 model is.
    pub documented: f64,
    /// The largest `|kernel - f64| / max(1, |f64|)` over every configuration, input and
    /// instruction set (`null` in JSON if infinite).
    pub measured: f64,
    /// The instruction sets measured, best first (`avx512`, `avx2+fma`, `sse2`).
    pub isas: Vec<&'static str>,
    pub configurations: usize,
    /// Kernel values compared or checked, all instruction sets together.
    pub evaluations: usize,
    pub at: String,
    /// Every kernel value finite and non-negative, invalid inputs included.
    pub finite: bool,
    /// Where a non-finite or negative value was found ("" when none).
    pub invalid: String,
    pub ok: bool,
}

/// Every row of a check.
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub bounds: Vec<BoundRow>,
    pub f32: Vec<F32Row>,
    pub kernels: Vec<KernelRow>,
}

impl CheckReport {
    /// Whether every bound holds.
    pub fn ok(&self) -> bool {
        self.bounds.iter().all(|r| r.ok)
            && self.f32.iter().all(|r| r.ok)
            && self.kernels.iter().all(|r| r.ok)
    }

    /// `fastbrdf check --json`'s object, `{"ok", "bounds", "f32", "kernels"}` (the CLI and
    /// the Python package print this one value).
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "ok": self.ok(),
            "bounds": self.bounds,
            "f32": self.f32,
            "kernels": self.kernels,
        })
    }

    /// How many bounds hold, of how many.
    pub fn holding(&self) -> (usize, usize) {
        let held = self.bounds.iter().filter(|r| r.ok).count()
            + self.f32.iter().filter(|r| r.ok).count()
            + self.kernels.iter().filter(|r| r.ok).count();
        (
            held,
            self.bounds.len() + self.f32.len() + self.kernels.len(),
        )
    }
}

/// The bound `b` of model `e`, re-measured: the worse of the grid and the search.
pub fn bound(e: &'static Entry, b: &'static ErrorBound, size: accuracy::SearchSize) -> BoundRow {
    let grid = accuracy::worst(e.info.id, b).expect("registry bounds name valid models");
    let found =
        accuracy::worst_search(e.info.id, b, size).expect("registry bounds name valid models");
    let w = accuracy::Worst {
        samples: grid.samples + found.samples,
        ..if found.err > grid.err { found } else { grid }
    };
    BoundRow {
        model: e.info.id,
        reference: b.reference,
        metric: b.metric,
        zone: b.zone,
        param: b.param,
        documented: b.bound,
        measured: w.err,
        at_param: w.param,
        at_x: w.x,
        samples: w.samples,
        ok: w.err <= b.bound,
    }
}

/// A spec's given values as `k=v k=v` (how `check` names a configuration; empty when none
/// is given).
pub fn fmt_params(spec: &ModelSpec) -> String {
    let kv: Vec<String> = spec
        .given()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    kv.join(" ")
}

/// Model `e`'s f32 bound, re-measured: the worst of the grid of parameter sets and the search.
pub fn f32_bound(e: &'static Entry, size: accuracy::SearchSize) -> F32Row {
    f32_bound_at(e, size).0
}

/// [`f32_bound`] and the configuration the search found its worst at (the kernels are
/// measured there too: [`run`]).
fn f32_bound_at(e: &'static Entry, size: accuracy::SearchSize) -> (F32Row, Option<ModelSpec>) {
    let configs = accuracy::domain_configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf);
    let mut worst = (0.0, String::new());
    for c in &configs {
        let (err, at) = accuracy::f32_worst(c).expect("domain configurations are valid");
        if err.is_nan() || err > worst.0 || worst.1.is_empty() {
            worst = (err, format!("{} {at}", fmt_params(c)));
        }
    }
    let found = accuracy::f32_search(&e.info, size);
    if found.err > worst.0 {
        worst = (
            found.err,
            format!(
                "{} {}",
                found.spec.as_ref().map(fmt_params).unwrap_or_default(),
                found.at
            ),
        );
    }
    let corner = corners(&e.info);
    if corner.err > worst.0 {
        worst = (corner.err, corner.at.clone());
    }
    let invalid = found.invalid.clone().or(corner.invalid.clone());
    let row = F32Row {
        model: e.info.id,
        documented: e.info.f32_bound,
        measured: worst.0,
        configurations: configs.len(),
        evaluations: found.evaluations,
        corners: corner.evaluations,
        at: worst.1,
        finite: invalid.is_none(),
        ok: worst.0 <= e.info.f32_bound && invalid.is_none(),
        invalid: invalid.unwrap_or_default(),
    };
    (row, found.spec)
}

/// Model `e`'s batch kernel against f64 on every instruction set of this CPU, at every
/// domain configuration and at `also` (`accuracy::kernel_worst`; [`run`] passes the
/// configuration where the f32 search found its worst, e.g. `n = 1e5`, beyond the grid's
/// rows); `None` for a shadowing term.
pub fn kernel_bound(e: &'static Entry, also: &[ModelSpec]) -> Option<KernelRow> {
    if !has_kernel(e) {
        return None;
    }
    let mut configs = accuracy::domain_configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf);
    configs.extend(also.iter().filter(|c| !c.is_coloured()).cloned());
    let mut row = KernelRow {
        model: e.info.id,
        documented: e.info.f32_bound,
        measured: 0.0,
        isas: Vec::new(),
        configurations: configs.len(),
        evaluations: 0,
        at: String::new(),
        finite: true,
        invalid: String::new(),
        ok: false,
    };
    for c in &configs {
        let w = accuracy::kernel_worst(c)
            .expect("domain configurations are valid")
            .expect("a kernel for every kind but shadowing");
        row.evaluations += w.evaluations;
        row.isas = w.isas;
        if !(w.err <= row.measured) || row.at.is_empty() {
            row.measured = w.err;
            row.at = format!("{} {}", fmt_params(c), w.at).trim().to_string();
        }
        if let (Some(bad), true) = (w.invalid, row.finite) {
            row.finite = false;
            row.invalid = format!("{} {bad}", fmt_params(c)).trim().to_string();
        }
    }
    row.ok = row.finite && row.measured <= row.documented;
    Some(row)
}

/// Whether `e` has a batch kernel of its own (every kind but a shadowing term).
fn has_kernel(e: &Entry) -> bool {
    e.info.kind != fastbrdf::Kind::Shadowing
}

/// Cosines at the ends of `[0, 1]`: 0, subnormal (`1e-45` is the smallest f32), the smallest
/// normal, tiny, grazing (issue 27's `0.003908168`), and 1 and its neighbour.
pub const CORNER_COS: [f32; 19] = [
    0.0,
    1e-45,
    1e-42,
    1e-39,
    1.175_494_4e-38,
    1e-30,
    1e-20,
    1e-10,
    1e-7,
    1e-5,
    1e-4,
    0.003_908_168,
    0.01,
    0.1,
    0.5,
    0.9,
    0.999,
    0.999_999_94,
    1.0,
];

/// Decimals near `eta = 1` that f32 does not hold: the f64 model reads them as given, the f32
/// model their rounding, as `--param eta=1.0001` does (issue 27: the Fresnel terms computed
/// `eta^2 - 1` from that rounding, 30 times their f32 bound off at grazing).
pub const CORNER_ETAS: [f64; 4] = [1.0001, 0.9999, 1.000001, 0.999999];

/// The worst f32-against-f64 error at the corners.
#[derive(Clone, Debug, Default)]
pub struct Corners {
    pub err: f64,
    pub at: String,
    /// A non-finite or negative value found there.
    pub invalid: Option<String>,
    pub evaluations: usize,
}

/// The parameter sets of the corners: `accuracy::domain_configs`, and each configuration
/// with an `eta` again at every [`CORNER_ETAS`] value (once per configuration of its other
/// values).
pub fn corner_configs(info: &fastbrdf::ModelInfo) -> Vec<ModelSpec> {
    let mut out = accuracy::domain_configs(info, info.kind == fastbrdf::Kind::Brdf);
    let with_eta: Vec<ModelSpec> = out
        .iter()
        .filter(|c| c.get("eta").is_some())
        .cloned()
        .collect();
    let mut seen = std::collections::BTreeSet::new();
    for c in with_eta {
        // The configuration without its eta: each is given the corner etas once.
        let others: Vec<(String, String)> =
            c.pairs().into_iter().filter(|(k, _)| k != "eta").collect();
        if !seen.insert(others) {
            continue;
        }
        for eta in CORNER_ETAS {
            // A combination the model refuses is not part of its domain.
            if let Ok(c) = c.with("eta", Given::Num(eta)) {
                out.push(c);
            }
        }
    }
    out
}

/// The directions of a BRDF's corner pairs: `wi` at the cosines `CORNER_COS` (above 0), `wo`
/// at the same cosines at azimuths 0, 1e-3, pi/2, pi - 1e-3 and pi from `wi`'s (the mirror
/// pair, back to back and near both).
fn corner_pairs() -> Vec<([f32; 3], [f32; 3])> {
    let dir = |c: f32, phi: f64| {
        let c = c as f64;
        let s = ((1.0 - c) * (1.0 + c)).sqrt();
        [(s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32]
    };
    let pi = std::f64::consts::PI;
    let mut out = vec![];
    for &ci in &CORNER_COS[1..] {
        for &co in &CORNER_COS[1..] {
            for phi in [0.0, 1e-3, 0.5 * pi, pi - 1e-3, pi] {
                out.push((dir(ci, 0.0), dir(co, phi)));
            }
        }
    }
    out
}

/// Model `info` in both precisions at every [`corner_configs`] configuration and every corner
/// input of its kind: cosines of [`CORNER_COS`] (lobes, distributions, Fresnel terms), all
/// combinations of them as `cos_v`, `cos_h`, `cos_vh` and `cos_l` (absent or a corner:
/// shadowing), with `alpha` at its ends (env terms), and [`corner_pairs`] (BRDFs). Mixed metric
/// `|v32 - v64| / max(1, |v64|)`; a non-finite or negative value is recorded as invalid.
pub fn corners(info: &fastbrdf::ModelInfo) -> Corners {
    use fastbrdf::{Model, model::ShadowInput};
    let mut out = Corners::default();
    let note = |out: &mut Corners, v32: f32, v64: f64, at: &dyn Fn() -> String| {
        out.evaluations += 1;
        if !(v32.is_finite() && v32 >= 0.0 && v64.is_finite() && v64 >= 0.0) {
            if out.invalid.is_none() {
                out.invalid = Some(format!("corner: {} f32={v32} f64={v64}", at()));
            }
            return;
        }
        let e = (f64::from(v32) - v64).abs() / v64.abs().max(1.0);
        if e > out.err || out.at.is_empty() {
            out.err = e;
            out.at = format!("corner: {} f32={v32} f64={v64}", at());
        }
    };
    let (alo, ahi) = fastbrdf::params::ALPHA.range();
    for c in corner_configs(info) {
        let (Ok(m32), Ok(m64)) = (c.model::<f32>(), c.model::<f64>()) else {
            continue; // a combination the model refuses: not part of its domain
        };
        let p = fmt_params(&c);
        match (&m32, &m64) {
            (Model::Lobe(a), Model::Lobe(b)) => {
                for x in CORNER_COS {
                    note(&mut out, a.eval(x), b.eval(x as f64), &|| {
                        format!("{p} c={x:e}")
                    });
                }
            }
            (Model::Distribution(a), Model::Distribution(b)) => {
                for x in CORNER_COS {
                    note(&mut out, a.eval(x), b.eval(x as f64), &|| {
                        format!("{p} cos_h={x:e}")
                    });
                }
            }
            (Model::Fresnel(a), Model::Fresnel(b)) => {
                for x in CORNER_COS {
                    note(&mut out, a.f(x), b.f(x as f64), &|| {
                        format!("{p} cos={x:e}")
                    });
                }
            }
            (Model::Shadowing(a), Model::Shadowing(b)) => {
                let ls = std::iter::once(None).chain(CORNER_COS.iter().map(|&l| Some(l)));
                for l in ls {
                    for v in CORNER_COS {
                        for h in CORNER_COS {
                            for vh in CORNER_COS {
                                let s32 = ShadowInput {
                                    cos_v: v,
                                    cos_l: l,
                                    cos_h: h,
                                    cos_vh: vh,
                                };
                                let s64 = ShadowInput {
                                    cos_v: v as f64,
                                    cos_l: l.map(f64::from),
                                    cos_h: h as f64,
                                    cos_vh: vh as f64,
                                };
                                note(&mut out, a.g(&s32), b.g(&s64), &|| format!("{p} {s32:?}"));
                            }
                        }
                    }
                }
            }
            (Model::Env(a), Model::Env(b)) => {
                for al in [alo, 0.01, 0.5, ahi] {
                    let al = al as f32;
                    for x in CORNER_COS {
                        note(&mut out, a.e(x, al), b.e(x as f64, al as f64), &|| {
                            format!("{p} cos_v={x:e} alpha={al}")
                        });
                    }
                }
            }
            (Model::Brdf(a), Model::Brdf(b)) => {
                for (wi, wo) in corner_pairs() {
                    let v32 = a.eval(wi, wo);
                    let v64 = b.eval(wi.map(f64::from), wo.map(f64::from));
                    note(&mut out, v32, v64, &|| format!("{p} wi={wi:?} wo={wo:?}"));
                }
            }
            _ => unreachable!("both precisions build the same kind"),
        }
    }
    out
}

/// How many steps [`run`] reports to `progress` for `entries`: one per error bound, one per
/// model, and one per model with a kernel.
pub fn steps(entries: &[&'static Entry]) -> usize {
    entries
        .iter()
        .map(|e| e.info.bounds.len() + 1 + usize::from(has_kernel(e)))
        .sum()
}

/// Re-measures every bound of `entries`, in parallel; `progress` is called [`steps`] times.
pub fn run(
    entries: &[&'static Entry],
    size: accuracy::SearchSize,
    progress: &(dyn Fn() + Sync),
) -> CheckReport {
    let bound_jobs: Vec<_> = entries
        .iter()
        .flat_map(|e| e.info.bounds.iter().map(move |b| (*e, b)))
        .collect();
    let bounds = bound_jobs
        .par_iter()
        .map(|(e, b)| {
            let r = bound(e, b, size);
            progress();
            r
        })
        .collect();
    let (f32, worst): (Vec<F32Row>, Vec<Option<ModelSpec>>) = entries
        .par_iter()
        .map(|e| {
            let r = f32_bound_at(e, size);
            progress();
            r
        })
        .unzip();
    let kernels = entries
        .par_iter()
        .zip(&worst)
        .filter_map(|(e, w)| {
            let r = kernel_bound(e, w.as_slice())?;
            progress();
            Some(r)
        })
        .collect();
    CheckReport {
        bounds,
        f32,
        kernels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf::registry;
    use std::sync::atomic::{AtomicUsize, Ordering};

    const SMALL: accuracy::SearchSize = accuracy::SearchSize {
        restarts: 2,
        steps: 40,
        seed: 7,
    };

    #[test]
    fn a_check_measures_every_bound_of_its_models() {
        let entries = vec![
            registry::find("schlick").unwrap(),
            registry::find("flog").unwrap(),
        ];
        let calls = AtomicUsize::new(0);
        let r = run(&entries, SMALL, &|| {
            calls.fetch_add(1, Ordering::Relaxed);
        });
        let n_bounds: usize = entries.iter().map(|e| e.info.bounds.len()).sum();
        assert!(n_bounds >= 2);
        assert_eq!(r.bounds.len(), n_bounds);
        assert_eq!(r.f32.len(), 2);
        assert_eq!(r.kernels.len(), 2);
        assert_eq!(calls.load(Ordering::Relaxed), steps(&entries));
        assert_eq!(steps(&entries), n_bounds + 4);
        for b in &r.bounds {
            // An approximation differs from its reference somewhere, within its bound.
            assert!(b.measured > 0.0 && b.measured <= b.documented, "{b:?}");
            assert!(b.ok && b.samples > 0);
            assert!(b.at_param >= b.param.1 && b.at_param <= b.param.2, "{b:?}");
        }
        for f in &r.f32 {
            assert!(f.finite && f.ok && f.invalid.is_empty(), "{f:?}");
            assert!(f.measured >= 0.0 && f.measured <= f.documented, "{f:?}");
            assert!(f.configurations > 0 && f.evaluations > 0);
        }
        for k in &r.kernels {
            assert!(k.finite && k.ok && k.invalid.is_empty(), "{k:?}");
            assert!(k.measured >= 0.0 && k.measured <= k.documented, "{k:?}");
            assert_eq!(
                k.isas,
                fastbrdf::batch::Isa::available()
                    .iter()
                    .map(|i| i.name())
                    .collect::<Vec<_>>()
            );
            assert!(
                k.configurations > 0 && k.evaluations > k.configurations,
                "{k:?}"
            );
        }
        assert!(r.ok());
        assert_eq!(r.holding(), (n_bounds + 4, n_bounds + 4));
    }

    #[test]
    fn one_exceeded_bound_fails_the_check() {
        let e = registry::find("schlick").unwrap();
        let mut r = CheckReport {
            bounds: vec![bound(e, &e.info.bounds[0], SMALL)],
            f32: vec![f32_bound(e, SMALL)],
            kernels: vec![kernel_bound(e, &[]).unwrap()],
        };
        assert!(r.ok());
        r.f32[0].ok = false;
        assert!(!r.ok());
        assert_eq!(r.holding(), (2, 3));
        r.f32[0].ok = true;
        r.kernels[0].ok = false;
        assert!(!r.ok());
        assert_eq!(r.holding(), (2, 3));
    }

    /// Issue 27: the corners reach the points the search missed (`fresnel-dielectric` at
    /// `eta = 1.0001` as typed, `cos = 0.003908168`; `v-cavity` at a subnormal `cos_vh` with
    /// `cos_v` of a smaller order), and the models hold their f32 bounds there. Failed before
    /// the fixes of `microfacet::fresnel` and `shadowing::VCavity` (3e-5 and 1 measured).
    #[test]
    fn corners_reach_the_ends_of_the_domain_and_hold() {
        let d = registry::find("fresnel-dielectric").unwrap();
        let configs = corner_configs(&d.info);
        assert!(
            configs
                .iter()
                .any(|c| c.pairs() == [("eta".to_string(), "1.0001".to_string())]),
            "{configs:?}"
        );
        assert!(CORNER_COS.contains(&0.003_908_168));
        assert!(CORNER_COS.iter().any(|&c| c > 0.0 && c < f32::MIN_POSITIVE));
        for id in ["fresnel-dielectric", "fresnel-conductor", "v-cavity"] {
            let e = registry::find(id).unwrap();
            let c = corners(&e.info);
            assert!(c.evaluations > 0 && c.invalid.is_none(), "{id}: {c:?}");
            assert!(c.err <= e.info.f32_bound, "{id}: {c:?}");
            let row = f32_bound(e, SMALL);
            assert!(row.ok && row.corners == c.evaluations, "{row:?}");
        }
    }

    /// Every model of the registry holds its f32 bound at the corners, finite and
    /// non-negative in both precisions.
    #[test]
    fn every_model_holds_its_f32_bound_at_the_corners() {
        let mut bad = vec![];
        for e in registry::all() {
            let c = corners(&e.info);
            eprintln!(
                "{:<28} {:>9.3e} {:>8} {}",
                e.info.id, c.err, c.evaluations, c.at
            );
            if c.invalid.is_some() || c.err > e.info.f32_bound || c.evaluations == 0 {
                bad.push(format!("{}: {c:?}", e.info.id));
            }
        }
        assert!(bad.is_empty(), "{}", bad.join("\n"));
    }

    /// Every model's batch kernel holds its model's f32 bound against f64, on every
    /// instruction set of this CPU, finite and non-negative on invalid inputs too; the
    /// measurement is not vacuous (an error above zero somewhere, every input evaluated).
    #[test]
    fn every_kernel_holds_its_f32_bound_on_every_isa() {
        let mut bad = vec![];
        for e in registry::all() {
            let Some(k) = kernel_bound(e, &[]) else {
                assert_eq!(e.info.kind, fastbrdf::Kind::Shadowing);
                continue;
            };
            eprintln!(
                "{:<28} {:>9.3e} {:>8} {}",
                k.model, k.measured, k.evaluations, k.at
            );
            if !k.ok {
                bad.push(format!("{k:?}"));
            }
        }
        assert!(bad.is_empty(), "{}", bad.join("\n"));
        let ct = kernel_bound(registry::find("cook-torrance").unwrap(), &[]).unwrap();
        let isa = fastbrdf::batch::Isa::available()[0].name();
        assert!(ct.measured > 0.0 && ct.at.contains(isa), "{ct:?}");
    }

    /// `run` measures each kernel also where the f32 search found the scalar model's worst
    /// (for phong often at the domain's n = 1e5, beyond the BRDF grid's rows), and it holds
    /// there.
    #[test]
    fn the_kernels_are_measured_where_the_f32_search_found_its_worst() {
        let e = registry::find("phong").unwrap();
        let worst = f32_bound_at(e, SMALL)
            .1
            .expect("the search names its configuration");
        let plain = kernel_bound(e, &[]).unwrap();
        let k = kernel_bound(e, std::slice::from_ref(&worst)).unwrap();
        assert_eq!(k.configurations, plain.configurations + 1);
        assert!(k.evaluations > plain.evaluations && k.ok, "{k:?}");
        let r = run(&[e], SMALL, &|| ());
        assert_eq!(
            r.kernels[0].configurations, k.configurations,
            "{:?}",
            r.kernels
        );
    }

    #[test]
    fn configurations_are_named_by_their_parameters() {
        let p = ModelSpec::parse("blinn-phong", &[("n", "20"), ("norm", "none")]).unwrap();
        assert_eq!(fmt_params(&p), "n=20 norm=none");
        assert_eq!(fmt_params(&ModelSpec::parse("flog", &[]).unwrap()), "");
    }
}
