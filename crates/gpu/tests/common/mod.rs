//! The GPU the tests share. Without an adapter the tests skip, except when `CI` is set: there
//! a missing driver is a failure (the README's test command installs Mesa's lavapipe).

#![allow(dead_code)]

use fastbrdf_gpu::Gpu;
use std::sync::OnceLock;

pub fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Option<Gpu>> = OnceLock::new();
    GPU.get_or_init(|| match Gpu::new() {
        Ok(g) => {
            eprintln!("GPU tests on {}", g.label());
            Some(g)
        }
        Err(e) => {
            if std::env::var_os("CI").is_some() {
                panic!("CI is set and there is no GPU adapter: {e}");
            }
            eprintln!("skipping GPU tests: {e}");
            None
        }
    })
    .as_ref()
}

/// The parameter sets the GPU tests run: `fastbrdf::accuracy::domain_configs` (light), except
/// that cook-torrance's energy compensation (`ms` other than `none`) is kept in one
/// configuration per method (the first, with `f = none`): its shader carries a 32 x 32 table
/// that lavapipe's LLVM takes about 30 s to compile, per shader. The CPU tests run every
/// configuration; the compensated WGSL reads the same table with the same arithmetic as the
/// CPU (`fastbrdf::microfacet::ms`), so one configuration per method checks the twin.
///
/// CI size: cook-torrance's light domain is about 6,500 configurations of 1,640 combinations
/// of its choice parameters (the values that are not numbers: `d`, `g`, `f`, `ms`,
/// `denominator`, `remap`, ...). Each combination is its own shader, which lavapipe's LLVM
/// compiles in about 0.05 s per coefficient form, cold (measured with
/// `MESA_SHADER_CACHE_DISABLE=true`): minutes over three forms, on a fresh machine, before
/// each configuration is run (the rest of `exact`'s 12.6 cold minutes were the compensated
/// shaders, [`forms`]). The CI size is an all-pairs cover (combinatorial testing):
/// a set of configurations, picked greedily from the full list in its order, in which every
/// pair of parameter values (choices and numbers alike) that occurs together in some full
/// configuration occurs together in at least one kept configuration. Every choice value is
/// thus compiled and run beside every value of every other parameter; what only a combination
/// of three or more would show is left to `FASTBRDF_FULL=1`, which runs them all
/// (docs/book/src/test-suite.md).
pub fn gpu_configs(info: &fastbrdf::ModelInfo) -> Vec<Vec<(String, String)>> {
    let all = gpu_configs_full(info);
    if info.id != "cook-torrance" || full() {
        return all;
    }
    all_pairs(all)
}

/// The coefficient forms a GPU test compiles configuration `config` of `info` in: storage,
/// literals and symbolic (BRDF Explorer's sliders), except, in CI size, cook-torrance's
/// energy compensation (`ms` other than `none`): storage alone. Its shader carries the 32 x 32
/// table, which lavapipe's LLVM took 135 s (kulla-conty) and 40 s (filament) to compile per
/// form, cold: 525 s of `exact`'s 620. The table's code is the same in every form (the forms
/// differ in how the coefficients reach it), and every form of every other configuration is
/// still checked; `FASTBRDF_FULL=1` checks all three.
pub fn forms(info: &fastbrdf::ModelInfo, config: &[(String, String)]) -> &'static [&'static str] {
    let compensated = config.iter().any(|(k, v)| k == "ms" && v != "none");
    if info.id == "cook-torrance" && compensated && !full() {
        &["storage"]
    } else {
        &["storage", "literals", "symbolic"]
    }
}

/// The configurations of `all` kept by a greedy all-pairs cover ([`gpu_configs`]): repeatedly
/// the first configuration that covers the most pairs not covered yet, until every pair of
/// `all` is covered; in the order of `all`.
pub fn all_pairs(all: Vec<Vec<(String, String)>>) -> Vec<Vec<(String, String)>> {
    use std::collections::HashMap;
    // Each configuration as the ids of its pairs of (name, value)s.
    let mut value_id = HashMap::new();
    let mut pair_id = HashMap::new();
    let covers: Vec<Vec<usize>> = all
        .iter()
        .map(|c| {
            let ids: Vec<usize> = c
                .iter()
                .map(|nv| {
                    let n = value_id.len();
                    *value_id.entry(nv).or_insert(n)
                })
                .collect();
            let mut v = vec![];
            for (i, &a) in ids.iter().enumerate() {
                for &b in &ids[i + 1..] {
                    let n = pair_id.len();
                    v.push(*pair_id.entry((a, b)).or_insert(n));
                }
            }
            v
        })
        .collect();
    let mut open = vec![true; pair_id.len()];
    let mut left = open.len();
    let mut keep = vec![false; all.len()];
    while left > 0 {
        let (best, gain) = covers
            .iter()
            .enumerate()
            .filter(|(k, _)| !keep[*k])
            .map(|(k, c)| (k, c.iter().filter(|&&p| open[p]).count()))
            .fold((0, 0), |a, b| if b.1 > a.1 { b } else { a });
        assert!(gain > 0, "an open pair no configuration covers");
        keep[best] = true;
        for &p in &covers[best] {
            left -= open[p] as usize;
            open[p] = false;
        }
    }
    all.into_iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(c, _)| c)
        .collect()
}

