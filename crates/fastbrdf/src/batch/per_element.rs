//! Per-element parameters: one model evaluated with a parameter value per element (a
//! roughness map), through the batch kernels, with the values of a model built for each
//! element's values exactly (no quantisation).
//!
//! How (grouping by value): the elements are taken in blocks of [`BLOCK`]; in each block every
//! element gets the dense id of its parameter values (their bits hashed: equal bits, one
//! group), the elements are ordered by group (a counting sort, O(n)), and each group's
//! inputs are gathered into contiguous buffers, evaluated by the kernel of the model built
//! for its values (`ModelSpec` with the values set, then `Kernel::new`: what
//! `fastbrdf.Model(..., alpha=v)` builds), and scattered back (a block with one value set
//! skips the ordering). With several blocks the slice is split into one contiguous part per
//! rayon thread; each part keeps its built models between its blocks (at most [`CACHE`] value
//! sets; then it starts afresh), so a map with a few hundred levels builds each level once per
//! part and call. The scalar paths (f64; the f32 shadowing
//! terms, which have no kernel) evaluate each element with its group's scalar model, in place.
//!
//! Cost: O(n) hashing, gathering and scattering per element plus one build per distinct
//! value set, part and call (1 to 4 microseconds: `python/examples/perelement_cost.py` and
//! `examples/per_element_cost.rs` measure both; docs/book/src/python-arrays.md has figures). All-distinct continuous values therefore cost a build per element: exact, but
//! hundreds of times slower than a map with few levels.
//!
//! Why not runtime-parameter kernels (the family built per SIMD lane): each family's plan
//! computes its coefficients in f64 with branches per value (forms chosen by `n`, clamps),
//! which a per-lane build would have to reproduce bit for bit for every family; grouping
//! reuses the plan and kernel code as they are, so results equal a model built per value, in
//! both precisions, for every model.

use super::{Input, Kernel};
use crate::error::{Error, Result};
use crate::model::{Kind, Model};
use crate::params::ParamKind;
use crate::real::Real;
use crate::spec::{Given, ModelSpec};
use rayon::prelude::*;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Elements grouped at a time (their gathered inputs stay in cache).
pub const BLOCK: usize = 16384;

/// The most value sets whose models are kept between blocks.
pub const CACHE: usize = 4096;

/// The inputs of a per-element evaluation in precision `T`: columns (lobes, distributions,
/// Fresnel, shadowing and split-sum terms, as `Model::eval_row` takes them) or BRDF
/// directions `wi`, `wo` (3 values per element, interleaved).
#[derive(Clone, Copy, Debug)]
pub enum Rows<'a, T> {
    Cols(&'a [&'a [T]]),
    Dirs(&'a [T], &'a [T]),
}

impl<T> Rows<'_, T> {
    /// The number of elements.
    pub fn len(&self) -> usize {
        match self {
            Rows::Cols(c) => c.first().map_or(0, |c| c.len()),
            Rows::Dirs(wi, _) => wi.len() / 3,
        }
    }

    /// Whether there are no elements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A hasher for 64-bit keys (multiply and fold): the keys are float bits and dense ids.
#[derive(Default)]
struct Fold(u64);

impl Hasher for Fold {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    #[inline]
    fn write_u64(&mut self, x: u64) {
        let m = (u128::from(self.0 ^ x)).wrapping_mul(0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c835);
        self.0 = (m as u64) ^ ((m >> 64) as u64);
    }
}

/// Dense ids (0, 1, ... in order of first appearance) of 64-bit keys.
#[derive(Default)]
struct Dense(HashMap<u64, u32, BuildHasherDefault<Fold>>);

impl Dense {
    fn clear(&mut self) {
        self.0.clear();
    }

    #[inline]
    fn id(&mut self, key: u64) -> u32 {
        let next = self.0.len() as u32;
        *self.0.entry(key).or_insert(next)
    }
}

