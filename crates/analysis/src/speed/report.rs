//! A benchmark run's rows, loading a saved run (checked to hold possible measurements), and
//! comparing two runs.

use super::PeerRow;
use serde::{Deserialize, Serialize};

/// A figure the run did not measure because one call would have taken too long
/// ([`super::LARGE_CALL_LIMIT_S`]): a quadrature reference such as `sheen-albedo` runs at
/// thousands of evaluations per second, and its large batch would take minutes per call.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Skipped {
    pub model: String,
    pub variant: String,
    pub batch: usize,
    /// One call's projected seconds, from the same kernel's rate on the 4096-element batch.
    pub projected_s: f64,
}

/// One throughput figure.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KernelRow {
    pub model: String,
    pub variant: String,
    pub batch: usize,
    pub evals_per_s: f64,
    /// The instruction set used.
    pub isa: String,
    /// Fraction of the measured FMA-pipe throughput used by the formula's own multiplies and
    /// adds (`fma_slots`): only for kernels of cosines whose formula is multiplies and adds
    /// alone (no division, square root or transcendental, whose cost the registry's counts do
    /// not measure); `null` otherwise.
    pub fma_fraction: Option<f64>,
    /// The machine limit that bounds this kernel, `"fma"` (the FMA pipes) or `"divider"`
    /// (the divide unit), with the fraction of it used ([`limit_fraction`]): for kernels of
    /// cosines whose formula is multiplies, adds and divisions, and for those whose family
    /// counts its kernel's operations (`Kernel::pipe_ops`: `sg`, `ue4-phong-approx`,
    /// `sg-tuned`, `beckmann`, `beckmann-ct`, whose vectorised `exp2` is a polynomial the
    /// registry's counts do not see); `null` otherwise. Absent from runs saved before it
    /// existed.
    #[serde(default)]
    pub limit: Option<String>,
    #[serde(default)]
    pub limit_fraction: Option<f64>,
    /// The SPIR-V instructions of the model's shader after `spirv-opt -O`, by class
    /// (`fastbrdf_gpu::cost`: the committed table for the built-in models, counted at run time
    /// for a user's shader, `file:PATH`); `null` when unknown (no `spirv-opt` for a user's
    /// shader, a model the table lacks). A property of the model, the same on every row of
    /// it; absent from runs saved before it existed.
    #[serde(default)]
    pub instructions: Option<Instructions>,
}

/// Instruction counts by class, as `fastbrdf_gpu::cost::Counts` (see its module
/// documentation for the classes); `total` is the sum of the six.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Instructions {
    pub arithmetic: u32,
    pub transcendental: u32,
    pub division_sqrt: u32,
    pub branches: u32,
    pub select: u32,
    pub other: u32,
    pub total: u32,
}

impl Instructions {
    /// The sum of the six classes (a saved run's `total` must equal it).
    pub fn sum(&self) -> u64 {
        [
            self.arithmetic,
            self.transcendental,
            self.division_sqrt,
            self.branches,
            self.select,
            self.other,
        ]
        .iter()
        .map(|&x| u64::from(x))
        .sum()
    }
}

/// One speedup.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SpeedupRow {
    pub name: String,
    pub measured: f64,
    /// The seed's number, when it states one.
    pub claimed: Option<f64>,
    /// How it was measured.
    pub how: String,
}

/// The whole run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub cpu: String,
    pub isa: String,
    pub threads: usize,
    /// Lane FMAs per second on one core with `isa` (independent FMA chains).
    pub fma_per_s: f64,
    /// Lane divisions per second on one core with `isa` (independent division chains);
    /// absent from runs saved before it was measured.
    #[serde(default)]
    pub div_per_s: Option<f64>,
    pub kernels: Vec<KernelRow>,
    pub speedups: Vec<SpeedupRow>,
    pub quick: bool,
    /// The GPU adapter of `--gpu` rows (variants `gpu`, `gpu+transfer`), with a warning when it
    /// is a software adapter (its figures are CPU figures); absent without `--gpu`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu: Option<String>,
    /// Each batch kernel raced against its C peer (absent from runs saved before issue 13,
    /// which load with none).
    #[serde(default)]
    pub peers: Vec<PeerRow>,
    /// The large-batch figures left out because one call would have taken too long (absent
    /// from runs saved before it existed, which load with none).
    #[serde(default)]
    pub skipped: Vec<Skipped>,
}

/// Largest saved run read (`fastbrdf bench --from`, `pareto --bench`, `reproduce --speedups`).
pub const SAVED_RUN_LIMIT: u64 = 64 << 20;

/// Largest plausible throughput figure (evaluations or lane-FMAs per second): 10^15, far above
/// any machine, so that only impossible numbers are refused.
const MAX_RATE: f64 = 1e15;

