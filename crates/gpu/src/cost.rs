//! A deterministic cost figure for a shader: its instruction count after a real optimising
//! compiler, by class of operation. Timings need a GPU and move with the machine; this figure
//! is the same everywhere (CI included), like the "7 instructions" engines quote.
//!
//! # How a function is counted
//!
//! The function (a model instance's `fb_<id>`, or a user's WGSL function, [`of_wgsl`]) is
//! called from a compute entry point that reads its arguments from one storage struct and
//! stores its result in a storage variable, with no invocation id and no bounds check. naga
//! writes the module as SPIR-V 1.3 (no debug information, no loop-bounding counters: those are
//! wgpu's safety net, not the shader's work), `spirv-opt -O` (SPIRV-Tools; Debian's
//! `spirv-tools`) optimises it: functions inlined, constants folded, dead code removed. The
//! optimised binary is read word by word ([`spirv`]): every instruction of the functions the
//! entry point reaches is counted once (a static count: a loop's body counts once, both arms
//! of a branch count), except
//!
//! - the wrapper's input and output: the access chains, loads and stores of storage, uniform,
//!   push-constant and shader input/output variables. The wrapper has no other instructions,
//!   so nothing is subtracted: a function that returns its argument counts 0 (a test checks
//!   it). Loads and stores of the shader's own variables (a constant table copied to a
//!   function variable) are counted, as "other";
//! - structure that does no work of its own: labels, merge declarations, unconditional
//!   branches, phis, returns, function and variable declarations, debug lines.
//!
//! Each SPIR-V instruction counts once whatever its width: a `vec3` multiply is one
//! instruction here and three on a scalar GPU. The figure is the optimiser's, before a
//! driver's own compiler (which fuses multiply-adds, may pick a cheaper `pow`).
//!
//! # Classes
//!
//! | class | core instructions | `GLSL.std.450` |
//! |---|---|---|
//! | arithmetic | `FAdd FSub FMul FNegate IAdd ISub IMul SNegate Dot VectorTimesScalar`, matrix products | `Fma FMin FMax FClamp` (and integer, `N` forms), `FAbs FSign Floor Ceil Fract Trunc Round FMix Step SmoothStep Cross Reflect FaceForward Radians Degrees` |
//! | transcendental | | `Exp Exp2 Log Log2 Pow Sin Cos Tan Asin Acos Atan Atan2` and hyperbolic forms |
//! | division_sqrt | `FDiv FRem FMod UDiv SDiv UMod SRem SMod` | `Sqrt InverseSqrt Length Distance Normalize Refract Determinant MatrixInverse` |
//! | branches | `BranchConditional Switch` | |
//! | select | `Select` | |
//! | other | everything else counted: comparisons, logic, conversions, composite construct/extract/shuffle, calls that were not inlined, loads and stores of the shader's own variables | `Modf Frexp Ldexp`, packing, bit finding |
//!
//! `total` is the sum of the six.
//!
//! # Built-in models
//!
//! A model instance is counted in its exported form (`spec::Instance::new`: coefficients as
//! f32 literals, what `fastbrdf shader` writes), so the compiler folds what a fixed material
//! lets it fold. The counts of every registry model at its defaults and of the benchmark's
//! configurations ([`configurations`]) are committed in `shader_costs.csv` ([`table`]), so
//! `fastbrdf models --json` and `fastbrdf bench` need no `spirv-opt`; `tests/cost.rs`
//! regenerates them and fails when they differ (`FASTBRDF_BLESS=1` rewrites the file).

mod spirv;
mod wrap;

use fastbrdf::ModelSpec;
use fastbrdf::model::Kind;
use fastbrdf::registry;
use std::sync::OnceLock;

pub use wrap::version as spirv_opt_version;

/// Instructions by class (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counts {
    pub arithmetic: u32,
    pub transcendental: u32,
    pub division_sqrt: u32,
    pub branches: u32,
    pub select: u32,
    pub other: u32,
    pub total: u32,
}

impl Counts {
    /// `total a/t/d/b/s/o`, e.g. `12 6/1/1/0/1/3`.
    pub fn short(&self) -> String {
        format!(
            "{} {}/{}/{}/{}/{}/{}",
            self.total,
            self.arithmetic,
            self.transcendental,
            self.division_sqrt,
            self.branches,
            self.select,
            self.other
        )
    }
}

/// The instruction counts of `function` in a WGSL `module` (see the module documentation).
///
/// The module is any valid WGSL: its other functions, constants and entry points may be
/// there (only what `function` reaches is counted; names starting `fbcost_` are reserved).
/// `function` takes f32, i32 or u32 scalars or vectors and returns one: a user's BRDF
/// `fn NAME(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32>`, or the built-ins' forms
/// (`spec`'s module documentation: `fn fb_pow(c: f32) -> f32`, ...). Errors name the function
/// or quote naga's message (line and column); a missing `spirv-opt` is an error that says
/// how to install it.
pub fn of_wgsl(module: &str, function: &str) -> Result<Counts, String> {
    let optimised = optimised(module, function)?;
    spirv::count(&optimised, wrap::ENTRY).map_err(|e| format!("WGSL function {function}: {e}"))
}