/// A model with some numeric parameters given per element.
#[derive(Clone, Debug)]
pub struct PerElement {
    id: &'static str,
    /// The spec's given values without the per-element ones.
    base: Vec<(&'static str, Given)>,
    /// The per-element parameters, in the order their values are passed.
    names: Vec<&'static str>,
    kind: Kind,
}

/// Whether `spec`'s model has a numeric parameter `name`: `Ok(false)` for a choice, the
/// registry's `UnknownParam` for none.
pub fn numeric(spec: &ModelSpec, name: &str) -> Result<bool> {
    match spec.info().params.iter().find(|s| s.name == name) {
        Some(s) => Ok(matches!(s.kind, ParamKind::Number { .. })),
        None => Err(Error::UnknownParam {
            model: spec.id().into(),
            param: name.into(),
        }),
    }
}

impl PerElement {
    /// `spec` (a grey model) with `names` given per element: each must be a numeric
    /// parameter of the model (else the registry's error; a choice is an `InvalidParam`).
    pub fn new(spec: &ModelSpec, names: &[&str]) -> Result<Self> {
        spec.plan()?;
        let mut resolved = Vec::with_capacity(names.len());
        for name in names {
            let s = spec
                .info()
                .params
                .iter()
                .find(|s| s.name == *name)
                .ok_or_else(|| Error::UnknownParam {
                    model: spec.id().into(),
                    param: (*name).into(),
                })?;
            if !matches!(s.kind, ParamKind::Number { .. }) {
                return Err(Error::InvalidParam {
                    model: spec.id().into(),
                    param: s.name.into(),
                    value: "an array".into(),
                    expected: "one choice (per-element values are for numeric parameters)".into(),
                });
            }
            resolved.push(s.name);
        }
        Ok(Self {
            id: spec.id(),
            base: spec
                .given()
                .iter()
                .filter(|(k, _)| !resolved.contains(k))
                .cloned()
                .collect(),
            names: resolved,
            kind: spec.kind(),
        })
    }

    /// The per-element parameters' names.
    pub fn names(&self) -> &[&'static str] {
        &self.names
    }

    /// The spec with the per-element parameters at `values` (in the order of `names`): what
    /// a model built with those values is built from (validated as such).
    pub fn spec_at(&self, values: &[f64]) -> Result<ModelSpec> {
        let mut given = self.base.clone();
        given.extend(
            self.names
                .iter()
                .zip(values)
                .map(|(k, v)| (*k, Given::Num(*v))),
        );
        ModelSpec::new(self.id, &given)
    }

    /// Checks parameter `which`'s values (the others at their first values): the first
    /// element whose value the model refuses (outside the documented range, NaN) is
    /// `Err((index, the library's error))`. Each value is range-checked; the least and
    /// greatest build a model (a value set a plan refuses would otherwise show only at
    /// evaluation).
    pub fn check(&self, which: usize, values: &[f64]) -> std::result::Result<(), (usize, Error)> {
        let spec = crate::registry::find(self.id)
            .ok()
            .and_then(|e| e.info.params.iter().find(|s| s.name == self.names[which]));
        let (min, max) = match spec.map(|s| s.kind) {
            Some(ParamKind::Number { min, max, .. }) => (min, max),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        };
        let build = |i: usize| {
            // The other parameters' values do not matter for this one's range: their
            // defaults stand in (the spec without them given).
            let mut given = self.base.clone();
            given.push((self.names[which], Given::Num(values[i])));
            ModelSpec::new(self.id, &given)
                .map(|_| ())
                .map_err(|e| (i, e))
        };
        let (mut lo, mut hi) = (None::<usize>, None::<usize>);
        for (i, &x) in values.iter().enumerate() {
            if !(x.is_finite() && x >= min && x <= max) {
                build(i)?;
                continue; // accepted after all (not expected)
            }
            if lo.is_none_or(|j| x < values[j]) {
                lo = Some(i);
            }
            if hi.is_none_or(|j| x > values[j]) {
                hi = Some(i);
            }
        }
        for i in [lo, hi].into_iter().flatten() {
            build(i)?;
        }
        Ok(())
    }

