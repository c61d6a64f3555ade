//! f32 against f64: the mixed error `|v32 - v64| / max(1, |v64|)` ([`super::mixed_error`])
//! of one model spec over inputs covering its domain ([`f32_worst`]), and an adversarial
//! search over a model's whole documented domain ([`f32_search`]).

use super::configs::{choice_sets, special_values};
use super::{
    SearchSize, direction_pairs, lobe_samples, mixed_error, param_at, param_q, samples, splitmix,
};
use crate::error::Result;
use crate::model::Model;
use crate::spec::{Given, ModelSpec};

/// The worst mixed f32-vs-f64 error of one model configuration over inputs covering its
/// domain (the same f32 inputs fed to both precisions), and a description of where.
/// The lobe's samples are those of its given `n` (20 if not given), a distribution's those of
/// its given `alpha` (0.3 if not given). A coloured spec is an error (measure each of
/// `spec.channel_specs()`).
pub fn f32_worst(spec: &ModelSpec) -> Result<(f64, String)> {
    use crate::model::ShadowInput;
    let m32 = spec.model::<f32>()?;
    let m64 = spec.model::<f64>()?;
    let mut worst = (0.0, String::new());
    let mut note = |e: f64, what: &dyn Fn() -> String| {
        if !(e <= worst.0) {
            worst = (e, what());
        }
    };
    if let (Model::Shadowing(a), Model::Shadowing(b)) = (&m32, &m64) {
        for (wi, wo) in direction_pairs(400, 5) {
            let (s32, s64) = shadow_inputs(wi, wo, true);
            note(mixed_error(a.g(&s32), b.g(&s64)), &|| format!("{s32:?}"));
            let (o32, o64) = (
                ShadowInput { cos_l: None, ..s32 },
                ShadowInput { cos_l: None, ..s64 },
            );
            note(mixed_error(a.g(&o32), b.g(&o64)), &|| format!("{o32:?}"));
        }
        return Ok(worst);
    }
    let grid = Grid::of(spec, &m64).expect("every kind but shadowing has a grid");
    for i in 0..grid.len() {
        let (v32, v64) = (grid.eval(&m32, i), grid.eval(&m64, i));
        note(mixed_error(v32, v64), &|| grid.at(i));
    }
    Ok(worst)
}

/// The f32 inputs [`f32_worst`] measures a model (but a shadowing term) on, as columns (the
/// batch kernels' layout, which `super::kernels` feeds them in): a lobe's cosines, a
/// distribution's `cos_h`, a Fresnel term's `cos_vh`, a split-sum term's (`cos_v`, `alpha`),
/// a BRDF's direction pairs.
pub(super) struct Grid {
    pub(super) kind: GridKind,
    /// One column per input (1, 2 or 6).
    pub(super) cols: Vec<Vec<f32>>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum GridKind {
    Lobe,
    Distribution,
    Fresnel,
    Env,
    Brdf,
}

impl Grid {
    /// The grid of `spec` (its model in f64: `m64`); `None` for a shadowing term.
    pub(super) fn of(spec: &ModelSpec, m64: &Model<f64>) -> Option<Self> {
        let param = |name: &str, default: f64| match spec.get(name) {
            Some(Given::Num(x)) => *x,
            _ => default,
        };
        let one = |kind, xs: Vec<f32>| {
            Some(Self {
                kind,
                cols: vec![xs],
            })
        };
        match m64 {
            Model::Lobe(_) => one(
                GridKind::Lobe,
                lobe_samples(param("n", 20.0))
                    .into_iter()
                    .chain((0..=1000).map(|i| i as f64 / 1000.0))
                    .map(|c| c as f32)
                    .collect(),
            ),
            Model::Distribution(_) => one(
                GridKind::Distribution,
                samples(m64, param("alpha", 0.3))
                    .into_iter()
                    .map(|c| c as f32)
                    .collect(),
            ),
            Model::Fresnel(_) => one(
                GridKind::Fresnel,
                (0..=2000).map(|i| i as f32 / 2000.0).collect(),
            ),
            Model::Env(_) => {
                let (mut c, mut a) = (vec![], vec![]);
                for i in 0..=40 {
                    for j in 0..=20 {
                        c.push((i as f32 / 40.0).powi(2));
                        a.push(0.005f32 + (1.0 - 0.005) * (j as f32 / 20.0).powi(2));
                    }
                }
                Some(Self {
                    kind: GridKind::Env,
                    cols: vec![c, a],
                })
            }
            Model::Brdf(_) => {
                let mut cols = vec![Vec::new(); 6];
                for (wi, wo) in direction_pairs(600, 3) {
                    for k in 0..3 {
                        cols[k].push(wi[k] as f32);
                        cols[k + 3].push(wo[k] as f32);
                    }
                }
                Some(Self {
                    kind: GridKind::Brdf,
                    cols,
                })
            }
            Model::Shadowing(_) => None,
        }
    }

