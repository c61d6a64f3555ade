//! `fastbrdf metals`: the named metals (complex index `eta + i k` per R, G, B channel, cited).
//! `--metal NAME` (render, compare, shader, eval) is `crate::model_args`.

use crate::CliError;
use fastbrdf::colour::{CHANNELS, METALS, WAVELENGTHS_NM};
use std::fmt::Write;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf metals\n  fastbrdf metals --json\n  \
fastbrdf render --model cook-torrance --param d=ggx --param g=smith-ggx-correlated --param alpha=0.2 --metal gold --out gold.png\n  \
fastbrdf compare --models ggx,beckmann --reference cook-torrance --param alpha=0.2 --metal copper --out cu.png\n  \
fastbrdf shader --model cook-torrance --param d=ggx --param g=smith-ggx-correlated --metal gold --lang glsl\n  \
fastbrdf render --model cook-torrance --param f=conductor --param eta=0.2,0.4,1.4 --param k=3.4,2.3,1.8 --out au.png\n\n\
--metal NAME gives a model f = conductor, eta = R,G,B and k = R,G,B (650, 550, 450 nm), which\n\
makes it coloured: three channel models, one per colour channel. Any numeric parameter may be\n\
given as R,G,B the same way (--param f0=0.95,0.64,0.54). --param values win over the metal's.\n\
A model without the conductor Fresnel term's parameters (eta, k: cook-torrance, the\n\
distributions, which shade as cook-torrance, and fresnel-conductor) is an error with --metal.\n\n\
Sources: refractiveindex.info's \"3D: selected data for 3D artists\" values at 650/550/450 nm\n\
as tabulated by Chaos Group (\"Understanding metalness\"); attributed to Johnson & Christy 1972\n\
(Au, Ag, Cu), Rakic 1995 (Al), Johnson & Christy 1974 (Cr, Fe). F0 is the conductor Fresnel\n\
term at normal incidence, ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2)."
)]
pub struct Args {
    /// Print JSON: an array of {"id", "symbol", "eta": [r, g, b], "k": [r, g, b], "f0":
    /// [r, g, b], "source"}, numbers as numbers, plus "wavelengths_nm" once: {"wavelengths_nm":
    /// [650, 550, 450], "metals": [...]}.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    if a.json {
        let doc = fastbrdf_analysis::render_json::metals();
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("serialisable")
        );
        return Ok(());
    }
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<10} {:<3} {:<24} {:<24} {:<20} source",
        "id", "", "eta (R, G, B)", "k (R, G, B)", "F0 (R, G, B)"
    );
    let three = |v: [f64; 3], p: usize| {
        v.iter()
            .map(|x| format!("{x:.p$}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    for m in &METALS {
        let _ = writeln!(
            s,
            "{:<10} {:<3} {:<24} {:<24} {:<20} {}",
            m.id,
            m.symbol,
            three(m.eta, 5),
            three(m.k, 4),
            three(m.f0(), 4),
            m.source
        );
    }
    let _ = writeln!(
        s,
        "channels {} at {} nm; F0: conductor Fresnel at normal incidence",
        CHANNELS.join(", "),
        WAVELENGTHS_NM
            .iter()
            .map(|w| w.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    crate::out!("{s}");
    Ok(())
}
