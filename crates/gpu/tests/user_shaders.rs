//! A user's own BRDF shader on the GPU (`fastbrdf_gpu::user`, issue 31): every BRDF Explorer
//! sample file loads and evaluates; two of them equal the library's own models; a WGSL and a
//! GLSL function model equal their formulas in f64; a shader's sampler is consistent with its
//! pdf; bad parameters, compile errors, non-UTF-8 and oversized files are clean errors naming
//! the file (and line and column).
//!
//! Parsing and translation run without a GPU; evaluation skips without an adapter unless `CI`
//! is set (`tests/common`).

mod common;
use common::{data, owned};

use fastbrdf::user::{Builtin, UserBrdf};
use fastbrdf_gpu::Gpu;
use fastbrdf_gpu::user::{
    GpuBrdf, Language, ParamKind, ParamValue, UserErrorKind, UserShader, load,
};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn compile(gpu: &Gpu, path: &Path, given: &[(&str, &str)]) -> GpuBrdf {
    let s = UserShader::load(path).unwrap_or_else(|e| panic!("{e}"));
    GpuBrdf::new(&gpu.device, &gpu.queue, s, &owned(given)).unwrap_or_else(|e| panic!("{e}"))
}

/// splitmix64: reproducible numbers in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A direction uniform on the upper hemisphere (z >= `zmin`).
    fn upper(&mut self, zmin: f64) -> [f64; 3] {
        let z = zmin + (1.0 - zmin) * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * self.next();
        [r * phi.cos(), r * phi.sin(), z]
    }

    fn pairs(&mut self, n: usize, zmin: f64) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        (0..n).map(|_| (self.upper(zmin), self.upper(zmin))).unzip()
    }
}

