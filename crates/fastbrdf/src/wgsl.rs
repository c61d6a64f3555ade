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
    /// Runtime mode: parameters written as an expression of others ([`Emit::with_alias`]).
    aliases: RefCell<Vec<Alias>>,
}

/// `p_<name>` stands for `expr`, an expression of the parameters `params`.
#[derive(Debug)]
struct Alias {
    name: String,
    expr: String,
    params: Vec<String>,
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
    /// Parameter `name` as a runtime argument, `p_<name>` (marks it used), or its alias's
    /// expression.
    pub fn param(&self, name: &str) -> String {
        if let Some(expr) = self.alias_of(name) {
            return expr;
        }
        self.used.borrow_mut().insert(name.to_string());
        format!("p_{name}")
    }
    /// Runs `f` with parameter `name` standing for the WGSL expression `expr` of the
    /// parameters `params` (runtime mode; the coefficients of the other modes are values
    /// already): inside `f`, [`Emit::param`] and [`Emit::kx`] write `(expr)` for `p_<name>`
    /// and mark `params` used instead of `name`. `cook-torrance` builds its anisotropic parts
    /// at `alpha = sqrt(alpha_x alpha_y)` so, and their runtime form reads
    /// `sqrt(p_alpha_x * p_alpha_y)` where an isotropic part reads `p_alpha`.
    pub fn with_alias<R>(
        &self,
        name: &str,
        expr: &str,
        params: &[&str],
        f: impl FnOnce() -> R,
    ) -> R {
        self.aliases.borrow_mut().push(Alias {
            name: name.into(),
            expr: expr.into(),
            params: params.iter().map(|p| p.to_string()).collect(),
        });
        let r = f();
        self.aliases.borrow_mut().pop();
        r
    }
    /// The alias of `name` as `(expr)`, marking its parameters used.
    fn alias_of(&self, name: &str) -> Option<String> {
        let aliases = self.aliases.borrow();
        let a = aliases.iter().rev().find(|a| a.name == name)?;
        let mut used = self.used.borrow_mut();
        for p in &a.params {
            used.insert(p.clone());
        }
        Some(format!("({})", a.expr))
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
                let mut expr = expr.to_string();
                for p in params {
                    match self.alias_of(p) {
                        Some(a) => expr = replace_ident(&expr, &format!("p_{p}"), &a),
                        None => {
                            self.param(p);
                        }
                    }
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

/// `text` with every whole identifier `ident` replaced by `by` (`p_alpha`, not `p_alpha_x`).
fn replace_ident(text: &str, ident: &str, by: &str) -> String {
    let is_id = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(ident) {
        let before = rest[..i].chars().next_back();
        let after = rest[i + ident.len()..].chars().next();
        let whole = !before.is_some_and(is_id) && !after.is_some_and(is_id);
        out.push_str(&rest[..i]);
        out.push_str(if whole { by } else { ident });
        rest = &rest[i + ident.len()..];
    }
    out.push_str(rest);
    out
}

/// The pair set-up every BRDF body starts with (`fb_pair` in `common.wgsl`, the twin of
/// `vec3::pair_setup`).
pub const PAIR: &str = "    let p = fb_pair(wi, wo);\n";
