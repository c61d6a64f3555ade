//! The C peers (issue 13): each lobe's and Beckmann's (and GGX's) batch kernel raced against
//! the C loop a performance-minded user would write (`c/peer.c`), round by round, with both
//! sides' accuracy against the f64 model.

use super::{Aligned, repeats_for, timed};
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::{Given, Model, ModelSpec, PipeOps};
use serde::{Deserialize, Serialize};
use std::hint::black_box;
use std::time::Duration;

/// The system C compiler that built `c/peer.c` (its `--version` line).
pub const PEER_COMPILER: &str = env!("FASTBRDF_PEER_CC");
/// The flags `c/peer.c` was compiled with (`-O3 -march=native -ffast-math`, or the fallback
/// without `-march=native`, which says so).
pub const PEER_FLAGS: &str = env!("FASTBRDF_PEER_FLAGS");
/// Whether the compiler vectorised libm calls into glibc's libmvec (then linked).
pub const PEER_LIBMVEC: bool = matches!(env!("FASTBRDF_PEER_LIBMVEC").as_bytes(), b"yes");

mod ffi {
    // The loops of `crates/analysis/c/peer.c`: each reads `n` floats from `x` and writes `n`
    // floats to `out`, nothing else.
    unsafe extern "C" {
        pub fn peer_pow(x: *const f32, out: *mut f32, n: usize, e: f32);
        pub fn peer_sg(x: *const f32, out: *mut f32, n: usize, rate: f32);
        pub fn peer_power4(x: *const f32, out: *mut f32, n: usize, k: f32);
        pub fn peer_power8(x: *const f32, out: *mut f32, n: usize, k: f32);
        pub fn peer_power16(x: *const f32, out: *mut f32, n: usize, k: f32);
        pub fn peer_cubic(x: *const f32, out: *mut f32, n: usize, a: f32, b: f32, d: f32, cut: f32);
        pub fn peer_schlick(x: *const f32, out: *mut f32, n: usize, e: f32);
        pub fn peer_beckmann(x: *const f32, out: *mut f32, n: usize, inv_a2: f32, scale: f32);
        pub fn peer_ggx(x: *const f32, out: *mut f32, n: usize, a2m1: f32, scale: f32);
    }
}

/// A C peer's parameters, computed once in f64 from the model's parameters and rounded to f32,
/// as a user would hoist them out of the loop.
#[derive(Clone, Copy, Debug)]
enum PeerFn {
    /// `powf(c, n)`, unclamped: where `c^n` underflows (c < 0.645 at n = 200) libmvec's
    /// powf falls back to scalar calls, and that is part of the measurement.
    Pow(f32),
    /// `exp2f(max(-126, rate (c - 1)))`, `rate = n / ln 2` (clamped like Beckmann's exponent,
    /// so libmvec's underflow fallback is not what is measured).
    Sg(f32),
    /// `max(0, 1 + k (c - 1))^(2^squarings)`, `k = n / g`.
    Power { squarings: u32, k: f32 },
    /// Seed 003's monomial form `a c^3 + b c^2 + d c`, clipped below `cut` and where negative.
    Cubic { a: f32, b: f32, d: f32, cut: f32 },
    /// `c / (n - n c + c)`.
    Schlick(f32),
    /// `scale expf(max(-87, -tan^2 inv_a2)) / cos^4`.
    Beckmann { inv_a2: f32, scale: f32 },
    /// `scale / ((alpha^2 - 1) c^2 + 1)^2`, `scale = alpha^2 / pi`, 0 for `c <= 0`.
    Ggx { a2m1: f32, scale: f32 },
}

/// One C peer: the model it stands in for (id and spec) and its loop.
#[derive(Clone, Debug)]
pub struct Peer {
    pub id: &'static str,
    /// The model the loop computes, at the peer's parameter.
    pub spec: ModelSpec,
    /// The C function's name.
    pub function: &'static str,
    f: PeerFn,
}