/// Rounded to f32 and back, as the GPU receives it.
fn f32s(v: [f64; 3]) -> [f64; 3] {
    v.map(|x| f64::from(x as f32))
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn explorer_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(data("brdf-explorer"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "brdf"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_brdf_explorer_sample_parses_and_translates() {
    let files = explorer_files();
    assert_eq!(files.len(), 31, "{files:?}");
    for f in &files {
        let s = UserShader::load(f).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.language(), Language::Brdf);
        assert_eq!(s.channels(), 3);
        assert!(!s.samples());
        let w = s.wgsl().unwrap();
        assert!(w.contains("fn fb_user_brdf("), "{}:\n{w}", f.display());
        // The translation is valid WGSL on its own (naga's WGSL front end and validator).
        let m = naga::front::wgsl::parse_str(&w).unwrap_or_else(|e| panic!("{w}\n{e}"));
        naga::valid::Validator::new(Default::default(), Default::default())
            .validate(&m)
            .unwrap();
    }
    let walter = UserShader::load(&data("brdf-explorer/walter.brdf")).unwrap();
    let names: Vec<&str> = walter.params().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["Kd", "Ks", "alphaG", "ior", "useFresnel"]);
    assert_eq!(
        walter.params()[2].kind,
        ParamKind::Float {
            min: 0.001,
            max: 1.0,
            default: 0.1
        }
    );
    let ward = UserShader::load(&data("brdf-explorer/ward.brdf")).unwrap();
    assert!(matches!(ward.params()[2].kind, ParamKind::Color { default } if default == [1.0; 3]));
    // The splice point moves where the host wants it.
    assert!(
        walter
            .wgsl_at(3, 7)
            .unwrap()
            .contains("@group(3) @binding(7)")
    );
}

#[test]
fn every_brdf_explorer_sample_evaluates_on_the_gpu() {
    let Some(gpu) = common::gpu() else { return };
    let mut rng = Rng(31);
    let (wi, wo) = rng.pairs(1000, 0.0);
    for f in explorer_files() {
        let m = compile(gpu, &f, &[]);
        assert_eq!(m.channels(), 3);
        assert_eq!(m.name(), format!("file:{}", f.display()));
        let mut out = vec![0.0; 3 * wi.len()];
        m.eval(&wi, &wo, &mut out)
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let finite = out.iter().filter(|v| v.is_finite()).count();
        assert!(finite > out.len() / 2, "{}: {finite} finite", f.display());
    }
    // The file's own `reflect` (the mirror direction 2 (L.N) N - L), not GLSL's built-in
    // (L - 2 (N.L) N, pointing into the surface): at the mirror pair modifiedphong.brdf is
    // (n + 2) / (2 pi) with n = 1.
    let m = compile(gpu, &data("brdf-explorer/modifiedphong.brdf"), &[]);
    let mut out = [0.0; 3];
    m.eval(&[[0.6, 0.0, 0.8]], &[[-0.6, 0.0, 0.8]], &mut out)
        .unwrap();
    assert!((out[0] - 3.0 / (2.0 * PI)).abs() < 1e-6, "{out:?}");
    // A local named like a function, initialised by calling it: `float G = G(NdotL, m) *
    // G(NdotV, m)` in g_schlick.brdf, with the parameter m shadowed by G's argument.
    let m = compile(gpu, &data("brdf-explorer/g_schlick.brdf"), &[("m", "0.5")]);
    m.eval(&[[0.6, 0.0, 0.8]], &[[0.0, 0.0, 1.0]], &mut out)
        .unwrap();
    let k = (2.0 * 0.25 / PI).sqrt();
    let g = |v: f64| v / (v - k * v + k);
    assert!((out[0] - g(0.8) * g(1.0)).abs() < 1e-6, "{out:?}");
    // lambert.brdf is reflectance / 3.14159265 everywhere, in f32.
    let m = compile(
        gpu,
        &data("brdf-explorer/lambert.brdf"),
        &[("reflectance", "0.5")],
    );
    let mut out = vec![0.0; 3 * wi.len()];
    m.eval(&wi, &wo, &mut out).unwrap();
    // 3.14159265 is pi in f32.
    let want = f64::from(0.5f32 / std::f32::consts::PI);
    assert!(
        out.iter().all(|&v| (v - want).abs() <= 1e-7),
        "{:?}",
        &out[..6]
    );
}

/// The largest |got - want| over `peak` (the largest |want|) and the largest relative error.
fn errors(got: &[f64], want: &[f64]) -> (f64, f64) {
    let peak = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    let (mut abs, mut rel) = (0.0f64, 0.0f64);
    for (g, w) in got.iter().zip(want) {
        assert!(g.is_finite() && w.is_finite(), "{g} vs {w}");
        abs = abs.max((g - w).abs());
        rel = rel.max((g - w).abs() / w.abs().max(1e-3 * peak));
    }
    (abs / peak, rel)
}

/// f32 arithmetic of the `.brdf` formulas on inputs as given: `1 - cos^2` of a rounded
/// `cos theta_h` near 1 costs about 2^-23 / alpha^2 of `D` (2.4e-5 at alpha = 0.1), so the
/// bound is 5e-5 of the largest value and 1e-4 relative; a parameter off by 1% fails both.
const OF_PEAK: f64 = 5e-5;
const RELATIVE: f64 = 1e-4;

#[test]
fn d_ggx_brdf_is_the_ggx_distribution() {
    let Some(gpu) = common::gpu() else { return };
    let m = compile(gpu, &data("brdf-explorer/d_ggx.brdf"), &[("alpha", "0.1")]);
    let spec = common::spec("ggx", &[("alpha", "0.1")]);
    let fastbrdf::Model::Distribution(d) = spec.model::<f64>().unwrap() else {
        panic!("ggx is a distribution")
    };
    let mut rng = Rng(7);
    let (mut wi, mut wo) = rng.pairs(20_000, 0.02);
    // The peak itself, and pairs close to it.
    wi.push([0.0, 0.0, 1.0]);
    wo.push([0.0, 0.0, 1.0]);
    for k in 0..200 {
        let t = 1e-3 * k as f64;
        wi.push([t.sin(), 0.0, t.cos()]);
        wo.push([-(0.5 * t).sin(), 0.0, (0.5 * t).cos()]);
    }
    let mut out = vec![0.0; 3 * wi.len()];
    m.eval(&wi, &wo, &mut out).unwrap();
    let got: Vec<f64> = out.chunks(3).map(|c| c[0]).collect();
    assert!(out.chunks(3).all(|c| c[0] == c[1] && c[1] == c[2]));
    let want: Vec<f64> = (0..wi.len())
        .map(|k| d.eval(normalize(add(f32s(wi[k]), f32s(wo[k])))[2]))
        .collect();
    let (of_peak, rel) = errors(&got, &want);
    eprintln!(
        "d_ggx.brdf against ggx alpha=0.1: max error {of_peak:.2e} of the peak, {rel:.2e} relative"
    );
    assert!(of_peak <= OF_PEAK && rel <= RELATIVE, "{of_peak:e} {rel:e}");
}

#[test]
fn walter_brdf_is_cook_torrance_with_ggx_and_smith() {
    let Some(gpu) = common::gpu() else { return };
    // Ks multiplies the specular term (default 0.1): 1 here; no diffuse, no Fresnel.
    let given = [
        ("Kd", "0"),
        ("Ks", "1"),
        ("alphaG", "0.1"),
        ("useFresnel", "0"),
    ];
    let m = compile(gpu, &data("brdf-explorer/walter.brdf"), &given);
    let spec = common::spec(
        "cook-torrance",
        &[
            ("alpha", "0.1"),
            ("d", "ggx"),
            ("g", "smith-ggx"),
            ("f", "none"),
        ],
    );
    let b = Builtin::new(&spec, fastbrdf::sample::Strategy::Auto).unwrap();
    let mut rng = Rng(11);
    let (wi, wo) = rng.pairs(20_000, 0.02);
    let (wi, wo): (Vec<_>, Vec<_>) = wi
        .into_iter()
        .map(f32s)
        .zip(wo.into_iter().map(f32s))
        .unzip();
    let mut out = vec![0.0; 3 * wi.len()];
    m.eval(&wi, &wo, &mut out).unwrap();
    let got: Vec<f64> = out.chunks(3).map(|c| c[0]).collect();
    let mut want = vec![0.0; wi.len()];
    b.eval(&wi, &wo, &mut want).unwrap();
    let (of_peak, rel) = errors(&got, &want);
    eprintln!(
        "walter.brdf against cook-torrance d=ggx g=smith-ggx f=none: max error {of_peak:.2e} of the peak, {rel:.2e} relative"
    );
    assert!(of_peak <= OF_PEAK && rel <= RELATIVE, "{of_peak:e} {rel:e}");
}

/// GGX with the uncorrelated Smith term, in f64: `ggx_sampled.wgsl`'s model, written apart.
fn ggx_smith(wi: [f64; 3], wo: [f64; 3], alpha: f64) -> f64 {
    if wi[2] <= 0.0 || wo[2] <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let c = normalize(add(wi, wo))[2];
    let d = a2 / (PI * (c * c * (a2 - 1.0) + 1.0).powi(2));
    // G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)).
    let g1 = |z: f64| 2.0 / (1.0 + (1.0 + a2 * (1.0 - z * z) / (z * z)).sqrt());
    d * g1(wi[2]) * g1(wo[2]) / (4.0 * wi[2] * wo[2])
}

#[test]
fn a_wgsl_function_model_evaluates_its_formula() {
    let Some(gpu) = common::gpu() else { return };
    let m = compile(
        gpu,
        &data("user/ggx_sampled.wgsl"),
        &[("alpha", "0.2"), ("scale", "0.5")],
    );
    assert_eq!(m.channels(), 1);
    assert!(m.samples());
    let mut rng = Rng(3);
    let (wi, wo) = rng.pairs(10_000, 0.05);
    let (wi, wo): (Vec<_>, Vec<_>) = wi
        .into_iter()
        .map(f32s)
        .zip(wo.into_iter().map(f32s))
        .unzip();
    let mut got = vec![0.0; wi.len()];
    m.eval(&wi, &wo, &mut got).unwrap();
    let want: Vec<f64> = (0..wi.len())
        .map(|k| 0.5 * ggx_smith(wi[k], wo[k], 0.2))
        .collect();
    let (of_peak, rel) = errors(&got, &want);
    eprintln!("ggx_sampled.wgsl: max error {of_peak:.2e} of the peak, {rel:.2e} relative");
    assert!(of_peak <= OF_PEAK && rel <= RELATIVE, "{of_peak:e} {rel:e}");
    // Below the horizon: 0, as the shader says.
    let mut out = [1.0];
    m.eval(&[[0.0, 0.6, -0.8]], &[[0.0, 0.0, 1.0]], &mut out)
        .unwrap();
    assert_eq!(out[0], 0.0);
}

#[test]
fn a_glsl_function_model_evaluates_its_formula() {
    let Some(gpu) = common::gpu() else { return };
    let path = data("user/blinn_phong.glsl");
    let kd = [0.2, 0.4, 0.6];
    for diffuse in [true, false] {
        let on = if diffuse { "1" } else { "false" };
        let given = [("n", "20"), ("kd", "0.2, 0.4, 0.6"), ("diffuse", on)];
        let m = compile(gpu, &path, &given);
        assert_eq!(m.channels(), 3);
        assert!(!m.samples());
        let mut rng = Rng(5);
        let (wi, wo) = rng.pairs(5_000, 0.01);
        let (wi, wo): (Vec<_>, Vec<_>) = wi
            .into_iter()
            .map(f32s)
            .zip(wo.into_iter().map(f32s))
            .unzip();
        let mut got = vec![0.0; 3 * wi.len()];
        m.eval(&wi, &wo, &mut got).unwrap();
        let mut want = Vec::new();
        for k in 0..wi.len() {
            let h = normalize(add(wi[k], wo[k]));
            let spec = 28.0 / (8.0 * PI) * h[2].max(0.0).powf(20.0);
            for c in kd {
                want.push(spec + if diffuse { c / PI } else { 0.0 });
            }
        }
        let (of_peak, rel) = errors(&got, &want);
        eprintln!(
            "blinn_phong.glsl diffuse={diffuse}: max error {of_peak:.2e} of the peak, {rel:.2e} relative"
        );
        assert!(of_peak <= OF_PEAK && rel <= RELATIVE, "{of_peak:e} {rel:e}");
    }
}

/// `n` pairs `wo`, `u` for samplers.
fn sample_inputs(n: usize, seed: u64) -> (Vec<[f64; 3]>, Vec<[f64; 2]>) {
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| (rng.upper(0.05), [rng.next(), rng.next()]))
        .unzip()
}