    /// Evaluates in f32 with `params[k]` the values of `names[k]` per element (f64, each
    /// `out.len()` long), as the model built for each element's values evaluates with
    /// `fastbrdf.Model.eval` in f32: its batch kernel (the scalar f32 model for shadowing
    /// terms, which have none).
    pub fn eval_f32(&self, params: &[&[f64]], rows: Rows<'_, f32>, out: &mut [f32]) -> Result<()> {
        self.check_lengths(params, &rows, out.len())?;
        blocks(out, |st: &mut State32, lo, o| {
            let g = &mut st.groups;
            g.group(params, lo, lo + o.len());
            match st.cache.models32(self, params, lo, g)? {
                Built32s::Kernels(ks) => match (rows, ks.as_slice()) {
                    // One value in the block, columns: the kernel reads them in place.
                    (Rows::Cols(cols), [k]) => {
                        let c: Vec<&[f32]> = cols.iter().map(|c| &c[lo..lo + o.len()]).collect();
                        k.eval(kernel_input(k, &c)?, o)
                    }
                    // One value in the block, directions: deinterleaved in order, no scatter.
                    (Rows::Dirs(wi, wo), [k]) => st.buf.dirs(k, wi, wo, lo, o),
                    _ => {
                        g.order();
                        st.buf.run(&ks, g, rows, lo, o)
                    }
                },
                Built32s::Scalar(ms) => {
                    scalar_rows(&ms, &g.ids, rows, lo, o);
                    Ok(())
                }
            }
        })
    }

    /// Evaluates in f64 (the scalar f64 model of each element's values), as
    /// [`PerElement::eval_f32`].
    pub fn eval_f64(&self, params: &[&[f64]], rows: Rows<'_, f64>, out: &mut [f64]) -> Result<()> {
        self.check_lengths(params, &rows, out.len())?;
        blocks(out, |st: &mut State64, lo, o| {
            st.groups.group(params, lo, lo + o.len());
            let ms = st.cache.models64(self, params, lo, &st.groups)?;
            scalar_rows(&ms, &st.groups.ids, rows, lo, o);
            Ok(())
        })
    }

    /// Calls `f(i, model)` for every element `i` of `0..n` in order, `model` the scalar model
    /// in precision `T` built for element `i`'s values (one build per distinct value set in a
    /// block of [`BLOCK`], kept between blocks): for what runs per element anyway (sampling,
    /// densities), on this thread. Stops at `f`'s first error.
    pub fn each_model<T: Real, E: From<Error>>(
        &self,
        params: &[&[f64]],
        n: usize,
        mut f: impl FnMut(usize, &Model<T>) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        let bad = self.names.iter().zip(params).find(|(_, p)| p.len() != n);
        if params.len() != self.names.len() || bad.is_some() {
            return Err(E::from(Error::Domain {
                input: "per-element".into(),
                reason: format!(
                    "{} parameter arrays of {n} values expected",
                    self.names.len()
                ),
            }));
        }
        let mut cache = Cache::<Model<T>>::default();
        let mut g = Groups::default();
        let mut lo = 0;
        while lo < n {
            let hi = n.min(lo + BLOCK);
            g.group(params, lo, hi);
            let which = cache.indices(self, params, lo, &g, |s| s.model::<T>())?;
            for (j, &id) in g.ids.iter().enumerate() {
                f(lo + j, &cache.built[which[id as usize]])?;
            }
            lo = hi;
        }
        Ok(())
    }

