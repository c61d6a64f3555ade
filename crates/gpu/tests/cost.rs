//! Instruction counts (`fastbrdf_gpu::cost`): the counter on hand-written WGSL of known
//! content, and the committed table of the built-ins (`src/shader_costs.csv`) against a fresh
//! measurement. `FASTBRDF_BLESS=1 cargo test -p fastbrdf-gpu --test cost` rewrites the table
//! (review the diff: `fastbrdf models --json` and `fastbrdf bench` print it).
//!
//! spirv-opt is Debian's `spirv-tools` (`tools/test.sh` installs it). Without it the tests
//! skip with a message, except when `CI` is set: there they fail.

use fastbrdf::ModelSpec;
use fastbrdf_gpu::cost::{self, Counts};
use std::path::PathBuf;

/// Whether spirv-opt runs; `false` (skip) without it; under `CI` a missing one panics.
fn spirv_opt() -> bool {
    match cost::spirv_opt_version() {
        Ok(_) => true,
        Err(e) => {
            if std::env::var_os("CI").is_some() {
                panic!("CI is set and spirv-opt is missing (Debian's spirv-tools): {e}");
            }
            eprintln!("skipping the instruction-count test: {e}");
            false
        }
    }
}

fn counts(src: &str, f: &str) -> Counts {
    cost::of_wgsl(src, f).unwrap_or_else(|e| panic!("{f}: {e}"))
}

#[test]
fn hand_written_functions_count_what_they_contain() {
    if !spirv_opt() {
        return;
    }
    // The wrapper alone counts nothing: its loads and store are not the function's.
    let zero = counts("fn id(c: f32) -> f32 { return c; }", "id");
    assert_eq!(zero, Counts::default(), "{zero:?}");
    let dirs = counts(
        "fn f(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return wi; }",
        "f",
    );
    assert_eq!(dirs, Counts::default(), "{dirs:?}");

    // One of each: exp, a division by a non-constant, a branch (or the select the optimiser
    // may make of it).
    let src = "
fn g(x: f32, y: f32) -> f32 {
    var r = exp(x) / y;
    if y > 0.5 {
        r = r * x + y;
    }
    return r;
}";
    let c = counts(src, "g");
    assert_eq!(c.transcendental, 1, "{c:?}");
    assert_eq!(c.division_sqrt, 1, "{c:?}");
    assert!(c.branches + c.select == 1, "{c:?}");
    assert!(c.arithmetic >= 1, "{c:?}");
    assert_eq!(
        c.total,
        c.arithmetic + c.transcendental + c.division_sqrt + c.branches + c.select + c.other
    );

    // Arithmetic alone: 3 multiplies and 2 adds in the source, which the optimiser may fuse
    // (Fma) and factor; a min and a max, exactly.
    let a = counts(
        "fn a(x: f32, y: f32, z: f32) -> f32 { return x * y + y * z + z * x; }",
        "a",
    );
    assert!((1..=5).contains(&a.arithmetic), "{a:?}");
    assert_eq!(a.total, a.arithmetic, "{a:?}");
    // A max, a min and an add, exactly (a min of a max would fold into one clamp).
    let m = counts(
        "fn m(x: f32, y: f32, z: f32) -> f32 { return max(x, y) + min(y, z); }",
        "m",
    );
    assert_eq!(
        m,
        Counts {
            arithmetic: 3,
            total: 3,
            ..Counts::default()
        }
    );

    // A select, a square root, a pow, a normalize, a dot.
    let b = counts(
        "fn b(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
            let h = normalize(wi + wo);
            let c = dot(h, wi);
            return select(0.0, pow(sqrt(c), 7.3), c > 0.0);
        }",
        "b",
    );
    assert_eq!(b.transcendental, 1, "{b:?}");
    assert_eq!(b.division_sqrt, 2, "{b:?}");
    assert_eq!(b.select, 1, "{b:?}");
    assert_eq!(b.branches, 0, "{b:?}");
    assert!(b.arithmetic >= 2 && b.other >= 1, "{b:?}");

    // Constants fold: the optimiser's work is counted, not the source's.
    let folded = counts(
        "fn k(x: f32) -> f32 { return x * (2.0 * 3.0) * exp(0.0); }",
        "k",
    );
    assert_eq!(
        folded,
        Counts {
            arithmetic: 1,
            total: 1,
            ..Counts::default()
        }
    );

    // A user's BRDF beside other code: only what the function reaches.
    let user = counts(
        "fn unused(x: f32) -> f32 { return exp(x) / x; }
         fn brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
             return vec3<f32>(0.3, 0.2, 0.1) * max(wi.z * wo.z, 0.0);
         }
         @fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(unused(1.0)); }",
        "brdf",
    );
    assert_eq!(user.transcendental + user.division_sqrt, 0, "{user:?}");
    assert!(user.arithmetic >= 3, "{user:?}");
}