#[test]
fn a_shader_sampler_agrees_with_its_pdf_and_its_brdf() {
    let Some(gpu) = common::gpu() else { return };
    let m = compile(gpu, &data("user/ggx_sampled.wgsl"), &[("alpha", "0.3")]);
    let (wo, u) = sample_inputs(4096, 17);
    let s = m.sample(&wo, &u).unwrap();
    let valid: Vec<usize> = (0..wo.len()).filter(|&k| s.valid[k]).collect();
    assert!(
        valid.len() > wo.len() * 3 / 4,
        "{} of {}",
        valid.len(),
        wo.len()
    );
    let wi: Vec<[f64; 3]> = valid.iter().map(|&k| s.wi[k]).collect();
    let wv: Vec<[f64; 3]> = valid.iter().map(|&k| wo[k]).collect();
    let mut pdf = vec![0.0; wi.len()];
    m.pdf(&wv, &wi, &mut pdf).unwrap();
    let mut f = vec![0.0; wi.len()];
    m.eval(&wi, &wv, &mut f).unwrap();
    for (j, &k) in valid.iter().enumerate() {
        let len = (wi[j][0].powi(2) + wi[j][1].powi(2) + wi[j][2].powi(2)).sqrt();
        assert!((len - 1.0).abs() < 1e-5, "|wi| = {len}");
        assert!(wi[j][2] > 0.0);
        // pdf(sample) is the pdf the sampler reported.
        assert!(
            (pdf[j] - s.pdf[k]).abs() <= 1e-5 * s.pdf[k],
            "{} vs {}",
            pdf[j],
            s.pdf[k]
        );
        // The weight is f cos / pdf, and the pdf is the formula's in f64.
        let w = f[j] * wi[j][2] / s.pdf[k];
        assert!(
            (s.weight[k] - w).abs() <= 1e-4 * w,
            "{} vs {w}",
            s.weight[k]
        );
        let h = normalize(add(wi[j], wv[j]));
        let a2 = 0.09;
        let d = a2 / (PI * (h[2] * h[2] * (a2 - 1.0) + 1.0).powi(2));
        let want = d * h[2] / (4.0 * (h[0] * wv[j][0] + h[1] * wv[j][1] + h[2] * wv[j][2]));
        assert!(
            (pdf[j] - want).abs() <= 1e-4 * want,
            "pdf {} vs {want}",
            pdf[j]
        );
    }
    // Rows without a sample (wi below the surface) are reported as such.
    assert!(valid.len() < wo.len());
    let k = (0..wo.len()).find(|&k| !s.valid[k]).unwrap();
    assert_eq!((s.pdf[k], s.weight[k]), (0.0, 0.0));
}