    fn check_lengths<T>(&self, params: &[&[f64]], rows: &Rows<'_, T>, n: usize) -> Result<()> {
        let bad = |what: String| {
            Err(Error::Domain {
                input: "per-element".into(),
                reason: what,
            })
        };
        if params.len() != self.names.len() {
            return bad(format!(
                "{} parameter arrays for {} names",
                params.len(),
                self.names.len()
            ));
        }
        if let Some((k, p)) = self.names.iter().zip(params).find(|(_, p)| p.len() != n) {
            return bad(format!("{k}: {} values, the output has {n}", p.len()));
        }
        let ok = match rows {
            Rows::Cols(c) => !c.is_empty() && c.iter().all(|c| c.len() == n),
            Rows::Dirs(wi, wo) => wi.len() == 3 * n && wo.len() == 3 * n,
        };
        if !ok {
            return bad(format!(
                "the inputs' lengths differ from the output's ({n})"
            ));
        }
        if matches!(rows, Rows::Dirs(..)) != (self.kind == Kind::Brdf) {
            return bad(format!(
                "model '{}' is a {}: it takes {}",
                self.id,
                self.kind.name(),
                if self.kind == Kind::Brdf {
                    "directions"
                } else {
                    "columns"
                }
            ));
        }
        Ok(())
    }
}

/// Runs `step` over the blocks of `out` (`step(state, first element, block's output)`). With
/// several blocks and threads, `out` is split into one contiguous part per thread of rayon's
/// pool, each run with its own state (its own built models: a value set in several parts is
/// built once per part, not once per block, as a state per rayon task would be).
fn blocks<T: Send, S: Default + Send>(
    out: &mut [T],
    step: impl Fn(&mut S, usize, &mut [T]) -> Result<()> + Sync,
) -> Result<()> {
    let seq = |first: usize, o: &mut [T]| {
        let mut s = S::default();
        o.chunks_mut(BLOCK)
            .enumerate()
            .try_for_each(|(b, o)| step(&mut s, first + b * BLOCK, o))
    };
    let threads = rayon::current_num_threads();
    if out.len() <= BLOCK || threads < 2 {
        return seq(0, out);
    }
    let part = out.len().div_ceil(BLOCK).div_ceil(threads) * BLOCK;
    out.par_chunks_mut(part)
        .enumerate()
        .try_for_each(|(p, o)| seq(p * part, o))
}

/// The f32 path's state per worker.
#[derive(Default)]
struct State32 {
    cache: Cache<Built32>,
    groups: Groups,
    buf: Buffers,
}

/// The f64 path's state per worker.
#[derive(Default)]
struct State64 {
    cache: Cache<Model<f64>>,
    groups: Groups,
}

/// The kernel input of columns, as `fastbrdf.Model.eval` feeds the kernel (split-sum terms:
/// two columns; lobes, distributions, Fresnel terms: one).
fn kernel_input<'a>(k: &Kernel, cols: &[&'a [f32]]) -> Result<Input<'a>> {
    match (k.kind(), cols) {
        (Kind::Env, [c, a]) => Ok(Input::Env([c, a])),
        (Kind::Lobe | Kind::Distribution | Kind::Fresnel, [c]) => Ok(Input::Cos(c)),
        _ => Err(Error::WrongKind {
            model: k.id().into(),
            expected: format!("the columns of a {}", k.kind().name()),
            found: format!("{} columns", cols.len()),
        }),
    }
}

/// What the f32 path builds per value set: kernels, or scalar models for shadowing terms.
enum Built32 {
    Kernel(Kernel),
    Scalar(Model<f32>),
}

fn build32(s: &ModelSpec) -> Result<Built32> {
    Ok(match s.kind() {
        Kind::Shadowing => Built32::Scalar(s.model::<f32>()?),
        _ => Built32::Kernel(Kernel::new(s)?),
    })
}

/// A block's models, one per group: all kernels or all scalar models (one model id).
enum Built32s<'a> {
    Kernels(Vec<&'a Kernel>),
    Scalar(Vec<&'a Model<f32>>),
}

/// Models built per value set (the bits of the values), kept between blocks.
struct Cache<B> {
    index: HashMap<Vec<u64>, usize>,
    built: Vec<B>,
}

impl<B> Default for Cache<B> {
    fn default() -> Self {
        Self {
            index: HashMap::new(),
            built: Vec::new(),
        }
    }
}

impl<B> Cache<B> {
    /// The index of each group's model in `built` (built where missing).
    fn indices(
        &mut self,
        pe: &PerElement,
        params: &[&[f64]],
        lo: usize,
        g: &Groups,
        build: impl Fn(&ModelSpec) -> Result<B>,
    ) -> Result<Vec<usize>> {
        if self.built.len() + g.firsts.len() > CACHE {
            self.index.clear();
            self.built.clear();
        }
        let mut which = Vec::with_capacity(g.firsts.len());
        let mut values = vec![0.0; params.len()];
        for &f in &g.firsts {
            let i = lo + f as usize;
            for (v, p) in values.iter_mut().zip(params) {
                *v = p[i];
            }
            let key: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
            let k = match self.index.get(&key) {
                Some(&k) => k,
                None => {
                    self.built.push(build(&pe.spec_at(&values)?)?);
                    self.index.insert(key, self.built.len() - 1);
                    self.built.len() - 1
                }
            };
            which.push(k);
        }
        Ok(which)
    }
}

impl Cache<Built32> {
    fn models32<'a>(
        &'a mut self,
        pe: &PerElement,
        params: &[&[f64]],
        lo: usize,
        g: &Groups,
    ) -> Result<Built32s<'a>> {
        let which = self.indices(pe, params, lo, g, build32)?;
        let built = &self.built;
        if which
            .iter()
            .all(|&k| matches!(built[k], Built32::Kernel(_)))
        {
            Ok(Built32s::Kernels(
                which
                    .iter()
                    .map(|&k| match &built[k] {
                        Built32::Kernel(x) => x,
                        Built32::Scalar(_) => unreachable!(),
                    })
                    .collect(),
            ))
        } else {
            Ok(Built32s::Scalar(
                which
                    .iter()
                    .map(|&k| match &built[k] {
                        Built32::Scalar(m) => Ok(m),
                        Built32::Kernel(_) => Err(Error::WrongKind {
                            model: pe.id.into(),
                            expected: "one kind of model for every value".into(),
                            found: "kernels and scalar models".into(),
                        }),
                    })
                    .collect::<Result<_>>()?,
            ))
        }
    }
}