/// The optimised SPIR-V that [`of_wgsl`] counts (entry point `fbcost_main`), to read with
/// `spirv-dis`.
pub fn optimised(module: &str, function: &str) -> Result<Vec<u32>, String> {
    let what = format!("WGSL function {function}");
    let src = wrap::wrapped(module, function, &what)?;
    let words = wrap::spirv(&src, &what)?;
    wrap::optimise(&words, &what)
}

/// The instruction counts of a (grey) model instance in its exported form.
pub fn of_model(spec: &ModelSpec) -> Result<Counts, String> {
    let inst = crate::spec::Instance::new(spec).map_err(|e| e.to_string())?;
    of_wgsl(&inst.module_source(), &inst.function).map_err(|e| format!("{spec}: {e}"))
}

/// The specs the committed table holds: every registry model at its defaults, then the
/// benchmark's other configurations (`fastbrdf-analysis`'s `speed::configurations`: lobes at
/// n = 200, the seed's Cook-Torrance variants), so `fastbrdf bench` finds every row it times.
pub fn configurations() -> Vec<ModelSpec> {
    let spec = |id: &str, given: &[(&str, &str)]| {
        ModelSpec::parse(id, given).unwrap_or_else(|e| panic!("a cost configuration: {e}"))
    };
    let mut v: Vec<ModelSpec> = registry::all()
        .iter()
        .map(|e| spec(e.info.id, &[]))
        .collect();
    for e in registry::all().iter().filter(|e| e.info.kind == Kind::Lobe) {
        v.push(spec(e.info.id, &[("n", "200")]));
    }
    for d in ["beckmann-ct", "beckmann-pow", "beckmann-power16"] {
        v.push(spec(
            "cook-torrance",
            &[
                ("d", d),
                ("g", "v-cavity"),
                ("f", "schlick"),
                ("denominator", "seed-000"),
            ],
        ));
    }
    v
}

/// The header row of the table's CSV.
const HEADER: &str = "spec,arithmetic,transcendental,division_sqrt,branches,select,other,total";

/// One row of the committed table.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Row {
    /// The spec as `ModelSpec`'s `Display` writes it: `id name=value ...` (given values).
    pub spec: String,
    pub counts: Counts,
}

/// The committed table (`src/shader_costs.csv`), parsed once.
pub fn table() -> &'static [Row] {
    static TABLE: OnceLock<Vec<Row>> = OnceLock::new();
    TABLE.get_or_init(|| {
        parse_table(include_str!("shader_costs.csv"))
            .unwrap_or_else(|e| panic!("src/shader_costs.csv: {e}"))
    })
}

/// The committed counts of `spec`, if the table has it (see [`configurations`]).
pub fn lookup(spec: &ModelSpec) -> Option<Counts> {
    let key = spec.to_string();
    table().iter().find(|r| r.spec == key).map(|r| r.counts)
}

/// A model's entry of `fastbrdf models --json` (and of the Python package's `models()`): its
/// registry info and `instructions`, the committed counts at its defaults ([`lookup`]; null
/// for a model the table lacks, which `tests/cost.rs` forbids). One function for both, so
/// they cannot drift.
pub fn model_entry(info: &fastbrdf::ModelInfo) -> serde_json::Value {
    let mut v = serde_json::to_value(info).expect("the registry serialises");
    let counts = fastbrdf::ModelSpec::parse(info.id, &[])
        .ok()
        .and_then(|s| lookup(&s));
    v["instructions"] = serde_json::to_value(counts).expect("counts serialise");
    v
}

/// The rows of a table's CSV text (`#` lines are comments).
pub fn parse_table(text: &str) -> Result<Vec<Row>, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty());
    match lines.next() {
        Some((_, h)) if h == HEADER => {}
        _ => return Err(format!("the first row is not the header '{HEADER}'")),
    }
    lines
        .map(|(i, l)| {
            let f: Vec<&str> = l.split(',').collect();
            if f.len() != 8 {
                return Err(format!("line {}: {} fields, not 8", i + 1, f.len()));
            }
            let n = |k: usize| {
                f[k].parse::<u32>()
                    .map_err(|e| format!("line {}, field {}: '{}': {e}", i + 1, k + 1, f[k]))
            };
            let counts = Counts {
                arithmetic: n(1)?,
                transcendental: n(2)?,
                division_sqrt: n(3)?,
                branches: n(4)?,
                select: n(5)?,
                other: n(6)?,
                total: n(7)?,
            };
            Ok(Row {
                spec: f[0].to_string(),
                counts,
            })
        })
        .collect()
}

/// The table's CSV text, measured now with `spirv-opt` (for the test that keeps the committed
/// file current).
pub fn generate_table() -> Result<String, String> {
    let version = wrap::version()?;
    let mut s = format!(
        "# SPIR-V instructions of each model instance (exported form) after spirv-opt -O, by class:\n\
         # see fastbrdf_gpu::cost. Measured with {version}.\n\
         # Regenerate: FASTBRDF_BLESS=1 cargo test -p fastbrdf-gpu --test cost\n{HEADER}\n"
    );
    for spec in configurations() {
        let key = spec.to_string();
        if key.contains(',') {
            return Err(format!("{key}: a spec with a comma cannot be a CSV key"));
        }
        let c = of_model(&spec)?;
        s.push_str(&format!(
            "{key},{},{},{},{},{},{},{}\n",
            c.arithmetic, c.transcendental, c.division_sqrt, c.branches, c.select, c.other, c.total
        ));
    }
    Ok(s)
}
