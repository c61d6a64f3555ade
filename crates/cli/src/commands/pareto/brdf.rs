//! `fastbrdf pareto --brdf`: full Cook-Torrance configurations against an exact reference
//! (fastbrdf-analysis::pareto_brdf): SIMD cost, BRDF-space and image-space error, Pareto front.

use crate::CliError;
use crate::commands::common::figures::save_error;
use crate::commands::common::progress::bar;
use fastbrdf_analysis::pareto_brdf::{self as pb, Config, FrontOn, Grid, Images, Row};
use fastbrdf_analysis::plot::{Point, save_scatter};
use fastbrdf_analysis::range;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The options of `pareto --brdf` (ignored without `--brdf`).
#[derive(clap::Args)]
pub struct BrdfArgs {
    /// Full specular BRDFs (cook-torrance: distribution x shadowing x Fresnel) against an exact
    /// reference configuration instead of lobes against cos^n.
    #[arg(long)]
    pub brdf: bool,
    /// With --brdf: roughness, one value or a list/range (LO..HI:STEP); every configuration,
    /// Beckmann and GGX alike, takes the same alpha.
    #[arg(long, default_value = "0.3", value_name = "ALPHAS", requires = "brdf")]
    pub alpha: String,
    /// With --brdf: the reference, cook-torrance parameters without alpha.
    #[arg(
        long,
        default_value = "d=ggx,g=smith-ggx-correlated,f=dielectric,eta=1.5",
        value_name = "PARAMS",
        requires = "brdf"
    )]
    pub reference: String,
    /// With --brdf: render side in pixels for the FLIP columns (1 sample per pixel); 0 skips
    /// the renders.
    #[arg(long, default_value_t = 128, value_name = "PIXELS", requires = "brdf")]
    pub size: u32,
    /// With --brdf: also compare renders of this OBJ mesh (e.g. the face).
    #[arg(long, value_name = "OBJ", requires = "brdf")]
    pub mesh: Option<PathBuf>,
    // The help's list and count come from the registry (`pareto_brdf::all_fresnel`,
    // `all_count`): a part added to it is counted, never a number written by hand.
    #[arg(long, requires = "brdf", help = all_help())]
    pub all: bool,
    /// With --brdf: a few seconds: a coarse BRDF grid (16 x 16 x 32 pairs), 5 ms per timing,
    /// renders of at most 32 x 32 pixels.
    #[arg(long, requires = "brdf")]
    pub quick: bool,
    /// With --brdf: the error the front is taken on: rms (rms_rel), max (max_rel_peak) or flip
    /// (flip_sphere).
    #[arg(long, default_value = "rms", value_parser = ["rms", "max", "flip"], requires = "brdf")]
    pub front_on: String,
    /// With --brdf: the BRDF-space grid, THETAxPHI (midpoints per hemisphere angle x relative
    /// azimuths, even): 48x96 by default, 16x32 with --quick.
    #[arg(long, value_name = "THETAxPHI", requires = "brdf")]
    pub grid: Option<String>,
    /// With --brdf: take the costs from this saved `pareto --brdf --json` output instead of
    /// measuring them (what the book's table in docs/book/src/pareto-brdf.md does, so that a test
    /// can keep it current).
    #[arg(long, value_name = "PARETO.json", requires = "brdf")]
    pub costs: Option<PathBuf>,
}

/// `--all`'s help: the Fresnel terms and the count, from the registry.
fn all_help() -> String {
    format!(
        "With --brdf: every distribution x shadowing term x Fresnel ({}): {} configurations",
        pb::all_fresnel().join(", "),
        pb::all_count()
    )
}

fn opt(x: Option<f64>, prec: usize) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.prec$}"),
        _ => "-".into(),
    }
}

/// The F column: the Fresnel id, and the parameters that are neither d, g nor f.
fn f_col(r: &Row) -> String {
    let mut s = r.f.clone();
    for (k, v) in &r.params {
        if !matches!(k.as_str(), "d" | "g" | "f") {
            s.push_str(&format!(" {k}={v}"));
        }
    }
    s
}