impl Cache<Model<f64>> {
    fn models64<'a>(
        &'a mut self,
        pe: &PerElement,
        params: &[&[f64]],
        lo: usize,
        g: &Groups,
    ) -> Result<Vec<&'a Model<f64>>> {
        let which = self.indices(pe, params, lo, g, |s| s.model::<f64>())?;
        Ok(which.iter().map(|&k| &self.built[k]).collect())
    }
}

/// The groups of one block: a dense id per element, each group's first element, and (after
/// [`Groups::order`]) the elements ordered by group.
#[derive(Default)]
struct Groups {
    ids: Vec<u32>,
    firsts: Vec<u32>,
    order: Vec<u32>,
    starts: Vec<usize>,
    first_map: Dense,
    own_map: Dense,
    pair_map: Dense,
}

impl Groups {
    /// Dense ids for elements `lo..hi` by their values' bits: the first parameter's bits
    /// give an id, each further parameter's id is combined with it (a map of id pairs).
    fn group(&mut self, params: &[&[f64]], lo: usize, hi: usize) {
        self.ids.clear();
        self.firsts.clear();
        let Some((p0, rest)) = params.split_first() else {
            self.ids.resize(hi - lo, 0);
            self.firsts.push(0);
            return;
        };
        self.first_map.clear();
        let mut last = None;
        for &x in &p0[lo..hi] {
            let b = x.to_bits();
            let id = match last {
                Some((lb, id)) if lb == b => id,
                _ => self.first_map.id(b),
            };
            last = Some((b, id));
            self.ids.push(id);
        }
        for p in rest {
            self.own_map.clear();
            self.pair_map.clear();
            for (id, &x) in self.ids.iter_mut().zip(&p[lo..hi]) {
                let own = self.own_map.id(x.to_bits());
                *id = self.pair_map.id((u64::from(*id) << 32) | u64::from(own));
            }
        }
        let mut seen = vec![false; self.ids.iter().max().map_or(0, |m| *m as usize + 1)];
        for (i, &id) in self.ids.iter().enumerate() {
            if !seen[id as usize] {
                seen[id as usize] = true;
                self.firsts.push(i as u32);
            }
        }
        // Ids are dense in order of first appearance (each map numbers new keys in order,
        // and a new pair appears first where a new combination does): group k's first
        // element is firsts[k].
        debug_assert!(
            self.firsts
                .iter()
                .enumerate()
                .all(|(k, &f)| self.ids[f as usize] == k as u32)
        );
    }

    /// Orders the elements by group (stable counting sort).
    fn order(&mut self) {
        let groups = self.firsts.len();
        self.starts.clear();
        self.starts.resize(groups + 1, 0);
        for &id in &self.ids {
            self.starts[id as usize + 1] += 1;
        }
        for k in 0..groups {
            self.starts[k + 1] += self.starts[k];
        }
        let mut next = self.starts.clone();
        self.order.clear();
        self.order.resize(self.ids.len(), 0);
        for (i, &id) in self.ids.iter().enumerate() {
            self.order[next[id as usize]] = i as u32;
            next[id as usize] += 1;
        }
    }
}

/// A block's inputs gathered in group order (each group contiguous), and its outputs.
#[derive(Default)]
struct Buffers {
    soa: [Vec<f32>; 6],
    out: Vec<f32>,
}