impl Peer {
    /// The peer of `id` (`pow`, `sg`, `power4`, `power8`, `power16`, `cubic`, `schlick`: at
    /// `n`; `beckmann`, `ggx`: at `alpha`), `None` for a model without one.
    pub fn new(id: &str, param: f64) -> Option<Self> {
        let n = param;
        let (id, function, name, f) = match id {
            "pow" => ("pow", "peer_pow", "n", PeerFn::Pow(n as f32)),
            "sg" => (
                "sg",
                "peer_sg",
                "n",
                PeerFn::Sg((n / std::f64::consts::LN_2) as f32),
            ),
            "power4" => ("power4", "peer_power4", "n", power(2, n)),
            "power8" => ("power8", "peer_power8", "n", power(3, n)),
            "power16" => ("power16", "peer_power16", "n", power(4, n)),
            "cubic" => {
                // Seed 003's closed forms, q = 0.5^(1/n) (as the library takes it), in f64.
                let q = 0.5f64.powf(1.0 / n);
                let den = 2.0 * (q - 1.0) * (q - 1.0) * q * q;
                let a = ((q - 1.0) * (2.0 * q + n) + 1.0) / den;
                let b = -(q * q * (4.0 * q - 3.0) + n * (q * q - 1.0) + 1.0) / den;
                let cut = fastbrdf::lobes::cubic::CubicShape::hermite(n).cut;
                let f = PeerFn::Cubic {
                    a: a as f32,
                    b: b as f32,
                    d: (1.0 - a - b) as f32,
                    cut: cut as f32,
                };
                ("cubic", "peer_cubic", "n", f)
            }
            "schlick" => ("schlick", "peer_schlick", "n", PeerFn::Schlick(n as f32)),
            "beckmann" => {
                let a2 = param * param;
                let f = PeerFn::Beckmann {
                    inv_a2: (1.0 / a2) as f32,
                    scale: (1.0 / (std::f64::consts::PI * a2)) as f32,
                };
                ("beckmann", "peer_beckmann", "alpha", f)
            }
            "ggx" => {
                let a2 = param * param;
                let f = PeerFn::Ggx {
                    a2m1: (a2 - 1.0) as f32,
                    scale: (a2 / std::f64::consts::PI) as f32,
                };
                ("ggx", "peer_ggx", "alpha", f)
            }
            _ => return None,
        };
        Some(Self {
            id,
            spec: ModelSpec::new(id, &[(name, Given::Num(param))]).ok()?,
            function,
            f,
        })
    }

    /// The model's parameters as `name=value` (the CLI's form).
    pub fn params_text(&self) -> String {
        self.spec
            .pairs()
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(",")
    }

    /// Runs the C loop over `x` into `out`.
    ///
    /// # Panics
    /// When the lengths differ.
    pub fn eval(&self, x: &[f32], out: &mut [f32]) {
        assert_eq!(x.len(), out.len(), "peer input and output lengths differ");
        let (x, o, n) = (x.as_ptr(), out.as_mut_ptr(), x.len());
        // SAFETY: every peer reads exactly `n` floats from `x` and writes exactly `n` floats to
        // `out` (c/peer.c), and both slices hold `n` elements (asserted above); the slices
        // cannot overlap (one is borrowed shared, the other mutably). The loops touch no other
        // memory and keep no pointer.
        unsafe {
            match self.f {
                PeerFn::Pow(e) => ffi::peer_pow(x, o, n, e),
                PeerFn::Sg(r) => ffi::peer_sg(x, o, n, r),
                PeerFn::Power { squarings: 2, k } => ffi::peer_power4(x, o, n, k),
                PeerFn::Power { squarings: 3, k } => ffi::peer_power8(x, o, n, k),
                PeerFn::Power { k, .. } => ffi::peer_power16(x, o, n, k),
                PeerFn::Cubic { a, b, d, cut } => ffi::peer_cubic(x, o, n, a, b, d, cut),
                PeerFn::Schlick(e) => ffi::peer_schlick(x, o, n, e),
                PeerFn::Beckmann { inv_a2, scale } => ffi::peer_beckmann(x, o, n, inv_a2, scale),
                PeerFn::Ggx { a2m1, scale } => ffi::peer_ggx(x, o, n, a2m1, scale),
            }
        }
    }
}

fn power(squarings: u32, n: f64) -> PeerFn {
    PeerFn::Power {
        squarings,
        k: (n / f64::from(1u32 << squarings)) as f32,
    }
}

/// The peers the benchmark races: the lobes at n = 200 (as the kernel rows), Beckmann and GGX
/// at alpha = 0.3.
pub fn peers() -> Vec<Peer> {
    let lobes = [
        "pow", "sg", "power4", "power8", "power16", "cubic", "schlick",
    ];
    let mut v: Vec<Peer> = lobes
        .iter()
        .map(|id| Peer::new(id, 200.0).expect("a peer exists"))
        .collect();
    v.push(Peer::new("beckmann", 0.3).expect("a peer exists"));
    v.push(Peer::new("ggx", 0.3).expect("a peer exists"));
    v
}

