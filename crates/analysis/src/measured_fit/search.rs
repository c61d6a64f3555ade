//! The search: the exact non-negative albedos, the three metrics, Nelder-Mead (argmin) from
//! several starts, and the fit's result.

use super::{Data, Free, Metric, Options, Problem, Residuals, undetermined};
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use fastbrdf::Brdf;
use std::cell::Cell;
use std::f64::consts::PI;

/// The non-negative least-squares albedos `(rho_d, rho_s)` of each channel given the specular
/// values `spec` (exact: see the module documentation).
pub fn albedos(data: &Data, spec: &[f64]) -> [[f64; 2]; 3] {
    [0, 1, 2].map(|c| {
        let (mut a11, mut a12, mut a22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for ((wi, v), &sk) in data.wi.iter().zip(&data.value).zip(spec) {
            let w = wi[2];
            let (x1, x2, y) = (w / PI, w * sk, w * v[c]);
            a11 += x1 * x1;
            a12 += x1 * x2;
            a22 += x2 * x2;
            r1 += x1 * y;
            r2 += x2 * y;
        }
        // SSE(a, b) - sum y^2 = -2 (a r1 + b r2) + a^2 a11 + 2 a b a12 + b^2 a22.
        let sse = |a: f64, b: f64| {
            -2.0 * (a * r1 + b * r2) + a * a * a11 + 2.0 * a * b * a12 + b * b * a22
        };
        let mut best = (0.0, 0.0);
        let mut cands = vec![];
        let det = a11 * a22 - a12 * a12;
        // Nearly collinear columns (a Lambert-like specular): only the boundary solutions.
        if det > 1e-12 * a11 * a22 {
            let a = (r1 * a22 - r2 * a12) / det;
            let b = (r2 * a11 - r1 * a12) / det;
            if a >= 0.0 && b >= 0.0 {
                cands.push((a, b));
            }
        }
        if a11 > 0.0 {
            cands.push(((r1 / a11).max(0.0), 0.0));
        }
        if a22 > 0.0 {
            cands.push((0.0, (r2 / a22).max(0.0)));
        }
        let mut e = 0.0;
        for (a, b) in cands {
            let s = sse(a, b);
            if s < e {
                (e, best) = (s, (a, b));
            }
        }
        [best.0, best.1]
    })
}

/// The three metrics of the model `rho_d / pi + rho_s spec` (per channel) against the data.
pub fn residuals(data: &Data, spec: &[f64], alb: &[[f64; 2]; 3]) -> Residuals {
    let (mut l2, mut lg, mut mx) = (0.0f64, 0.0f64, 0.0f64);
    for ((wi, v), &sk) in data.wi.iter().zip(&data.value).zip(spec) {
        let w = wi[2];
        for (c, a) in alb.iter().enumerate() {
            let m = v[c];
            let f = a[0] / PI + a[1] * sk;
            let d = w * (m - f);
            l2 += d * d;
            mx = mx.max(d.abs());
            let l = (w * m).ln_1p() - (w * f).ln_1p();
            lg += l * l;
        }
    }
    let n = (3 * data.len()).max(1) as f64;
    Residuals {
        ngan_l2: (l2 / n).sqrt(),
        low_log: (lg / n).sqrt(),
        max: mx,
    }
}

/// A fit's result.
#[derive(Clone, Debug)]
pub struct Fit {
    pub problem: Problem,
    pub metric: Metric,
    /// The free parameters' fitted values, in `problem.free`'s order.
    pub values: Vec<f64>,
    /// Per channel R, G, B.
    pub rho_d: [f64; 3],
    pub rho_s: [f64; 3],
    pub residuals: Residuals,
    /// Objective evaluations (each one model evaluation per sample).
    pub evaluations: u64,
    /// Nelder-Mead runs made (starts and polishes).
    pub runs: usize,
    pub samples: usize,
    /// The fitted quantities the data do not determine (see the module documentation): free
    /// parameter names and `rho_d` / `rho_s` (any channel), in that order; empty when every
    /// one is determined.
    pub undetermined: Vec<String>,
}

impl Fit {
    /// The fitted model: the fixed values, then the fitted ones.
    pub fn params(&self) -> fastbrdf::Result<fastbrdf::ModelSpec> {
        self.problem.params(&self.values)
    }

    /// The fitted RGB BRDF, for rendering.
    pub fn brdf(&self) -> fastbrdf::Result<FittedBrdf> {
        Ok(FittedBrdf {
            model: self.problem.model(&self.values)?,
            rho_d: self.rho_d,
            rho_s: self.rho_s,
        })
    }
}

/// A fitted model with its albedos: `rho_d[c] / pi + rho_s[c] spec`, evaluated in f64 and
/// rounded to f32 for the renderer.
pub struct FittedBrdf {
    pub model: Box<dyn Brdf<f64>>,
    pub rho_d: [f64; 3],
    pub rho_s: [f64; 3],
}

impl FittedBrdf {
    pub fn eval_rgb(&self, wi: [f64; 3], wo: [f64; 3]) -> [f64; 3] {
        if !(wi[2] > 0.0 && wo[2] > 0.0) {
            return [0.0; 3];
        }
        let s = self.model.eval(wi, wo);
        [0, 1, 2].map(|c| self.rho_d[c] / PI + self.rho_s[c] * s)
    }
}

impl fastbrdf_render::scene::RgbBrdf for FittedBrdf {
    fn eval_rgb(&self, wi: [f32; 3], wo: [f32; 3]) -> [f32; 3] {
        FittedBrdf::eval_rgb(self, wi.map(f64::from), wo.map(f64::from)).map(|v| v as f32)
    }
}

/// The objective over the unbounded vector `x`: the free parameters' `u`, then (joint
/// search) the six albedos (their absolute values).
struct Objective<'a> {
    problem: &'a Problem,
    data: &'a Data,
    metric: Metric,
    joint: bool,
    /// Evaluations, shared by the copies handed to argmin.
    evals: &'a Cell<u64>,
}