impl Report {
    /// Reads a saved `fastbrdf bench --json` run (once, at most [`SAVED_RUN_LIMIT`] bytes) and
    /// checks that every figure is a possible measurement: rates finite, positive and at most
    /// 10^15 per second, speedups finite and positive, at least one thread, batches of at least
    /// one element. The error names the file and the first impossible field.
    pub fn load(path: &std::path::Path) -> Result<Self, fastbrdf_io::IoError> {
        let bad = |message: String| fastbrdf_io::IoError::Input {
            path: path.display().to_string(),
            message,
        };
        let text = fastbrdf_io::read_text_bounded(path, SAVED_RUN_LIMIT, "a bench run")?;
        let r: Report = serde_json::from_str(&text)
            .map_err(|e| bad(format!("not a `fastbrdf bench --json` run: {e}")))?;
        let rate = |x: f64| x.is_finite() && x > 0.0 && x <= MAX_RATE;
        if !rate(r.fma_per_s) {
            return Err(bad(format!(
                "fma_per_s = {} is not a possible rate (finite, positive, at most 1e15)",
                r.fma_per_s
            )));
        }
        if let Some(d) = r.div_per_s.filter(|&d| !rate(d)) {
            return Err(bad(format!(
                "div_per_s = {d} is not a possible rate (finite, positive, at most 1e15)"
            )));
        }
        if r.threads == 0 {
            return Err(bad("threads = 0: a run has at least one thread".into()));
        }
        for (i, k) in r.kernels.iter().enumerate() {
            if !rate(k.evals_per_s) || k.batch == 0 {
                return Err(bad(format!(
                    "kernels[{i}] ({} {}): evals_per_s = {} with batch {} is not a possible measurement",
                    k.model, k.variant, k.evals_per_s, k.batch
                )));
            }
            if let Some(c) = k.instructions.filter(|c| c.sum() != u64::from(c.total)) {
                return Err(bad(format!(
                    "kernels[{i}] ({}): instructions.total = {} is not the sum of its classes ({})",
                    k.model,
                    c.total,
                    c.sum()
                )));
            }
            let fractions = [
                ("fma_fraction", k.fma_fraction),
                ("limit_fraction", k.limit_fraction),
            ];
            for (name, f) in fractions {
                if let Some(f) = f.filter(|f| !(f.is_finite() && *f >= 0.0)) {
                    return Err(bad(format!(
                        "kernels[{i}] ({}): {name} = {f} is not a fraction",
                        k.model
                    )));
                }
            }
        }
        for (i, s) in r.speedups.iter().enumerate() {
            let ok = |x: f64| x.is_finite() && x > 0.0;
            if !ok(s.measured) || s.claimed.is_some_and(|c| !ok(c)) {
                return Err(bad(format!(
                    "speedups[{i}] ({}): a speedup is a finite positive ratio",
                    s.name
                )));
            }
        }
        for (i, p) in r.peers.iter().enumerate() {
            let spreads = [&p.kernel_evals_per_s, &p.peer_evals_per_s];
            let rates_ok = spreads.iter().all(|s| s.values().into_iter().all(rate));
            let ratio_ok = p
                .ratio
                .values()
                .into_iter()
                .all(|x| x.is_finite() && x > 0.0);
            let err_ok = |e: f64| e.is_finite() && e >= 0.0;
            if !rates_ok || !ratio_ok || p.batch == 0 || p.rounds == 0 || p.repeats == 0 {
                return Err(bad(format!(
                    "peers[{i}] ({}): rates, ratio, batch, rounds and repeats must be possible measurements",
                    p.model
                )));
            }
            if !err_ok(p.kernel_max_error) || !err_ok(p.peer_max_error) {
                return Err(bad(format!(
                    "peers[{i}] ({}): an error is finite and non-negative",
                    p.model
                )));
            }
        }
        Ok(r)
    }

    /// Every speedup of the run as `(name, measured)`, as [`crate::reproduce::run`] takes them.
    pub fn measured_speedups(&self) -> Vec<(String, f64)> {
        self.speedups
            .iter()
            .map(|s| (s.name.clone(), s.measured))
            .collect()
    }
}

/// Below this ratio of a kernel's rate to a saved run's, `fastbrdf bench --compare` marks the
/// row `slower`: this shared 2-core machine moves a kernel by 10-20% between runs, while the
/// regressions this is for were 2-10x (the Cook-Torrance kernels ran 6-10x slower for a day of
/// commits before anyone compared the tables).
pub const SLOWER_BELOW: f64 = 0.8;

/// One kernel row of two runs: `ratio = new / old` evaluations per second.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CompareRow {
    pub model: String,
    pub variant: String,
    pub batch: usize,
    pub old_evals_per_s: f64,
    pub new_evals_per_s: f64,
    pub ratio: f64,
    /// `ratio < SLOWER_BELOW`.
    pub slower: bool,
}