#[test]
fn the_broken_samplers_are_broken_as_they_say() {
    let Some(gpu) = common::gpu() else { return };
    let (wo, u) = sample_inputs(4096, 23);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // pdf 5% too large, weight consistent with it.
    let m = compile(gpu, &data("user/broken_pdf_scaled.wgsl"), &[]);
    let s = m.sample(&wo, &u).unwrap();
    assert!(s.valid.iter().all(|&v| v));
    for k in 0..wo.len() {
        let want = 1.05 * s.wi[k][2] / PI;
        assert!((s.pdf[k] - want).abs() <= 1e-5 * want);
        assert!((s.weight[k] - 1.0 / 1.05).abs() <= 1e-5);
    }
    // The weight without the cosine: the shader's own brdf_weight, 1 / cos.
    let m = compile(gpu, &data("user/broken_weight_no_cosine.wgsl"), &[]);
    assert!(m.shader().own_weight());
    let s = m.sample(&wo, &u).unwrap();
    for k in 0..wo.len() {
        assert!(
            (s.weight[k] * s.wi[k][2] - 1.0).abs() <= 1e-4,
            "{}",
            s.weight[k]
        );
    }
    // No samples past 60 degrees, where f is not zero: mean weight 0.75.
    let m = compile(gpu, &data("user/broken_pdf_zero.wgsl"), &[]);
    let s = m.sample(&wo, &u).unwrap();
    assert!(s.wi.iter().all(|w| w[2] >= 0.5 - 1e-6));
    assert!((mean(&s.weight) - 0.75).abs() < 1e-4, "{}", mean(&s.weight));
    let mut p = [1.0];
    m.pdf(&[[0.0, 0.0, 1.0]], &[[0.9, 0.0, 0.4]], &mut p)
        .unwrap();
    let mut f = [0.0];
    m.eval(&[[0.0, 0.0, 1.0]], &[[0.9, 0.0, 0.4]], &mut f)
        .unwrap();
    assert!(p[0] == 0.0 && f[0] > 0.3, "pdf {} f {}", p[0], f[0]);
}