/// The process's flush-to-zero and denormals-are-zero flags (MXCSR bits 15 and 6); `None`
/// off x86-64.
pub fn ftz_daz() -> Option<(bool, bool)> {
    #[cfg(target_arch = "x86_64")]
    {
        // `_mm_getcsr` is deprecated in favour of inline assembly because *setting* MXCSR
        // behind the compiler's back is undefined; reading it is what this needs.
        #[allow(deprecated)]
        // SAFETY: `_mm_getcsr` only reads the MXCSR register (stmxcsr), which SSE (part of the
        // x86-64 baseline, so always present) provides; it changes no state.
        let csr = unsafe { std::arch::x86_64::_mm_getcsr() };
        Some((csr & 0x8000 != 0, csr & 0x0040 != 0))
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        None
    }
}

/// What the FTZ/DAZ state means for the peers, in words.
pub fn ftz_note(state: Option<(bool, bool)>) -> String {
    match state {
        Some((ftz, daz)) => format!(
            "FTZ {}, DAZ {} in this process (MXCSR, read at run time). The C peers are a static library compiled with -ffast-math: that sets no flag (only linking an executable with -ffast-math adds GCC's crtfastmath.o, which sets FTZ/DAZ at start-up), so the kernels and the peers both run with the state read here{}",
            if ftz { "on" } else { "off" },
            if daz { "on" } else { "off" },
            if ftz || daz {
                ""
            } else {
                "; subnormal results (e.g. pow's tail) are computed in full on both sides"
            }
        ),
        None => "FTZ/DAZ unknown (not x86-64)".into(),
    }
}

/// Median and spread of repeated measurements.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Spread {
    pub median: f64,
    /// First and third quartiles.
    pub q1: f64,
    pub q3: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// The summary of `xs` (quartiles by linear interpolation). `xs` must not be empty.
    pub fn of(xs: &[f64]) -> Self {
        let mut v = xs.to_vec();
        v.sort_by(f64::total_cmp);
        let q = |p: f64| {
            let t = p * (v.len() - 1) as f64;
            let (i, f) = (t.floor() as usize, t.fract());
            if i + 1 < v.len() {
                v[i] + f * (v[i + 1] - v[i])
            } else {
                v[i]
            }
        };
        Self {
            median: q(0.5),
            q1: q(0.25),
            q3: q(0.75),
            min: v[0],
            max: v[v.len() - 1],
        }
    }

    pub(super) fn values(&self) -> [f64; 5] {
        [self.median, self.q1, self.q3, self.min, self.max]
    }
}

/// A batch kernel against its C peer, from the same rounds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PeerRow {
    pub model: String,
    /// `name=value` (the CLI's form).
    pub params: String,
    /// Elements per call.
    pub batch: usize,
    /// Calls per timed round (one clock read each side of them).
    pub repeats: usize,
    /// Rounds, each timing the kernel then the peer.
    pub rounds: usize,
    /// The kernel's instruction set.
    pub isa: String,
    pub kernel_evals_per_s: Spread,
    pub peer_evals_per_s: Spread,
    /// Kernel rate over peer rate, per round.
    pub ratio: Spread,
    /// Max of `|v - v64| / max(1, |v64|)` against the f64 model, over the benchmark's inputs
    /// and a grid of 65537 cosines.
    pub kernel_max_error: f64,
    pub peer_max_error: f64,
    /// The C function.
    pub peer: String,
    pub compiler: String,
    pub flags: String,
    /// Whether powf/expf/exp2f calls went to glibc's vector library.
    pub libmvec: bool,
    /// MXCSR's flush-to-zero and denormals-are-zero bits (absent off x86-64).
    pub ftz: Option<bool>,
    pub daz: Option<bool>,
    /// The machine limit of the kernel's median rate, as `KernelRow::limit` (absent from runs
    /// saved before it existed).
    #[serde(default)]
    pub kernel_limit: Option<String>,
    #[serde(default)]
    pub kernel_limit_fraction: Option<f64>,
    /// The C loop's median rate against the same limit, counted with the model's own
    /// operations (what the same arithmetic at the C loop's rate would use): how close the
    /// peer is to the bound the kernel is held to.
    #[serde(default)]
    pub peer_limit_fraction: Option<f64>,
    /// The kernel's own operation count where its family gives one (`Kernel::pipe_ops`),
    /// read when the race builds the kernel; not saved (the limit fields carry its use).
    #[serde(skip)]
    pub kernel_pipe_ops: Option<PipeOps>,
}

/// How long the race runs.
pub struct PeerOptions {
    pub rounds: usize,
    /// Target duration of one side of one round.
    pub round: Duration,
}