#[test]
fn bad_functions_are_errors_that_name_them() {
    if !spirv_opt() {
        return;
    }
    let e = cost::of_wgsl("fn f(x: f32) -> f32 { return x; }", "g").unwrap_err();
    assert!(e.contains("no function g") && e.contains("f"), "{e}");
    let e = cost::of_wgsl("fn f(x: f32) -> f32 { return y; }", "f").unwrap_err();
    assert!(e.contains("y") && e.contains(":1:"), "{e}");
    let e = cost::of_wgsl("fn f(x: bool) -> f32 { return 1.0; }", "f").unwrap_err();
    assert!(e.contains("argument x of f"), "{e}");
    let e = cost::of_wgsl("fn f(x: f32) { }", "f").unwrap_err();
    assert!(e.contains("f returns nothing"), "{e}");
    let e = cost::of_wgsl("fn fbcost_x(x: f32) -> f32 { return x; }", "fbcost_x").unwrap_err();
    assert!(e.contains("reserved"), "{e}");
    // A coloured spec is three instances: an error naming its R,G,B parameter.
    let s = ModelSpec::parse("cook-torrance", &[("f0", "0.9,0.6,0.5")]).unwrap();
    let e = cost::of_model(&s).unwrap_err();
    assert!(e.contains("f0"), "{e}");
}

#[test]
fn approximations_cost_less_than_their_exact_twins() {
    let rows = cost::table();
    let get = |spec: &str| {
        rows.iter()
            .find(|r| r.spec == spec)
            .unwrap_or_else(|| panic!("{spec} is not in the table"))
            .counts
    };
    // The committed table (no spirv-opt needed): powers by squaring have no transcendental
    // call, the exact lobe has one.
    let pow = get("pow");
    assert!(pow.transcendental >= 1, "pow {pow:?}");
    for id in ["power4", "power8", "power16", "cubic", "rational"] {
        let c = get(id);
        assert_eq!(c.transcendental, 0, "{id} {c:?}");
    }
    // Beckmann through a power of a cosine instead of exp(-tan^2 / alpha^2): no exponential.
    let exact = get("beckmann");
    let approx = get("beckmann-power16");
    assert!(exact.transcendental >= 1, "{exact:?}");
    assert!(
        approx.transcendental < exact.transcendental,
        "{approx:?} vs {exact:?}"
    );
    for r in rows {
        let c = r.counts;
        assert_eq!(
            c.total,
            c.arithmetic + c.transcendental + c.division_sqrt + c.branches + c.select + c.other,
            "{}",
            r.spec
        );
        // Only a constant counts nothing (fresnel-none returns 1).
        assert_eq!(c.total == 0, r.spec == "fresnel-none", "{} {c:?}", r.spec);
    }
}

#[test]
fn the_committed_table_is_what_spirv_opt_measures() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/shader_costs.csv");
    if std::env::var_os("FASTBRDF_BLESS").is_some() {
        let fresh = cost::generate_table().unwrap();
        std::fs::write(&path, &fresh).unwrap();
        return;
    }
    // Every configuration has a row, whether or not spirv-opt is here.
    for spec in cost::configurations() {
        assert!(
            cost::lookup(&spec).is_some(),
            "{spec} has no row in src/shader_costs.csv (FASTBRDF_BLESS=1 cargo test -p fastbrdf-gpu --test cost)"
        );
    }
    if !spirv_opt() {
        return;
    }
    let fresh = cost::generate_table().unwrap();
    let committed = std::fs::read_to_string(&path).unwrap();
    let (old, new) = (
        cost::parse_table(&committed).unwrap(),
        cost::parse_table(&fresh).unwrap(),
    );
    let differ: Vec<String> = new
        .iter()
        .filter(|r| !old.contains(r))
        .map(|r| format!("{}: measured {}", r.spec, r.counts.short()))
        .chain(
            old.iter()
                .filter(|r| !new.iter().any(|n| n.spec == r.spec))
                .map(|r| format!("{}: no longer a configuration", r.spec)),
        )
        .collect();
    let version = |t: &str| {
        t.lines()
            .find_map(|l| l.split("Measured with ").nth(1))
            .map_or("?", |v| v.trim_end_matches('.'))
            .to_string()
    };
    assert!(
        differ.is_empty(),
        "src/shader_costs.csv differs from this measurement (committed with {}, measured with {}; \
         FASTBRDF_BLESS=1 cargo test -p fastbrdf-gpu --test cost rewrites it):\n{}",
        version(&committed),
        version(&fresh),
        differ.join("\n")
    );
    assert_eq!(old.len(), new.len());
}