#[test]
fn the_broken_brdf_files_are_broken_as_they_say() {
    let Some(gpu) = common::gpu() else { return };
    let one = |name: &str, wi: [f64; 3], wo: [f64; 3]| {
        let m = compile(gpu, &data(&format!("user/{name}")), &[]);
        let mut out = [0.0; 3];
        m.eval(&[wi], &[wo], &mut out).unwrap();
        out[0]
    };
    let (a, b) = ([0.6, 0.0, 0.8], [0.0, 0.0, 1.0]);
    let f = one("broken_nonreciprocal.brdf", a, b);
    let r = one("broken_nonreciprocal.brdf", b, a);
    assert!(
        (f - 0.9 / PI).abs() < 1e-6 && (r - 1.0 / PI).abs() < 1e-6,
        "{f} {r}"
    );
    assert!((one("broken_energy_gain.brdf", a, b) - 1.2 / PI).abs() < 1e-6);
    assert!(
        one(
            "broken_negative_lobe.brdf",
            [-0.6, 0.0, 0.8],
            [0.6, 0.0, 0.8]
        ) < -0.1
    );
    assert!((one("broken_nan_grazing.brdf", a, b) - 1.0 / PI).abs() < 1e-6);
    let g = one("broken_nan_grazing.brdf", [1.0, 0.0, 0.0], b);
    // 0 / 0; a driver may fold NaN away (WGSL allows it), lavapipe does not.
    if gpu.is_software() {
        assert!(g.is_nan(), "{g}");
    }
}