/// Whether configuration `config` of model `id` has one of the shaders lavapipe takes minutes
/// to compile, cold: its 32 x 32 tables are constant arrays that WGSL indexes at run time
/// through a local copy, and LLVM chews on the copy (measured with
/// `MESA_SHADER_CACHE_DISABLE=true`, one shader: cook-torrance `ms=kulla-conty` 130 s,
/// `ms=filament` 40 s, sheen-albedo-table 133 s). Such shaders are compiled on their own device
/// ([`on_own_gpu`]), beside the rest.
pub fn slow_to_compile(id: &str, config: &[(String, String)]) -> bool {
    id == "sheen-albedo-table"
        || (id == "cook-torrance" && config.iter().any(|(k, v)| k == "ms" && v != "none"))
}

/// Runs `f` on a thread with a device of its own, and returns its handle. lavapipe compiles a
/// shader on its device's queue thread, one at a time, so the tests' shared device ([`gpu`])
/// compiles one shader at once, on one core; a second device compiles beside it, and CI's
/// second core is used. Under CI a missing adapter fails, as in [`gpu`]; otherwise the thread
/// returns `None`.
pub fn on_own_gpu<T: Send + 'static>(
    f: impl FnOnce(&Gpu) -> T + Send + 'static,
) -> std::thread::JoinHandle<Option<T>> {
    std::thread::spawn(move || match Gpu::new() {
        Ok(g) => Some(f(&g)),
        Err(e) => {
            if std::env::var_os("CI").is_some() {
                panic!("CI is set and there is no GPU adapter: {e}");
            }
            None
        }
    })
}

/// A check of some configurations of one model on a GPU: how many checks it made, and the
/// failures.
pub type Check = fn(&Gpu, &fastbrdf::ModelInfo, &[Vec<(String, String)>]) -> (usize, Vec<String>);

/// Runs `check` over every model's [`gpu_configs`]: those [`slow_to_compile`] each on a device
/// of its own ([`on_own_gpu`], started first), the rest on `gpu`, model by model
/// ([`report_time`]). Returns the checks made and the failures.
pub fn check_every_model(gpu: &Gpu, check: Check) -> (usize, Vec<String>) {
    let mut slow = vec![];
    for e in fastbrdf::registry::all() {
        let info = &e.info;
        for config in gpu_configs(info) {
            if slow_to_compile(info.id, &config) {
                slow.push(on_own_gpu(move |g| {
                    let t = std::time::Instant::now();
                    let r = check(g, info, std::slice::from_ref(&config));
                    report_time(info.id, 1, t);
                    r
                }));
            }
        }
    }
    let (mut checked, mut failures) = (0, vec![]);
    for e in fastbrdf::registry::all() {
        let info = &e.info;
        let t = std::time::Instant::now();
        let configs: Vec<_> = gpu_configs(info)
            .into_iter()
            .filter(|c| !slow_to_compile(info.id, c))
            .collect();
        let (n, f) = check(gpu, info, &configs);
        checked += n;
        failures.extend(f);
        report_time(info.id, configs.len(), t);
    }
    for h in slow {
        if let Some((n, f)) = h.join().expect("a check on its own device panicked") {
            checked += n;
            failures.extend(f);
        }
    }
    (checked, failures)
}

/// Model `id` with parameters `given` in coefficient form `form`: "storage" (coefficients in a
/// buffer), "literals" (inline) or any other name for the runtime form (BRDF Explorer's
/// sliders); panics on a bad spec.
pub fn instance(id: &str, given: &[(&str, &str)], form: &str) -> fastbrdf_gpu::spec::Instance {
    use fastbrdf_gpu::spec::Instance;
    match form {
        "storage" => Instance::with_storage(&spec(id, given)).unwrap(),
        "literals" => Instance::new(&spec(id, given)).unwrap(),
        _ => Instance::runtime(&spec(id, given)).unwrap().runtime_entry(),
    }
}

/// Whether `FASTBRDF_FULL=1` asks for the full sizes ([`gpu_configs`], [`forms`]).
pub fn full() -> bool {
    std::env::var("FASTBRDF_FULL").is_ok_and(|v| v == "1")
}

/// With `FASTBRDF_PARITY_TIMES` set, prints model `id`'s time since `t` over its `n`
/// configurations (`parity`, `exact`, `finite`: on lavapipe, cold, mostly its shaders'
/// compilation, which shows the models that cost CI).
pub fn report_time(id: &str, n: usize, t: std::time::Instant) {
    if std::env::var_os("FASTBRDF_PARITY_TIMES").is_some() {
        let s = t.elapsed().as_secs_f64();
        eprintln!("{id:<28} {n:>4} configurations {s:>7.1} s");
    }
}

