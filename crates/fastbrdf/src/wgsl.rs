//! WGSL text of a model's plan: each family writes the call of its WGSL twin (the library
//! function in the `.wgsl` file beside its Rust file) with its coefficients placed as an
//! [`Emit`] says, and the WGSL library itself ([`library_sources`]: those files, collected from
//! the family lists of [`crate::plan`], with the shared helpers of `common.wgsl` and the
//! runtime-parameter functions of `runtime.wgsl`). No GPU here: `fastbrdf-gpu` splits the
//! library into items, assembles modules, validates them with naga and runs them.

use std::cell::RefCell;
use std::collections::BTreeSet;

/// An f32 literal that parses back to the same f32.
pub fn lit(x: f64) -> String {
    let f = x as f32;
    assert!(f.is_finite(), "non-finite coefficient {x}");
    format!("{f:?}f")
}

/// Where the coefficients of an instance go: inline as literals (exported code with fixed
/// parameters), into the storage array `fb_k` (the compute and render paths), or computed in
/// the shader from the model's parameters passed as arguments `p_<name>` (runtime parameters:
/// `fastbrdf shader --runtime-params`, BRDF Explorer's sliders).
///
/// Why literals and storage: a shader compiler folds literal constants into reassociated
/// expressions (Mesa turns the cubic's Newton form `(x - x2) d3` into `x d3 - x2 d3`, which
/// cancels catastrophically when `d3 ~ 1e8`). Coefficients it cannot see keep the arrangement
/// the CPU uses; `fastbrdf-gpu`'s `tests/parity.rs` measures every form. Runtime coefficients
/// are computed in f32 in the shader: closed forms inline, the rest by the `fb_rt_*`
/// functions of `runtime.wgsl` (f32 error measured per model in `fastbrdf-gpu`'s
/// `tests/runtime.rs`).
#[derive(Debug, Default)]
pub struct Emit {
    mode: Mode,
    values: RefCell<Vec<f32>>,
    /// Runtime mode: the parameters the expressions use.
    used: RefCell<BTreeSet<String>>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Mode {
    #[default]
    Literals,
    Storage,
    Runtime,
}

impl Emit {
    /// Coefficients as literals.
    pub fn literals() -> Self {
        Self::default()
    }
    /// Coefficients as `fb_k[i]`.
    pub fn storage() -> Self {
        Self {
            mode: Mode::Storage,
            ..Default::default()
        }
    }
    /// Coefficients computed in the shader from `p_<param>` arguments.
    pub fn runtime() -> Self {
        Self {
            mode: Mode::Runtime,
            ..Default::default()
        }
    }
    /// Whether coefficients are computed in the shader from parameters.
    pub fn is_runtime(&self) -> bool {
        self.mode == Mode::Runtime
    }
    /// The storage values, in `fb_k` order.
    pub fn into_values(self) -> Vec<f32> {
        self.values.into_inner()
    }
    /// The parameters the runtime expressions used.
    pub fn used(&self) -> BTreeSet<String> {
        self.used.borrow().clone()
    }
    /// Parameter `name` as a runtime argument, `p_<name>` (marks it used).
    pub fn param(&self, name: &str) -> String {
        self.used.borrow_mut().insert(name.to_string());
        format!("p_{name}")
    }
    fn stored(&self, x: f64) -> String {
        let mut v = self.values.borrow_mut();
        v.push(x as f32);
        format!("fb_k[{}]", v.len() - 1)
    }
    /// One coefficient, value `x`, which is the WGSL expression `expr` of the parameters
    /// `params` (written `p_<name>` in `expr`).
    pub fn kx(&self, x: impl Into<f64>, expr: &str, params: &[&str]) -> String {
        let x = x.into();
        match self.mode {
            Mode::Literals => lit(x),
            Mode::Storage => self.stored(x),
            Mode::Runtime => {
                for p in params {
                    self.param(p);
                }
                format!("({expr})")
            }
        }
    }
    /// A constant that does not depend on the parameters (stored on our own paths, so that no
    /// compiler folds it).
    pub fn constant(&self, x: impl Into<f64>) -> String {
        let x = x.into();
        if self.mode == Mode::Storage {
            self.stored(x)
        } else {
            lit(x)
        }
    }
}

/// The pair set-up every BRDF body starts with (`fb_pair` in `common.wgsl`, the twin of
/// `vec3::pair_setup`).
pub const PAIR: &str = "    let p = fb_pair(wi, wo);\n";