#[test]
fn batches_span_chunks_and_two_dimensional_dispatches() {
    let Some(gpu) = common::gpu() else { return };
    let mut m = compile(gpu, &data("user/ggx_sampled.wgsl"), &[]);
    let mut rng = Rng(29);
    let (mut wi, wo) = rng.pairs(2_500, 0.05);
    // Inputs go as given: unnormalised and NaN rows too.
    wi[10] = [0.0, 0.0, 2.0];
    wi[11] = [f64::NAN, 0.0, 1.0];
    let mut whole = vec![0.0; wi.len()];
    m.eval(&wi, &wo, &mut whole).unwrap();
    // 2500 rows in chunks of 1000, 16 workgroups of 64 spread over 3 x 6.
    m.set_limits(3, 1000);
    let mut split = vec![0.0; wi.len()];
    m.eval(&wi, &wo, &mut split).unwrap();
    for k in 0..wi.len() {
        assert!(
            whole[k] == split[k] || (whole[k].is_nan() && split[k].is_nan()),
            "row {k}: {} vs {}",
            whole[k],
            split[k]
        );
    }
    assert!(whole.iter().filter(|v| **v > 0.0).count() > 2_000);
    // Normalised inside the shader's h only: a longer wi changes f.
    let mut unit = [0.0];
    m.eval(&[[0.0, 0.0, 1.0]], &[wo[10]], &mut unit).unwrap();
    assert_ne!(unit[0], whole[10]);
    // Sampling and pdfs span chunks as well.
    let (so, u) = sample_inputs(2_500, 31);
    let s = m.sample(&so, &u).unwrap();
    assert_eq!(s.valid.len(), 2_500);
    assert!(m.eval(&wi, &wo, &mut [0.0; 3]).is_err());
}

fn given(k: &str, v: &str) -> Vec<(String, String)> {
    vec![(k.to_string(), v.to_string())]
}

#[test]
fn bad_parameters_are_input_errors_naming_the_parameter() {
    let path = data("brdf-explorer/walter.brdf");
    let name = format!("file:{}", path.display());
    let e = load(&path, &given("alphaG", "2")).err().unwrap();
    assert_eq!(e.kind, UserErrorKind::Input);
    assert_eq!(
        e.message,
        format!("parameter 'alphaG' of {name}: 2 is outside [0.001, 1]")
    );
    let e = load(&path, &given("alpha", "0.2")).err().unwrap();
    assert_eq!(
        e.message,
        format!("{name} has no parameter 'alpha'; its parameters: Kd, Ks, alphaG, ior, useFresnel")
    );
    let e = load(&path, &given("useFresnel", "maybe")).err().unwrap();
    assert!(
        e.message.contains("'maybe' is not 0, 1, false or true"),
        "{e}"
    );
    let e = load(&path, &given("Ks", "nan")).err().unwrap();
    assert!(e.message.contains("'nan' is not a finite number"), "{e}");
    let ward = UserShader::load(&data("brdf-explorer/ward.brdf")).unwrap();
    let v = ward.values(&given("Cs", "0.5")).unwrap();
    assert_eq!(v[2], ParamValue::Color([0.5; 3]));
    assert!(ward.values(&given("Cs", "1,2")).is_err());
    let lambert = UserShader::load(&data("brdf-explorer/showVectors.brdf")).unwrap();
    let e = lambert
        .values(&[("show_X".into(), "1".into()), ("show_X".into(), "0".into())])
        .unwrap_err();
    assert!(e.message.contains("given twice"), "{e}");
}

