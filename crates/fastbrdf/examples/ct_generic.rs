//! What Cook-Torrance's generic path costs (issue 28, `batch::cook_torrance`): for
//! configurations with a specialised kernel, the specialised kernel and the generic path
//! (a vectorised pass per part over blocks of pairs) are timed interleaved on the same 4096
//! direction pairs, best instruction set, one thread; the generic path of configurations
//! without one is timed against the plan's parts matched per element (the only other way to
//! run them). Medians of 41 rounds, ns per evaluation.
//! Run: `cargo run --release -p fastbrdf --example ct_generic`.

use fastbrdf::ModelSpec;
use fastbrdf::batch::{CtPath, Input, Isa, Kernel};
use std::time::Instant;

mod common;
use common::median;

fn main() {
    let cols = common::pair_columns(4096, 3);
    let n = cols[0].len();
    let input = Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
    println!(
        "isa: {}, {n} pairs, ns per evaluation (median of 41)",
        Isa::best().name()
    );
    let configs: [&[(&str, &str)]; 9] = [
        // Specialised by the rule.
        &[
            ("d", "ggx"),
            ("g", "smith-ggx-correlated"),
            ("f", "dielectric"),
        ],
        &[
            ("d", "ggx"),
            ("g", "smith-ggx-correlated-fast"),
            ("f", "schlick-sg"),
        ],
        &[("d", "ggx"), ("g", "smith-ggx"), ("f", "conductor")],
        &[("d", "beckmann"), ("g", "smith-rational"), ("f", "schlick")],
        &[
            ("d", "beckmann-power16"),
            ("g", "v-cavity"),
            ("f", "schlick"),
            ("denominator", "seed-000"),
        ],
        // Generic by the rule.
        &[("d", "beckmann"), ("g", "smith"), ("f", "none")],
        &[("d", "beckmann"), ("g", "smith-ggx"), ("f", "dielectric")],
        &[("d", "ggx"), ("g", "kelemen"), ("f", "dielectric")],
        &[("d", "beckmann-pow"), ("g", "neumann"), ("f", "schlick-sg")],
    ];
    let mut ratios = vec![];
    for given in configs {
        let spec = ModelSpec::parse("cook-torrance", given).unwrap();
        let plan = spec.plan().unwrap();
        let rule = Kernel::from_plan(spec.id(), plan).unwrap();
        let (a_name, a, b_name) = if rule.specialised() {
            ("specialised", rule, "generic")
        } else {
            let per = Kernel::from_plan_path(spec.id(), plan, CtPath::PerElement).unwrap();
            ("per element", per, "generic")
        };
        let b = Kernel::from_plan_path(spec.id(), plan, CtPath::Generic).unwrap();
        let mut out = vec![0.0f32; n];
        let (mut ta, mut tb) = (vec![], vec![]);
        for _ in 0..41 {
            let t = Instant::now();
            for _ in 0..8 {
                a.eval(input, &mut out).unwrap();
            }
            ta.push(t.elapsed().as_secs_f64() / (8 * n) as f64);
            let t = Instant::now();
            for _ in 0..8 {
                b.eval(input, &mut out).unwrap();
            }
            tb.push(t.elapsed().as_secs_f64() / (8 * n) as f64);
        }
        let (ta, tb) = (median(ta) * 1e9, median(tb) * 1e9);
        let label = given
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(" ");
        println!(
            "{label:62} {a_name:11} {ta:6.2}  {b_name} {tb:6.2}  {b_name}/{a_name} {:.2}",
            tb / ta
        );
        if a_name == "specialised" {
            ratios.push(tb / ta);
        }
    }
    let geo = ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64;
    println!(
        "generic/specialised: geometric mean {:.2} over {} configurations",
        geo.exp(),
        ratios.len()
    );
}