/// The kernel rows `new` shares with `old` (same model, variant and batch), in `new`'s order.
pub fn compare(old: &Report, new: &Report) -> Vec<CompareRow> {
    new.kernels
        .iter()
        .filter_map(|k| {
            let o = old
                .kernels
                .iter()
                .find(|o| o.model == k.model && o.variant == k.variant && o.batch == k.batch)?;
            let ratio = k.evals_per_s / o.evals_per_s;
            Some(CompareRow {
                model: k.model.clone(),
                variant: k.variant.clone(),
                batch: k.batch,
                old_evals_per_s: o.evals_per_s,
                new_evals_per_s: k.evals_per_s,
                ratio,
                slower: ratio < SLOWER_BELOW,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `compare` pairs rows by model, variant and batch, in the new run's order, and marks
    /// only the ones below `SLOWER_BELOW`.
    #[test]
    fn compare_pairs_rows_and_marks_the_slower_ones() {
        let row = |model: &str, variant: &str, batch: usize, rate: f64| KernelRow {
            model: model.into(),
            variant: variant.into(),
            batch,
            evals_per_s: rate,
            isa: "avx512".into(),
            fma_fraction: None,
            limit: None,
            limit_fraction: None,
            instructions: None,
        };
        let run = |kernels: Vec<KernelRow>| Report {
            cpu: "test".into(),
            isa: "avx512".into(),
            threads: 2,
            fma_per_s: 1e11,
            div_per_s: None,
            speedups: vec![],
            kernels,
            quick: true,
            gpu: None,
            peers: vec![],
            skipped: vec![],
        };
        let old = run(vec![
            row("power4", "simd", 4096, 4e10),
            row("cook-torrance", "simd", 4096, 5e8),
            row("cook-torrance", "simd", 1 << 24, 5e8),
            row("ward", "simd", 4096, 5e8),
        ]);
        let new = run(vec![
            row("cook-torrance", "simd", 4096, 6e7),
            row("power4", "simd", 4096, 3.3e10),
            row("power4", "scalar", 4096, 7e8),
            row("phong", "simd", 4096, 4e8),
        ]);
        let c = compare(&old, &new);
        let got: Vec<(&str, f64, bool)> = c
            .iter()
            .map(|r| (r.model.as_str(), r.ratio, r.slower))
            .collect();
        assert_eq!(
            got,
            [("cook-torrance", 0.12, true), ("power4", 0.825, false)]
        );
        assert_eq!((c[0].old_evals_per_s, c[0].new_evals_per_s), (5e8, 6e7));
        assert!(
            compare(&new, &new)
                .iter()
                .all(|r| r.ratio == 1.0 && !r.slower)
        );
    }

    /// `instructions` is written as null when unknown and as the counts object otherwise; a
    /// saved run without it loads with none; a saved total that is not the sum of its classes
    /// is refused, naming the row.
    #[test]
    fn instructions_are_null_or_counts_and_a_wrong_total_is_refused() {
        let mut row = KernelRow {
            model: "file:mine.brdf".into(),
            variant: "gpu".into(),
            batch: 1024,
            evals_per_s: 1e7,
            isa: "gpu".into(),
            fma_fraction: None,
            limit: None,
            limit_fraction: None,
            instructions: None,
        };
        let v = serde_json::to_value(&row).unwrap();
        assert!(v["instructions"].is_null(), "{v}");
        let c = Instructions {
            arithmetic: 37,
            transcendental: 4,
            division_sqrt: 12,
            branches: 4,
            select: 0,
            other: 13,
            total: 70,
        };
        row.instructions = Some(c);
        let v = serde_json::to_value(&row).unwrap();
        assert_eq!(v["instructions"]["division_sqrt"], 12);
        assert_eq!(v["instructions"]["total"], 70);
        let mut old = v.clone();
        old.as_object_mut().unwrap().remove("instructions");
        let back: KernelRow = serde_json::from_value(old).unwrap();
        assert_eq!(back.instructions, None);
        let run = |kernels: Vec<KernelRow>| Report {
            cpu: "test".into(),
            isa: "avx2".into(),
            threads: 1,
            fma_per_s: 1e10,
            div_per_s: None,
            kernels,
            speedups: vec![],
            quick: true,
            gpu: Some("test".into()),
            peers: vec![],
            skipped: vec![],
        };
        let dir = std::env::temp_dir().join(format!("fastbrdf-speed-instr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("run.json");
        std::fs::write(
            &path,
            serde_json::to_string(&run(vec![row.clone()])).unwrap(),
        )
        .unwrap();
        let loaded = Report::load(&path).unwrap();
        assert_eq!(loaded.kernels[0].instructions, Some(c));
        row.instructions = Some(Instructions { total: 71, ..c });
        std::fs::write(&path, serde_json::to_string(&run(vec![row])).unwrap()).unwrap();
        let e = Report::load(&path).unwrap_err().to_string();
        assert!(
            e.contains("kernels[0] (file:mine.brdf)") && e.contains("71"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