/// `origin:line:col: error:` where `alpah` is in the file.
fn where_alpah(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let (k, line) = text
        .lines()
        .enumerate()
        .find(|(_, l)| l.contains("alpah"))
        .unwrap();
    let col = line[..line.find("alpah").unwrap()].chars().count() + 1;
    format!("{}:{}:{col}: error: ", path.display(), k + 1)
}

#[test]
fn compile_errors_name_the_users_file_line_and_column() {
    for f in [
        "compile_error.brdf",
        "compile_error.glsl",
        "compile_error.wgsl",
    ] {
        let path = data(&format!("user/{f}"));
        let e = UserShader::load(&path).unwrap_err();
        assert_eq!(e.kind, UserErrorKind::Input);
        let at = where_alpah(&path);
        assert!(e.message.starts_with(&at), "{f}: want {at}, got\n{e}");
        assert!(e.message.contains("alpah"), "{e}");
        eprintln!("{e}");
    }
    // A missing BRDF, a wrong signature, a lone sampler.
    let e = UserShader::parse("fn f() {}\n", "a.wgsl", Language::Wgsl).unwrap_err();
    assert!(
        e.message
            .starts_with("a.wgsl: error: the shader defines no function fn brdf("),
        "{e}"
    );
    let e = UserShader::parse(
        "// x\nfn brdf(wi: vec3<f32>) -> f32 { return wi.x; }\n",
        "b.wgsl",
        Language::Wgsl,
    )
    .unwrap_err();
    assert!(
        e.message.starts_with("b.wgsl:2:4: error: brdf must be"),
        "{e}"
    );
    let e = UserShader::parse(
        "float brdf(vec3 wi, vec3 wo) { return 1.0; }\nfloat brdf_pdf(vec3 wo, vec3 wi) { return 1.0; }\n",
        "c.glsl",
        Language::Glsl,
    )
    .unwrap_err();
    assert!(
        e.message
            .contains("c.glsl:2:7: error: the shader defines brdf_pdf but not brdf_sample"),
        "{e}"
    );
    let e = UserShader::parse(
        "analytic\n::begin shader\nvec3 brdf(vec3 L) { return L; }\n::end shader\n",
        "d.brdf",
        Language::Brdf,
    )
    .unwrap_err();
    assert!(
        e.message
            .contains("d.brdf: error: the shader block defines no function vec3 BRDF"),
        "{e}"
    );
    // A resource of the shader's own (BRDF Explorer's template uniforms are not declared).
    let e = UserShader::parse(
        "analytic\n::begin shader\nuniform vec3 incidentVector;\n\
         vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return incidentVector; }\n\
         ::end shader\n",
        "f.brdf",
        Language::Brdf,
    )
    .unwrap_err();
    assert!(e.message.starts_with("f.brdf:3:"), "{e}");
    // naga's own words: "uniform/buffer blocks require layout(binding=X)".
    assert!(e.message.contains("binding"), "{e}");
    let e = UserShader::parse(
        "@group(0) @binding(0) var<uniform> k: f32;\n\
         fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 { return k; }\n",
        "g.wgsl",
        Language::Wgsl,
    )
    .unwrap_err();
    assert!(e.message.starts_with("g.wgsl:1:"), "{e}");
    assert!(e.message.contains("'k' is a resource"), "{e}");
    // A type error the validator finds, past the front end, still in the user's lines (naga
    // points at the returned argument's declaration: line 3, column 9).
    let e = UserShader::parse(
        "// x\n\nfn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {\n    return wi;\n}\n",
        "e.wgsl",
        Language::Wgsl,
    )
    .unwrap_err();
    assert!(e.message.starts_with("e.wgsl:3:9: error: "), "{e}");
    assert!(
        e.message
            .contains("does not match the declared return type"),
        "{e}"
    );
}

