//! `fastbrdf materials`: the 86 MERL materials' published fits (Ngan, Matusik and Durand,
//! EGSR 2005). `--material NAME` is `crate::model_args`.

use crate::CliError;
use fastbrdf_analysis::materials;
use std::fmt::Write;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf materials\n  fastbrdf materials --json\n  \
fastbrdf shader --model flog --material gold-paint            (n = the material's Blinn-Phong n)\n  \
fastbrdf render --model cook-torrance --material gold-paint --param f=schlick --out gold.png\n  \
fastbrdf errors --over materials\n\n\
Source: Ngan, Matusik and Durand, \"Experimental Analysis of BRDF Models\", EGSR 2005, the fits\n\
of the 86 MERL materials (transcribed from bsdfbenchmark/bbm fits/ngan_{blinnphong,cooktorrance,ward}.fit).\n\
--material NAME gives a model the material's figures by parameter: n from blinn_phong_n;\n\
alpha of Ward (ward, ward-*) from ward_alpha; alpha of distributions, shadowing and\n\
cook-torrance from cook_torrance_m (Beckmann m = alpha); f0 from cook_torrance_f0. Explicit\n\
--param values win. In render and compare it also sets --albedo to the matching fit's kd and\n\
the diffuse weight to 1 unless given. The `inside` column names the model families whose\n\
current documented domains hold the material's figures (blinn-phong: n; cook-torrance: m and\n\
f0; ward: alpha)."
)]
pub struct Args {
    /// Print JSON: an array of {"name", "blinn_phong": {"n", "kd": [r, g, b], "ks": [r, g, b]},
    /// "cook_torrance": {"m", "f0", "kd", "ks"}, "ward": {"alpha", "kd", "ks"}, "inside":
    /// [family, ...]}, numbers as numbers, in the table's order.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let all = materials::all();
    if a.json {
        let rows = fastbrdf_analysis::render_json::materials();
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&rows).expect("serialisable")
        );
        return Ok(());
    }
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} MERL materials, fits by Ngan, Matusik and Durand (EGSR 2005)",
        all.len()
    );
    let _ = writeln!(
        s,
        "{:<26} {:>10} {:>8} {:>8} {:>8}  inside documented domains",
        "material", "n", "m", "f0", "ward a"
    );
    for m in all {
        let inside = materials::families(m);
        let _ = writeln!(
            s,
            "{:<26} {:>10} {:>8} {:>8} {:>8}  {}",
            m.name,
            m.blinn_phong_n,
            m.cook_torrance_m,
            m.cook_torrance_f0,
            m.ward_alpha,
            if inside.is_empty() {
                "-".to_string()
            } else {
                inside.join(", ")
            }
        );
    }
    let count = |f: &str| {
        all.iter()
            .filter(|m| materials::families(m).contains(&f))
            .count()
    };
    let dom = |id: &str, p: &str| {
        materials::domain(id, p).map_or_else(String::new, |(lo, hi)| format!("[{lo}, {hi}]"))
    };
    let _ = writeln!(
        s,
        "inside: blinn-phong {} of {} (n in {}), cook-torrance {} (m in {}, f0 in {}), ward {} (alpha in {})",
        count("blinn-phong"),
        all.len(),
        dom("blinn-phong", "n"),
        count("cook-torrance"),
        dom("cook-torrance", "alpha"),
        dom("cook-torrance", "f0"),
        count("ward"),
        dom("ward", "alpha"),
    );
    crate::out!("{s}");
    Ok(())
}