/// [`gpu_configs`] before its CI size: every configuration the GPU tests can run.
pub fn gpu_configs_full(info: &fastbrdf::ModelInfo) -> Vec<Vec<(String, String)>> {
    let get = |c: &[(String, String)], k: &str| {
        c.iter()
            .find(|(n, _)| n == k)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    let mut seen = std::collections::BTreeSet::new();
    fastbrdf::accuracy::domain_configs(info, true)
        .iter()
        .map(|s| s.pairs())
        .filter(|c| {
            // sheen-albedo-table: the sheen tables are such arrays too (two 32 x 32): one
            // configuration, the 8-bit rounding.
            if info.id == "sheen-albedo-table" {
                return get(c, "v") == "charlie" && get(c, "bits") == "8";
            }
            // env-brdf-table: its tables are such arrays too (~14 s per configuration at 16 x
            // 16): one configuration, the half-float storage's bit rounding, at the smallest size.
            if info.id == "env-brdf-table" {
                return get(c, "size") == "16"
                    && get(c, "bits") == "16"
                    && get(c, "term") == "bias";
            }
            // gltf-pbr: its choice product is about 1,000 sets and lavapipe compiles each
            // configuration's shader in three coefficient forms (tens of seconds each, cold:
            // the longest part of CI). So: the configurations that bring a choice value not
            // seen yet among d, f, diffuse, sheen_v and the untabled sheen albedos (3; the
            // seven g terms are the same WGSL functions cook-torrance's configurations check,
            // and one call site wires them in); the specular albedo scaling in one,
            // MaterialX's fit (no table; env-brdf-table's twin is checked as its own model).
            // The energy compensation's table is such an array too (about 30 s a form, cold):
            // its twin is checked through cook-torrance's configurations, and gltf-pbr's call
            // of it by naga (`fastbrdf shader --model gltf-pbr --param ms=kulla-conty`), not on
            // lavapipe. The CPU tests run them all.
            if info.id == "gltf-pbr" {
                let (sa, ms) = (get(c, "spec_albedo"), get(c, "ms"));
                let plain = |x: &str, none: &str| x.is_empty() || x == none;
                if !plain(&sa, "fresnel") || !plain(&ms, "none") {
                    return sa == "materialx"
                        && ms == "none"
                        && get(c, "sheen_albedo") != "table"
                        && seen.insert("gltf-pbr spec_albedo".to_string());
                }
                // Not the sheen albedo table: lavapipe compiles its two 32 x 32 constant arrays
                // (copied into a local per call, `fb_sheen_table`) for minutes per form, cold;
                // the table's data is checked on the GPU by sheen-albedo-table, gltf-pbr's call
                // by naga (`fastbrdf shader --model gltf-pbr`, the default). See issue 33's note.
                if get(c, "sheen_albedo") == "table" {
                    return false;
                }
                let pairs: Vec<String> = ["d", "f", "diffuse", "sheen_v", "sheen_albedo"]
                    .iter()
                    .map(|k| format!("gltf-pbr {k}={}", get(c, k)))
                    .collect();
                let new = pairs.iter().any(|p| !seen.contains(p));
                seen.extend(pairs);
                return new;
            }
            let ms = get(c, "ms");
            if ms.is_empty() || ms == "none" {
                return true;
            }
            get(c, "f") == "none" && seen.insert(ms)
        })
        .collect()
}

/// The spec of model `id` with parameters given as text (as the CLI parses them); panics with
/// the error on a bad one.
pub fn spec(id: &str, given: &[(&str, &str)]) -> fastbrdf::ModelSpec {
    fastbrdf::ModelSpec::parse(id, given).unwrap_or_else(|e| panic!("{id} {given:?}: {e}"))
}

/// A file of `tests/data/` (users' shaders: `brdf-explorer/`, `user/`).
pub fn data(p: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(p)
}

/// `(name, value)` pairs as owned strings (the `given` values of `fastbrdf_gpu::user`).
pub fn owned(given: &[(&str, &str)]) -> Vec<(String, String)> {
    given
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// How many pixels of `scene` (rendered on `g` with `o`) differ in their bits between the
/// per-scene shader (`fastbrdf_gpu::render::features`: the parts no object uses left out)
/// and the shader with every part on.
pub fn pixels_unlike_every_part_on(
    g: &Gpu,
    scene: &fastbrdf_render::scene::Scene,
    o: &fastbrdf_render::render::Options,
) -> usize {
    use fastbrdf_gpu::render::{features::force_all, render};
    force_all(false);
    let per_scene = render(&g.device, &g.queue, scene, o).unwrap();
    force_all(true);
    let all = render(&g.device, &g.queue, scene, o);
    force_all(false);
    let bits = |p: &glam::Vec3| p.to_array().map(f32::to_bits);
    (per_scene.pixels.iter().zip(&all.unwrap().pixels))
        .filter(|(a, b)| bits(a) != bits(b))
        .count()
}