    pub(super) fn len(&self) -> usize {
        self.cols[0].len()
    }

    /// Input `k` of element `i`, and in f64 (the same value).
    pub(super) fn x(&self, i: usize, k: usize) -> f32 {
        self.cols[k][i]
    }
    pub(super) fn x64(&self, i: usize, k: usize) -> f64 {
        self.cols[k][i] as f64
    }

    /// Model `m` (f32 or f64, of the grid's kind) at element `i`: its f32 inputs, exactly.
    pub(super) fn eval<T: crate::real::Real>(&self, m: &Model<T>, i: usize) -> T {
        let x = |k: usize| T::c(self.x64(i, k));
        match m {
            Model::Lobe(l) => l.eval(x(0)),
            Model::Distribution(d) => d.eval(x(0)),
            Model::Fresnel(f) => f.f(x(0)),
            Model::Env(e) => e.e(x(0), x(1)),
            Model::Brdf(b) => b.eval([x(0), x(1), x(2)], [x(3), x(4), x(5)]),
            Model::Shadowing(_) => unreachable!("a shadowing term has no grid"),
        }
    }

    /// Element `i` of a BRDF's grid as (`wi`, `wo`).
    pub(super) fn pair(&self, i: usize) -> ([f32; 3], [f32; 3]) {
        (
            [self.x(i, 0), self.x(i, 1), self.x(i, 2)],
            [self.x(i, 3), self.x(i, 4), self.x(i, 5)],
        )
    }