#[test]
fn unreadable_files_are_clean_errors() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("user_shaders");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("latin1.brdf");
    std::fs::write(&bad, b"analytic\n# caf\xe9\n").unwrap();
    let e = UserShader::load(&bad).unwrap_err();
    assert_eq!(e.kind, UserErrorKind::Input);
    assert_eq!(
        e.message,
        format!(
            "{}:2:6: not UTF-8 text (byte 0xe9); save the shader as UTF-8",
            bad.display()
        )
    );
    let big = dir.join("big.wgsl");
    let mut text = String::from("fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 { return 1.0; }\n");
    text.push_str(&"// padding\n".repeat(500_000));
    std::fs::write(&big, text).unwrap();
    let e = UserShader::load(&big).unwrap_err();
    assert!(e.message.contains("larger than the 4 MiB allowed"), "{e}");
    let e = UserShader::load(&dir.join("missing.wgsl")).unwrap_err();
    assert!(e.message.contains("missing.wgsl: cannot open"), "{e}");
    let e = UserShader::load(&dir).unwrap_err();
    assert!(
        e.message.contains("unknown shader language") || e.message.contains("folder"),
        "{e}"
    );
    let e = UserShader::load(&dir.join("model.hlsl")).unwrap_err();
    assert!(e.message.contains("unknown shader language"), "{e}");
}

#[test]
fn the_wgsl_splices_under_the_documented_contract() {
    let s = UserShader::load(&data("user/ggx_sampled.wgsl")).unwrap();
    let w = s.wgsl().unwrap();
    for want in [
        "fn fb_user_brdf(",
        "fn fb_user_sample(",
        "fn fb_user_pdf(",
        "fn fb_user_weight(",
        "struct FbUserParams",
        "@group(1) @binding(0)",
        "fn fbu_ggx_d(",
    ] {
        assert!(w.contains(want), "{want} missing from\n{w}");
    }
    // The user's names are prefixed, so a host's own `ggx_d` does not collide.
    let host = format!("{w}\nfn ggx_d(c: f32) -> f32 {{ return c; }}\n");
    naga::front::wgsl::parse_str(&host).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&host)));
    let block = s.param_block(&s.values(&given("alpha", "0.5")).unwrap());
    assert_eq!(block, [0.5, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
}

#[test]
fn function_files_tolerate_a_version_line_and_their_own_entry_points() {
    // A GLSL file's `#version` is dropped (line numbers stay the file's).
    let s = UserShader::parse(
        "#version 410\n// param float k 0 2 1\nfloat brdf(vec3 wi, vec3 wo) { return k * wi.z; }\n",
        "v.glsl",
        Language::Glsl,
    )
    .unwrap();
    assert_eq!((s.channels(), s.params().len()), (1, 1));
    let e = UserShader::parse(
        "#version 410\nfloat brdf(vec3 wi, vec3 wo) { return kk; }\n",
        "v.glsl",
        Language::Glsl,
    )
    .unwrap_err();
    assert!(e.message.starts_with("v.glsl:2:39: error: "), "{e}");
    // A WGSL file's own entry point is left out of the module.
    let s = UserShader::parse(
        "fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return wi; }\n\
         @compute @workgroup_size(1) fn main() {}\n",
        "e.wgsl",
        Language::Wgsl,
    )
    .unwrap();
    assert_eq!(s.channels(), 3);
    assert!(!s.wgsl().unwrap().contains("@compute"));
    assert_eq!(
        Language::from_path(Path::new("a/B.BRDF")),
        Some(Language::Brdf)
    );
    assert_eq!(
        Language::from_path(Path::new("m.frag")),
        Some(Language::Glsl)
    );
}