impl Objective<'_> {
    fn values(&self, x: &[f64]) -> Vec<f64> {
        self.problem
            .free
            .iter()
            .zip(x)
            .map(|(f, &u)| f.value(u))
            .collect()
    }

    /// (cost, albedos) at `x`.
    fn eval(&self, x: &[f64]) -> (f64, [[f64; 2]; 3]) {
        self.evals.set(self.evals.get() + 1);
        let values = self.values(x);
        let Some(spec) = self.problem.spec(self.data, &values) else {
            return (f64::INFINITY, [[0.0; 2]; 3]);
        };
        let alb = if self.joint {
            let k = self.problem.free.len();
            [0, 1, 2].map(|c| [x[k + 2 * c].abs(), x[k + 2 * c + 1].abs()])
        } else {
            albedos(self.data, &spec)
        };
        let r = residuals(self.data, &spec, &alb).get(self.metric);
        (if r.is_finite() { r } else { f64::INFINITY }, alb)
    }
}

impl CostFunction for Objective<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.eval(x).0)
    }
}

/// One Nelder-Mead run from `x0` with per-coordinate steps `step`; the best point and cost.
fn nelder_mead(obj: &Objective, x0: &[f64], step: &[f64], iters: u64) -> (Vec<f64>, f64) {
    if x0.is_empty() {
        return (Vec::new(), obj.eval(x0).0);
    }
    let mut simplex = vec![x0.to_vec()];
    for i in 0..x0.len() {
        let mut v = x0.to_vec();
        v[i] += step[i];
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-12)
        .expect("a non-negative tolerance");
    let run = Executor::new(
        Objective {
            problem: obj.problem,
            data: obj.data,
            metric: obj.metric,
            joint: obj.joint,
            evals: obj.evals,
        },
        solver,
    )
    .configure(|s| s.max_iters(iters))
    .run();
    match run {
        Ok(r) => {
            let best = r.state().get_best_param().cloned().unwrap_or(x0.to_vec());
            let cost = r.state().get_best_cost();
            (best, cost)
        }
        Err(_) => (x0.to_vec(), obj.eval(x0).0),
    }
}