pub fn run(a: &BrdfArgs, json: bool, markdown: bool, out: Option<&Path>) -> Result<(), CliError> {
    let alphas =
        range::parse(&a.alpha, 0.05).map_err(|e| CliError::input(format!("--alpha: {e}")))?;
    let (lo, hi) = (fastbrdf::params::ALPHA_MIN, 1.0);
    if let Some(bad) = alphas.iter().find(|x| !(**x >= lo && **x <= hi)) {
        return Err(CliError::input(format!(
            "--alpha: {} is outside [{lo}, {hi}]",
            range::num(*bad)
        )));
    }
    if alphas.len() > 16 {
        return Err(CliError::input("--alpha: at most 16 values"));
    }
    let reference =
        Config::parse(&a.reference).map_err(|e| CliError::input(format!("--reference: {e}")))?;
    let size = if a.quick { a.size.min(32) } else { a.size };
    if size > 1024 {
        return Err(CliError::input("--size: at most 1024"));
    }
    let images = if size == 0 {
        if a.mesh.is_some() {
            return Err(CliError::input("--mesh needs renders: --size above 0"));
        }
        None
    } else {
        Some(Images::new(size, a.mesh.clone())?)
    };
    let saved_costs = match &a.costs {
        None => None,
        Some(p) => {
            let bytes = fastbrdf_io::read_bounded(p, 64 << 20, "--costs")?;
            let v: serde_json::Value = serde_json::from_slice(&bytes)
                .map_err(|e| CliError::input(format!("--costs {}: {e}", p.display())))?;
            Some(
                pb::saved_costs(&v)
                    .map_err(|e| CliError::input(format!("--costs {}: {e}", p.display())))?,
            )
        }
    };
    let o = pb::Options {
        saved_costs,
        reference,
        configs: pb::configurations(a.all),
        alphas,
        grid: match &a.grid {
            Some(g) => Grid::parse(g).map_err(|e| CliError::input(format!("--grid {e}")))?,
            None if a.quick => Grid::QUICK,
            None => Grid::DEFAULT,
        },
        budget: Duration::from_millis(if a.quick { 5 } else { 60 }),
        images,
        front_on: FrontOn::parse(&a.front_on).expect("clap checked it"),
    };
    let bar = bar(pb::steps(&o) as u64, "pareto");
    let rows = pb::run(&o, &|| bar.inc(1)).map_err(|e| match &a.costs {
        Some(p) if e.starts_with("the saved costs") => {
            CliError::input(format!("--costs {}: {e}", p.display()))
        }
        _ => CliError::input(e),
    })?;
    bar.finish_and_clear();
    if let Some(out) = out {
        let first: Vec<&Row> = rows.iter().filter(|r| r.alpha == o.alphas[0]).collect();
        let y = |r: &Row| match o.front_on {
            FrontOn::Rms => r.rms_rel,
            FrontOn::Max => r.max_rel_peak,
            FrontOn::FlipSphere => r.flip_sphere.unwrap_or(f64::NAN),
        };
        let points: Vec<Point> = first
            .iter()
            .map(|r| Point {
                label: r.label.clone(),
                x: r.ns_per_eval,
                y: y(r),
                highlight: r.pareto,
            })
            .collect();
        let front: Vec<(f64, f64)> = first
            .iter()
            .filter(|r| r.pareto)
            .map(|r| (r.ns_per_eval, y(r)))
            .collect();
        let [png, svg] = save_scatter(
            &format!(
                "Cook-Torrance configurations: {} against cost (alpha = {})",
                o.front_on.name(),
                range::num(o.alphas[0])
            ),
            "ns per evaluation (SIMD, one core, 4096 direction pairs)",
            o.front_on.name(),
            &front,
            &points,
            out,
        )
        .map_err(save_error)?;
        eprintln!("wrote {} and {}", png.display(), svg.display());
    }
    let mesh_name = a
        .mesh
        .as_ref()
        .and_then(|m| m.file_stem())
        .map(|s| s.to_string_lossy().into_owned());
    if json {
        let mesh = a.mesh.as_ref().map(|m| m.display().to_string());
        let v = pb::json(&o, &rows, size, mesh.as_deref());
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    } else if markdown {
        let mesh_col = mesh_name
            .as_deref()
            .map(|m| format!(" FLIP {m} |"))
            .unwrap_or_default();
        crate::outln!(
            "| alpha | D | G | F | ns/eval | x ref | max / peak | RMS rel | FLIP sphere |{mesh_col} Pareto |"
        );
        crate::outln!(
            "|---|---|---|---|---|---|---|---|---|{}---|",
            if mesh_name.is_some() { "---|" } else { "" }
        );
        for r in &rows {
            let mesh = if mesh_name.is_some() {
                format!(" {} |", opt(r.flip_mesh, 4))
            } else {
                String::new()
            };
            crate::outln!(
                "| {} | `{}` | `{}`{} | `{}` | {:.2} | {:.2} | {:.4} | {:.4} | {} |{mesh} {} |",
                range::num(r.alpha),
                r.d,
                r.g,
                if r.simd { "" } else { " (erfc)" },
                f_col(r),
                r.ns_per_eval,
                r.cost_ratio,
                r.max_rel_peak,
                r.rms_rel,
                opt(r.flip_sphere, 4),
                match (r.reference, r.pareto) {
                    (true, true) => "reference, yes",
                    (true, false) => "reference",
                    (false, true) => "yes",
                    (false, false) => "",
                }
            );
        }
    } else {
        crate::outln!(
            "reference: cook-torrance {} ({}); front on (ns/eval, {}); * on the front, = the reference",
            o.reference.label(),
            a.reference,
            o.front_on.name()
        );
        crate::outln!(
            "{:>5} {:<17} {:<33} {:<26} {:>8} {:>6} {:>9} {:>14} {:>9} {:>8} {:>8}",
            "alpha",
            "D",
            "G",
            "F",
            "ns/eval",
            "x ref",
            "max/peak",
            "at ti/to/phi",
            "rms rel",
            "FLIP sph",
            "FLIP msh"
        );
        for r in &rows {
            crate::outln!(
                "{:>5} {:<17} {:<33} {:<26} {:>8.2} {:>6.2} {:>9.4} {:>14} {:>9.4} {:>8} {:>8} {}",
                range::num(r.alpha),
                r.d,
                format!("{}{}", r.g, if r.simd { "" } else { " (erfc)" }),
                f_col(r),
                r.ns_per_eval,
                r.cost_ratio,
                r.max_rel_peak,
                if r.max_rel_peak > 0.0 {
                    format!(
                        "{:.0}/{:.0}/{:.0}",
                        r.max_at_deg[0], r.max_at_deg[1], r.max_at_deg[2]
                    )
                } else {
                    "-".into()
                },
                r.rms_rel,
                opt(r.flip_sphere, 4),
                opt(r.flip_mesh, 4),
                match (r.reference, r.pareto) {
                    (true, true) => "=*",
                    (true, false) => "=",
                    (false, true) => "*",
                    (false, false) => "",
                }
            );
        }
    }
    Ok(())
}