/// Max mixed error `|v - v64| / max(1, |v64|)` of `f` over `xs` against the f64 model.
pub fn max_mixed_error(m64: &Model<f64>, xs: &[f32], f: impl FnOnce(&[f32], &mut [f32])) -> f64 {
    let mut out = vec![0.0f32; xs.len()];
    f(xs, &mut out);
    xs.iter()
        .zip(&out)
        .map(|(&c, &v)| {
            let r = match m64 {
                Model::Lobe(l) => l.eval(f64::from(c)),
                Model::Distribution(d) => d.eval(f64::from(c)),
                _ => unreachable!("peers stand in for lobes and distributions"),
            };
            let e = (f64::from(v) - r).abs() / r.abs().max(1.0);
            // A non-finite value is the worst error there is.
            if e.is_nan() { f64::INFINITY } else { e }
        })
        .fold(0.0, f64::max)
}

/// The inputs accuracy is measured on: `cos` and 65537 evenly spaced cosines in [0, 1].
pub fn accuracy_inputs(cos: &[f32]) -> Vec<f32> {
    let grid = (0..=65536).map(|i| (f64::from(i) / 65536.0) as f32);
    cos.iter().copied().chain(grid).collect()
}

/// Races every peer of `models` (all when empty) against its kernel on `cos` (4096 cosines).
pub fn peer_rows(
    models: &[String],
    cos: &[f32],
    opts: &PeerOptions,
) -> fastbrdf::Result<Vec<PeerRow>> {
    let state = ftz_daz();
    let acc_in = accuracy_inputs(cos);
    let mut rows = Vec::new();
    for peer in peers() {
        if !(models.is_empty() || models.iter().any(|m| m == peer.id)) {
            continue;
        }
        let kernel = Kernel::new(&peer.spec)?;
        let m64 = peer.spec.model::<f64>()?;
        let kernel_max_error = max_mixed_error(&m64, &acc_in, |x, o| {
            kernel.eval(Input::Cos(x), o).expect("shapes match")
        });
        let peer_max_error = max_mixed_error(&m64, &acc_in, |x, o| peer.eval(x, o));
        // One input and one output buffer, both 64-byte aligned, for both sides: the same
        // addresses, so neither gains from where its allocation happened to land.
        let x = Aligned::from_slice(cos);
        let mut out = Aligned::zeroed(cos.len());
        let run_kernel = |o: &mut [f32]| {
            kernel
                .eval(Input::Cos(black_box(&x)), o)
                .expect("shapes match");
            black_box(o);
        };
        let run_peer = |o: &mut [f32]| {
            peer.eval(black_box(&x), o);
            black_box(o);
        };
        // Warm up, then size a round: enough calls that the slower side takes `opts.round`.
        let one = timed(8, || run_kernel(&mut out)).max(timed(8, || run_peer(&mut out))) / 8.0;
        let repeats = repeats_for(opts.round.as_secs_f64(), one);
        let evals = (repeats * cos.len()) as f64;
        let (mut k, mut p, mut ratio) = (vec![], vec![], vec![]);
        for _ in 0..opts.rounds.max(1) {
            let tk = timed(repeats, || run_kernel(&mut out)).max(1e-12);
            let tp = timed(repeats, || run_peer(&mut out)).max(1e-12);
            k.push(evals / tk);
            p.push(evals / tp);
            ratio.push(tp / tk);
        }
        rows.push(PeerRow {
            model: peer.id.into(),
            params: peer.params_text(),
            batch: cos.len(),
            repeats,
            rounds: opts.rounds.max(1),
            isa: kernel.isa().name().into(),
            kernel_evals_per_s: Spread::of(&k),
            peer_evals_per_s: Spread::of(&p),
            ratio: Spread::of(&ratio),
            kernel_max_error,
            peer_max_error,
            peer: peer.function.into(),
            compiler: PEER_COMPILER.into(),
            flags: PEER_FLAGS.into(),
            libmvec: PEER_LIBMVEC,
            ftz: state.map(|s| s.0),
            daz: state.map(|s| s.1),
            kernel_limit: None,
            kernel_limit_fraction: None,
            peer_limit_fraction: None,
            kernel_pipe_ops: kernel.pipe_ops(),
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::super::Inputs;
    use super::*;

    /// Each C peer's maximum mixed error against the f64 model of the same id and
    /// parameters, on the benchmark's inputs and a 65537-point grid.
    fn peer_errors() -> Vec<(&'static str, f64, f64)> {
        let xs = accuracy_inputs(&Inputs::new(4096).cos);
        peers()
            .iter()
            .map(|p| {
                let m64 = p.spec.model::<f64>().unwrap();
                let kernel = Kernel::new(&p.spec).unwrap();
                let ke = max_mixed_error(&m64, &xs, |x, o| kernel.eval(Input::Cos(x), o).unwrap());
                (p.id, max_mixed_error(&m64, &xs, |x, o| p.eval(x, o)), ke)
            })
            .collect()
    }

    /// The peers compile, link and compute their models: each within 1e-5 (mixed) of the f64
    /// model of the same id and parameters (measured: 3e-8 to 7e-7; GGX's engine form
    /// 1.2e-6, its cancellation near the peak), like the kernels.
    /// The exception is the seed cubic, which C evaluates in the seed's monomial form: at
    /// n = 200 its coefficients are about 1.3e4 and cancel in f32 (measured 4.8e-4; the
    /// library's Newton form is 1e-7), so it is held to 2e-3 only and must stay a cubic (a
    /// wrong coefficient errs by far more).
    #[test]
    fn c_peers_agree_with_the_f64_models() {
        let errors = peer_errors();
        let ids: Vec<&str> = errors.iter().map(|e| e.0).collect();
        assert_eq!(
            ids,
            [
                "pow", "sg", "power4", "power8", "power16", "cubic", "schlick", "beckmann", "ggx"
            ]
        );
        for (id, peer, kernel) in errors {
            let bound = if id == "cubic" { 2e-3 } else { 1e-5 };
            assert!(
                peer <= bound,
                "{id}: C peer errs by {peer:e} (bound {bound:e})"
            );
            assert!(kernel <= 1e-5, "{id}: kernel errs by {kernel:e}");
        }
    }

    /// A peer of no registered model, and the peers' parameters in the CLI's form.
    #[test]
    fn peers_name_their_models_and_parameters() {
        assert!(Peer::new("gauss", 200.0).is_none());
        let p = Peer::new("beckmann", 0.3).unwrap();
        assert_eq!(
            (p.params_text().as_str(), p.function),
            ("alpha=0.3", "peer_beckmann")
        );
        for p in peers() {
            assert_eq!(p.spec.id(), p.id);
            assert!(p.spec.model::<f64>().is_ok(), "{}", p.id);
            assert_eq!(p.function, format!("peer_{}", p.id));
        }
    }

    #[test]
    fn spread_is_the_median_and_quartiles() {
        let s = Spread::of(&[5.0, 1.0, 3.0, 2.0, 4.0]);
        assert_eq!(
            s,
            Spread {
                median: 3.0,
                q1: 2.0,
                q3: 4.0,
                min: 1.0,
                max: 5.0
            }
        );
        let s = Spread::of(&[1.0, 2.0]);
        assert_eq!((s.median, s.q1, s.q3), (1.5, 1.25, 1.75));
        assert_eq!(Spread::of(&[7.0]).values(), [7.0; 5]);
    }

    /// The race's rows (not their timings): one per selected peer, every figure a possible
    /// measurement, the ratio the kernel's rate over the peer's, FTZ/DAZ read on x86-64.
    #[test]
    fn peer_rows_have_every_field() {
        let cos = Inputs::new(4096).cos;
        let opts = PeerOptions {
            rounds: 3,
            round: Duration::from_micros(1),
        };
        let models = vec!["power16".to_string(), "beckmann".into(), "ward".into()];
        let rows = peer_rows(&models, &cos, &opts).unwrap();
        let ids: Vec<&str> = rows.iter().map(|r| r.model.as_str()).collect();
        assert_eq!(ids, ["power16", "beckmann"]);
        for r in &rows {
            assert_eq!((r.batch, r.rounds), (4096, 3));
            assert!(r.repeats >= 1);
            for s in [&r.kernel_evals_per_s, &r.peer_evals_per_s, &r.ratio] {
                assert!(
                    s.values().iter().all(|x| x.is_finite() && *x > 0.0),
                    "{r:?}"
                );
                assert!(s.min <= s.q1 && s.q1 <= s.median && s.median <= s.q3 && s.q3 <= s.max);
            }
            assert!(
                r.kernel_max_error <= 1e-5 && r.peer_max_error <= 1e-5,
                "{r:?}"
            );
            assert_eq!(
                (r.compiler.as_str(), r.flags.as_str()),
                (PEER_COMPILER, PEER_FLAGS)
            );
            assert!(r.flags.starts_with("-O3"));
            assert_eq!(r.ftz.is_some(), cfg!(target_arch = "x86_64"));
        }
        assert_eq!(rows[1].params, "alpha=0.3");
        assert!(ftz_note(ftz_daz()).contains("FTZ"));
    }
}