/// The `j`-th start in `[0, 1]^d`: the defaults for `j = 0`, then a Kronecker sequence.
fn start(free: &[Free], j: usize) -> Vec<f64> {
    const ALPHAS: [f64; 8] = [
        0.618_033_988_749_894_9,
        0.414_213_562_373_095,
        0.732_050_807_568_877_2,
        0.236_067_977_499_79,
        0.645_751_311_064_590_6,
        0.316_624_790_355_4,
        0.123_105_625_617_66,
        0.358_898_943_540_674,
    ];
    free.iter()
        .enumerate()
        .map(|(i, f)| {
            let t = if j == 0 {
                f.t_of(f.default)
            } else {
                (0.5 + j as f64 * ALPHAS[i % ALPHAS.len()]).fract()
            };
            Free::u_of_t(t.clamp(0.02, 0.98))
        })
        .collect()
}

/// Fits `problem` to `data` with `opts`; `progress(done, total)` after each Nelder-Mead run.
pub fn fit(
    problem: &Problem,
    data: &Data,
    opts: &Options,
    progress: &dyn Fn(usize, usize),
) -> Result<Fit, String> {
    if data.is_empty() {
        return Err("no valid measured sample within 80 degrees of the normal".into());
    }
    let k = problem.free.len();
    let restarts = opts.restarts.max(1);
    let joint = opts.metric != Metric::NganL2;
    let total = restarts + 1 + usize::from(joint) * 2;
    let counter = Cell::new(0u64);
    let l2 = Objective {
        problem,
        data,
        metric: Metric::NganL2,
        joint: false,
        evals: &counter,
    };
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut runs = 0;
    let starts = if k == 0 { 1 } else { restarts };
    for j in 0..starts {
        let x0 = start(&problem.free, j);
        let r = nelder_mead(&l2, &x0, &vec![0.4; k], opts.max_iters);
        runs += 1;
        progress(runs, total);
        if best.as_ref().is_none_or(|b| r.1 < b.1) {
            best = Some(r);
        }
    }
    let (mut x, _) = best.expect("at least one start");
    if k > 0 {
        x = nelder_mead(&l2, &x, &vec![0.05; k], opts.max_iters).0;
        runs += 1;
    }
    progress(runs, total);
    let (_, mut alb) = l2.eval(&x);
    if joint {
        let obj = Objective {
            problem,
            data,
            metric: opts.metric,
            joint: true,
            evals: &counter,
        };
        let mut xj = x.clone();
        xj.extend(alb.iter().flatten());
        let mut step = vec![0.2; k];
        step.extend(alb.iter().flatten().map(|a| 0.2 * a + 1e-3));
        for scale in [1.0, 0.1] {
            let s: Vec<f64> = step.iter().map(|v| v * scale).collect();
            xj = nelder_mead(&obj, &xj, &s, opts.max_iters * 2).0;
            runs += 1;
            progress(runs, total);
        }
        // Keep the joint result only where it improves the chosen metric.
        let before = {
            let values = l2.values(&x);
            let spec = problem
                .spec(data, &values)
                .expect("finite at the l2 optimum");
            residuals(data, &spec, &alb).get(opts.metric)
        };
        let (cost, a) = obj.eval(&xj);
        if cost < before {
            x = xj[..k].to_vec();
            alb = a;
        }
    }
    let values = l2.values(&x);
    let spec = problem
        .spec(data, &values)
        .ok_or("the model is not finite at the optimum")?;
    let undetermined = undetermined(problem, data, &values, &spec, &alb);
    Ok(Fit {
        undetermined,
        problem: problem.clone(),
        metric: opts.metric,
        residuals: residuals(data, &spec, &alb),
        values,
        rho_d: alb.map(|a| a[0]),
        rho_s: alb.map(|a| a[1]),
        evaluations: counter.get(),
        runs,
        samples: data.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf::measured::{self, MeasuredBrdf};
    use fastbrdf::{Model, ModelSpec};

    /// Cook-Torrance (f = schlick, d = ggx) tabulated exactly with f0 0.04, f90 1 and rho_s 1.
    fn schlick_data() -> Data {
        let params = [
            ("f", "schlick"),
            ("d", "ggx"),
            ("alpha", "0.3"),
            ("f0", "0.04"),
        ];
        let spec = ModelSpec::parse("cook-torrance", &params).unwrap();
        let Model::Brdf(b) = spec.model::<f64>().unwrap() else {
            panic!("a BRDF")
        };
        let kd = [0.05, 0.04, 0.03];
        let bytes = measured::merl_bytes(|th, td, pd| {
            let (wi, wo) = measured::from_half_diff(th, td, pd);
            if wi[2] <= 0.0 || wo[2] <= 0.0 {
                return [-1.0; 3];
            }
            let s = b.eval(wi, wo);
            [0, 1, 2].map(|c| kd[c] / PI + s)
        });
        let m = MeasuredBrdf::from_reader(&bytes[..], std::path::Path::new("s.binary")).unwrap();
        Data::from_measured(&m, 1500)
    }

    fn fixed(p: &[(&str, &str)]) -> ModelSpec {
        ModelSpec::parse("cook-torrance", p).unwrap()
    }

    /// Issue 27: with f90 free only products of f0, f90 and rho_s were determined (f0 0.0316,
    /// f90 0.791, rho_s 1.265 on these data, no warning). f90 is now held at 1 and the fit
    /// recovers f0 and rho_s; asking for f90 is reported as undetermined.
    #[test]
    fn schlick_f90_is_held_and_a_degenerate_request_is_reported() {
        let data = schlick_data();
        let fx = fixed(&[("f", "schlick"), ("d", "ggx")]);
        let problem = Problem::new(&fx, true).unwrap();
        let names: Vec<&str> = problem.free.iter().map(|f| f.name).collect();
        assert_eq!(names, ["alpha", "f0"]);
        assert_eq!(problem.held, [("f90", 1.0)]);
        let r = fit(&problem, &data, &Options::default(), &|_, _| {}).unwrap();
        assert!((r.values[1] - 0.04).abs() < 0.02 * 0.04, "{:?}", r.values);
        assert!((r.values[0] - 0.3).abs() < 0.02 * 0.3, "{:?}", r.values);
        for c in 0..3 {
            assert!((r.rho_s[c] - 1.0).abs() < 0.02, "{:?}", r.rho_s);
        }
        assert!(r.undetermined.is_empty(), "{:?}", r.undetermined);
        // Asked for, f90 is fitted, and the fit says what it cannot determine.
        let free = Problem::with_free(&fx, true, &["f90".into()]).unwrap();
        let names: Vec<&str> = free.free.iter().map(|f| f.name).collect();
        assert_eq!(names, ["alpha", "f0", "f90"]);
        let d = fit(&free, &data, &Options::default(), &|_, _| {}).unwrap();
        assert_eq!(d.undetermined, ["f0", "f90", "rho_s"], "{d:?}");
        // Bad requests.
        assert!(Problem::with_free(&fx, true, &["nope".into()]).is_err());
        assert!(Problem::with_free(&fx, true, &["d".into()]).is_err());
        let both = fixed(&[("f", "schlick"), ("f90", "1")]);
        assert!(Problem::with_free(&both, true, &["f90".into()]).is_err());
        // The fitted model is a spec: the fixed values, then the fitted ones.
        let spec = r.params().unwrap();
        assert_eq!(
            spec.get("f"),
            Some(&fastbrdf::Given::Choice("schlick".into()))
        );
        assert_eq!(spec.get("f0"), Some(&fastbrdf::Given::Num(r.values[1])));
        // A coloured spec is refused: the albedos carry the colour.
        let rgb = fixed(&[("f", "schlick"), ("f0", "0.1,0.2,0.3")]);
        assert!(Problem::new(&rgb, true).is_err());
    }
}