    /// Where element `i` lies, as [`f32_worst`] reports it.
    pub(super) fn at(&self, i: usize) -> String {
        match self.kind {
            GridKind::Lobe => format!("c={}", self.x(i, 0)),
            GridKind::Distribution => format!("cos_h={}", self.x(i, 0)),
            GridKind::Fresnel => format!("cos={}", self.x(i, 0)),
            GridKind::Env => format!("cos_v={} alpha={}", self.x(i, 0), self.x(i, 1)),
            GridKind::Brdf => {
                let (wi, wo) = self.pair(i);
                format!("wi={wi:?} wo={wo:?}")
            }
        }
    }
}

/// What an adversarial search found: the largest mixed f32-vs-f64 error, where, and the
/// first non-finite or negative value (in either precision), if any.
#[derive(Clone, Debug, Default)]
pub struct Found {
    /// The largest `|v32 - v64| / max(1, |v64|)` found (infinite if a value was invalid).
    pub err: f64,
    /// The model spec where it occurs (`None` when no configuration was built).
    pub spec: Option<ModelSpec>,
    /// The input where it occurs.
    pub at: String,
    /// A non-finite or negative value found, with its parameters and input.
    pub invalid: Option<String>,
    /// Model evaluations (each in both precisions).
    pub evaluations: usize,
}

/// The f32 value nearest to `v` inside `[min, max]`, written so that f64 parses it exactly:
/// both precisions then build the same model (a parameter's own rounding to f32 is a
/// different model, not an arithmetic error).
fn f32_param(v: f64, min: f64, max: f64) -> f64 {
    let mut x = v.clamp(min, max) as f32;
    while (x as f64) < min {
        x = f32_step(x, true);
    }
    while (x as f64) > max {
        x = f32_step(x, false);
    }
    x as f64
}

/// The next f32 above (`up`) or below `x` (`f32::next_up` needs Rust 1.86; MSRV 1.85).
fn f32_step(x: f32, up: bool) -> f32 {
    if x == 0.0 {
        let tiny = f32::from_bits(1);
        if up { tiny } else { -tiny }
    } else if (x > 0.0) == up {
        f32::from_bits(x.to_bits() + 1)
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

/// A shadowing term's inputs for the unit pair (`wi`, `wo`): in f32, and the same f32 values
/// in f64 (both precisions are fed the same inputs). `with_l` gives the two-sided form `cos_l`.
fn shadow_inputs(
    wi: [f64; 3],
    wo: [f64; 3],
    with_l: bool,
) -> (
    crate::model::ShadowInput<f32>,
    crate::model::ShadowInput<f64>,
) {
    let s = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let s32 = crate::model::ShadowInput {
        cos_v: wo[2] as f32,
        cos_l: if with_l { Some(wi[2] as f32) } else { None },
        cos_h: (s[2] / len) as f32,
        cos_vh: (0.5 * len) as f32,
    };
    let s64 = crate::model::ShadowInput {
        cos_v: s32.cos_v as f64,
        cos_l: s32.cos_l.map(f64::from),
        cos_h: s32.cos_h as f64,
        cos_vh: s32.cos_vh as f64,
    };
    (s32, s64)
}

/// A cosine from `u` in [0, 1] in one of three densities: uniform, dense near 1
/// (`1 - u^6`: narrow lobes) and dense near 0 (`u^6`: grazing, down to 1e-36).
fn cos_at(u: f64, mode: usize) -> f64 {
    match mode % 3 {
        0 => u,
        1 => 1.0 - u.powi(6),
        _ => u.powi(6),
    }
}

/// The direction pair for a BRDF or shadowing term from `u[0..4]`: `wi` from its cosine
/// (`cos_at`, or log-uniform in [COS_MIN, 1] for grazing) and azimuth, `wo` the reflection of `wi` about a microfacet normal `h` at
/// `theta_h = (pi/2) u^3` (dense near the mirror direction). Every pair of the upper
/// hemisphere has such a form.
fn pair_at(u: &[f64], mode: usize, target: Target) -> ([f32; 3], [f32; 3]) {
    use std::f64::consts::PI;
    if let (3, Target::Mirror(b)) = (mode, target) {
        // wo at the angle acos(b) (+- 1e-5) from the mirror direction of wi.
        let ci = u[0].max(1e-3);
        let si = ((1.0 - ci) * (1.0 + ci)).sqrt();
        let pi_ = 2.0 * PI * u[1];
        let wi = [si * pi_.cos(), si * pi_.sin(), ci];
        let r = [-wi[0], -wi[1], wi[2]];
        let g = b.clamp(-1.0, 1.0).acos() + 1e-5 * (2.0 * u[2] - 1.0);
        // An orthonormal pair (t1, t2) perpendicular to r.
        let t1 = [r[2] * pi_.cos(), r[2] * pi_.sin(), -si];
        let t2 = [
            r[1] * t1[2] - r[2] * t1[1],
            r[2] * t1[0] - r[0] * t1[2],
            r[0] * t1[1] - r[1] * t1[0],
        ];
        let ph = 2.0 * PI * u[3];
        let wo: [f64; 3] = std::array::from_fn(|k| {
            g.cos() * r[k] + g.sin() * (ph.cos() * t1[k] + ph.sin() * t2[k])
        });
        return (wi.map(|x| x as f32), wo.map(|x| x as f32));
    }
    // Grazing density: log-uniform from COS_MIN (below it every BRDF is 0 by rule) to 1.
    let ci = if mode % 3 == 2 {
        crate::vec3::COS_MIN.powf(1.0 - u[0])
    } else {
        cos_at(u[0], mode).clamp(0.0, 1.0)
    };
    let si = ((1.0 - ci) * (1.0 + ci)).sqrt();
    let pi_ = 2.0 * PI * u[1];
    let wi = [si * pi_.cos(), si * pi_.sin(), ci];
    let th = match (mode, target) {
        (3, Target::Half(b)) => b.clamp(-1.0, 1.0).acos() + 1e-5 * (2.0 * u[2] - 1.0),
        _ => 0.5 * PI * u[2].powi(3),
    };
    let ph = 2.0 * PI * u[3];
    let h = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
    let d = 2.0 * (wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2]);
    let wo = [d * h[0] - wi[0], d * h[1] - wi[1], d * h[2] - wi[2]];
    (wi.map(|x| x as f32), wo.map(|x| x as f32))
}

/// A break of the model (a cut or kink) that restarts of mode 3 start near: a cosine (lobes,
/// distributions), `reflect(wi).wo` (phong) or `cos theta_h` (blinn-phong).
#[derive(Clone, Copy, Debug)]
enum Target {
    None,
    Cos(f64),
    Mirror(f64),
    Half(f64),
}

/// The breaks of a model ([`Target`]s).
fn targets(m: &Model<f64>) -> Vec<Target> {
    match m {
        Model::Lobe(l) => {
            let mut t: Vec<Target> = l.kinks().into_iter().map(Target::Cos).collect();
            t.push(Target::Cos(l.zero_below()));
            t
        }
        Model::Brdf(b) => b
            .mirror_breaks()
            .into_iter()
            .map(Target::Mirror)
            .chain(b.half_breaks().into_iter().map(Target::Half))
            .collect(),
        _ => vec![],
    }
}

/// One evaluation in both precisions on the same f32 input: `(mixed error, where)`; the
/// error is infinite when either value is non-finite or negative.
fn eval_both(
    m32: &Model<f32>,
    m64: &Model<f64>,
    u: &[f64],
    mode: usize,
    target: Target,
) -> (f64, String) {
    let judge = |v32: f32, v64: f64| {
        if !(v32.is_finite() && v32 >= 0.0 && v64.is_finite() && v64 >= 0.0) {
            f64::INFINITY
        } else {
            mixed_error(v32, v64)
        }
    };
    match (m32, m64) {
        (Model::Lobe(a), Model::Lobe(b)) => {
            let c = match (mode, target) {
                (3, Target::Cos(t)) => (t + 1e-5 * (2.0 * u[0] - 1.0)).clamp(0.0, 1.0) as f32,
                _ => cos_at(u[0], mode) as f32,
            };
            let (v32, v64) = (a.eval(c), b.eval(c as f64));
            (judge(v32, v64), format!("c={c} f32={v32} f64={v64}"))
        }
        (Model::Distribution(a), Model::Distribution(b)) => {
            let c = cos_at(u[0], mode) as f32;
            let (v32, v64) = (a.eval(c), b.eval(c as f64));
            (judge(v32, v64), format!("cos_h={c} f32={v32} f64={v64}"))
        }
        (Model::Fresnel(a), Model::Fresnel(b)) => {
            let c = cos_at(u[0], mode) as f32;
            let (v32, v64) = (a.f(c), b.f(c as f64));
            (judge(v32, v64), format!("cos={c} f32={v32} f64={v64}"))
        }
        (Model::Shadowing(a), Model::Shadowing(b)) => {
            let (wi, wo) = pair_at(u, mode, target);
            let (wi, wo) = (wi.map(f64::from), wo.map(f64::from));
            let (s32, s64) = shadow_inputs(wi, wo, u[4] < 0.5);
            let (v32, v64) = (a.g(&s32), b.g(&s64));
            (judge(v32, v64), format!("{s32:?} f32={v32} f64={v64}"))
        }
        (Model::Env(a), Model::Env(b)) => {
            let c = cos_at(u[0], mode) as f32;
            let (lo, hi) = crate::params::ALPHA.range();
            let al = (lo * (hi / lo).powf(u[1])) as f32;
            let (v32, v64) = (a.e(c, al), b.e(c as f64, al as f64));
            (
                judge(v32, v64),
                format!("cos_v={c} alpha={al} f32={v32} f64={v64}"),
            )
        }
        (Model::Brdf(a), Model::Brdf(b)) => {
            let (wi, wo) = pair_at(u, mode, target);
            let v32 = a.eval(wi, wo);
            let v64 = b.eval(wi.map(f64::from), wo.map(f64::from));
            (
                judge(v32, v64),
                format!("wi={wi:?} wo={wo:?} f32={v32} f64={v64}"),
            )
        }
        _ => unreachable!("both precisions build the same kind"),
    }
}

/// Adversarial search for the largest f32-vs-f64 error of `info`'s model over its whole
/// documented domain: for every combination of its choice parameters, random restarts
/// (numeric parameters at their edges, at special values or uniform, logarithmically for
/// wide positive ranges; optional parameters given or not; inputs in three densities),
/// each refined by hill climbing over the numeric parameters and the inputs together with a
/// step shrinking geometrically from 0.3 to 1e-7. Numeric parameters are f32 values, fed
/// exactly to both precisions. Also records any non-finite or negative value.
pub fn f32_search(info: &crate::ModelInfo, size: SearchSize) -> Found {
    use crate::params::ParamKind;
    let choice_sets = choice_sets(info);
    let mut numeric: Vec<(&str, f64, f64, bool)> = vec![];
    for p in info.params {
        if let ParamKind::Number {
            min, max, default, ..
        } = p.kind
        {
            numeric.push((p.name, min, max, default.is_none()))
        }
    }
    let dims = match info.kind {
        crate::Kind::Brdf => 4,
        crate::Kind::Shadowing => 5,
        crate::Kind::Env => 2,
        _ => 1,
    };
    let mut state = size.seed ^ (info.id.len() as u64).wrapping_mul(0x9E37_79B9);
    for b in info.id.bytes() {
        state = state.rotate_left(5) ^ b as u64;
    }
    let mut rnd = move || splitmix(&mut state);
    let mut found = Found::default();
    // q: numeric coordinates in [0, 1]; given: whether each optional one is given.
    let given_of = |set: &[(&'static str, Given)], q: &[f64], on: &[bool]| {
        let mut g = set.to_vec();
        for (i, &(name, min, max, _)) in numeric.iter().enumerate() {
            if on[i] {
                g.push((
                    name,
                    Given::Num(f32_param(param_at(q[i], min, max), min, max)),
                ));
            }
        }
        g
    };
    // The spec (refused combinations are not part of the domain) and both precisions.
    let build = |g: &[(&'static str, Given)]| {
        let spec = ModelSpec::new(info.id, g).ok()?;
        let m32 = spec.model::<f32>().ok()?;
        let m64 = spec.model::<f64>().ok()?;
        Some((m32, m64, spec))
    };
    for set in &choice_sets {
        // Whether this choice combination has breaks (at default parameters).
        let breaks = build(set).map(|m| targets(&m.1)).unwrap_or_default();
        for r in 0..size.restarts {
            // Modes 0-2: input densities; mode 3 (every fourth restart of a model with cuts
            // or kinks): near one of them.
            let mode = if breaks.is_empty() { r % 3 } else { r % 4 };
            let mut target = Target::None;
            let mut q: Vec<f64> = numeric
                .iter()
                .map(|&(name, min, max, _)| {
                    let t = rnd();
                    if t < 0.2 {
                        0.0
                    } else if t < 0.4 {
                        1.0
                    } else if t < 0.6 {
                        let s = special_values(name, min, max);
                        let v = s[(rnd() * s.len() as f64) as usize % s.len()];
                        param_q(v, min, max)
                    } else {
                        rnd()
                    }
                })
                .collect();
            let on: Vec<bool> = numeric
                .iter()
                .map(|&(_, _, _, optional)| !optional || rnd() < 0.5)
                .collect();
            let mut u: Vec<f64> = (0..dims).map(|_| rnd()).collect();
            let g = given_of(set, &q, &on);
            let Some(mut models) = build(&g) else {
                continue; // e.g. a combination the model refuses: not part of its domain
            };
            if mode == 3 {
                let t = targets(&models.1);
                if t.is_empty() {
                    continue;
                }
                target = t[(rnd() * t.len() as f64) as usize % t.len()];
            }
            let (mut e, mut at) = eval_both(&models.0, &models.1, &u, mode, target);
            found.evaluations += 1;
            for t in 0..size.steps {
                let sigma = 0.3 * (1e-7f64 / 0.3).powf(t as f64 / size.steps as f64);
                let step = |x: f64, r: f64| (x + sigma * (2.0 * r - 1.0)).clamp(0.0, 1.0);
                if !numeric.is_empty() && mode != 3 && rnd() < 0.15 {
                    let q2: Vec<f64> = q
                        .iter()
                        .map(|&x| if rnd() < 0.5 { step(x, rnd()) } else { x })
                        .collect();
                    let g2 = given_of(set, &q2, &on);
                    if let Some(m2) = build(&g2) {
                        let (e2, at2) = eval_both(&m2.0, &m2.1, &u, mode, target);
                        found.evaluations += 1;
                        if e2 >= e {
                            (q, models, e, at) = (q2, m2, e2, at2);
                        }
                    }
                } else {
                    let u2: Vec<f64> = u.iter().map(|&x| step(x, rnd())).collect();
                    let (e2, at2) = eval_both(&models.0, &models.1, &u2, mode, target);
                    found.evaluations += 1;
                    if e2 >= e {
                        (u, e, at) = (u2, e2, at2);
                    }
                }
            }
            let spec = models.2;
            if e.is_infinite() && found.invalid.is_none() {
                found.invalid = Some(format!("{:?} {at}", spec.pairs()));
            }
            // The first restart's result, then the largest (`found.spec` is set by the first).
            if e > found.err || found.spec.is_none() {
                found.err = e;
                found.spec = Some(spec);
                found.at = at;
            }
        }
    }
    found
}