impl Buffers {
    /// Runs `k` on the block's directions (`lo..lo + out.len()`), deinterleaved in order.
    fn dirs(
        &mut self,
        k: &Kernel,
        wi: &[f32],
        wo: &[f32],
        lo: usize,
        out: &mut [f32],
    ) -> Result<()> {
        let m = out.len();
        let (wi, wo) = (&wi[3 * lo..3 * (lo + m)], &wo[3 * lo..3 * (lo + m)]);
        for b in &mut self.soa {
            b.resize(m, 0.0);
        }
        let [a, b, c, d, e, f] = &mut self.soa;
        for (j, (x, y)) in wi.chunks_exact(3).zip(wo.chunks_exact(3)).enumerate() {
            (a[j], b[j], c[j]) = (x[0], x[1], x[2]);
            (d[j], e[j], f[j]) = (y[0], y[1], y[2]);
        }
        k.eval(
            Input::Dirs(std::array::from_fn(|i| self.soa[i].as_slice())),
            out,
        )
    }

    /// Gathers the block's elements (`lo..lo + out.len()` of `rows`) in the order of
    /// `g.order`, runs each group's kernel `ks[k]` on its contiguous slice (as
    /// `fastbrdf.Model.eval` runs it with scalar parameters) and scatters into `out`.
    fn run(
        &mut self,
        ks: &[&Kernel],
        g: &Groups,
        rows: Rows<'_, f32>,
        lo: usize,
        out: &mut [f32],
    ) -> Result<()> {
        let m = out.len();
        let width = match rows {
            Rows::Cols(cols) => cols.len().min(6),
            Rows::Dirs(..) => 6,
        };
        for b in &mut self.soa[..width] {
            b.resize(m, 0.0);
        }
        self.out.resize(m, 0.0);
        match rows {
            Rows::Cols(cols) => {
                for (b, c) in self.soa.iter_mut().zip(cols) {
                    let c = &c[lo..lo + m];
                    for (x, &i) in b.iter_mut().zip(&g.order) {
                        *x = c[i as usize];
                    }
                }
            }
            Rows::Dirs(wi, wo) => {
                let (wi, wo) = (&wi[3 * lo..3 * (lo + m)], &wo[3 * lo..3 * (lo + m)]);
                let [a, b, c, d, e, f] = &mut self.soa;
                for (j, &i) in g.order.iter().enumerate() {
                    let i = 3 * i as usize;
                    (a[j], b[j], c[j]) = (wi[i], wi[i + 1], wi[i + 2]);
                    (d[j], e[j], f[j]) = (wo[i], wo[i + 1], wo[i + 2]);
                }
            }
        }
        for (k, kernel) in ks.iter().enumerate() {
            let r = g.starts[k]..g.starts[k + 1];
            let s: [&[f32]; 6] = std::array::from_fn(|a| {
                if a < width {
                    &self.soa[a][r.clone()]
                } else {
                    &[][..]
                }
            });
            let input = match rows {
                Rows::Cols(_) => kernel_input(kernel, &s[..width])?,
                Rows::Dirs(..) => Input::Dirs(s),
            };
            kernel.eval(input, &mut self.out[r])?;
        }
        for (&i, &v) in g.order.iter().zip(&self.out) {
            out[i as usize] = v;
        }
        Ok(())
    }
}

/// The scalar model of each element's group (`Model::eval_row`, the lenient rules; BRDFs'
/// `eval` on the directions), elements `lo..lo + out.len()`, in place.
fn scalar_rows<T: Real>(
    ms: &[&Model<T>],
    ids: &[u32],
    rows: Rows<'_, T>,
    lo: usize,
    out: &mut [T],
) {
    match rows {
        Rows::Cols(cols) => {
            let mut input = vec![None; cols.len()];
            for (j, (o, &id)) in out.iter_mut().zip(ids).enumerate() {
                for (x, c) in input.iter_mut().zip(cols) {
                    *x = Some(c[lo + j]);
                }
                *o = ms[id as usize].eval_row(&input);
            }
        }
        Rows::Dirs(wi, wo) => {
            for (j, (o, &id)) in out.iter_mut().zip(ids).enumerate() {
                let k = 3 * (lo + j);
                let (a, b) = (&wi[k..k + 3], &wo[k..k + 3]);
                *o = match ms[id as usize] {
                    Model::Brdf(br) => br.eval([a[0], a[1], a[2]], [b[0], b[1], b[2]]),
                    m => m.eval_row(&[a, b].concat().into_iter().map(Some).collect::<Vec<_>>()),
                };
            }
        }
    }
}
