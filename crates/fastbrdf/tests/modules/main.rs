//! No import circles (issue 28, "Circles"): for every crate of the workspace, the modules'
//! imports read from the source form no cycle, except the core's registration.
//!
//! How the graph is built (from the text, no compiler):
//!
//! - A module is a file: `a.rs` or `a/mod.rs` is the module `a`, found from the crate root by
//!   its `mod a;` declarations. Inline `mod x { .. }` blocks belong to their file.
//! - Comments (doc comments included), string and character literals are blanked first, and
//!   every `#[cfg(test)]` module (a `mod tests { .. }` block, or a `mod x;` file) is left out:
//!   a test that imports its parent with `use super::*` is not an import of the shipped code.
//! - Edges come from `use` trees and from paths in code that start with `crate::`, `$crate::`,
//!   `super::` (resolved from the file, through the inline modules around it), `self::`, a child
//!   module, or a name that a `use` bound to a module of the crate. A path that names an item is
//!   followed through the `use` / `pub use` re-exports of the module it reaches, so
//!   `crate::Plan` is an edge to the module that defines `Plan`, not to `lib.rs`. A `use` that
//!   only names a module (`use super::render;`) binds the name; the paths that use it are the
//!   edges. Every edge keeps its `file:line`.
//!
//! The rule for module folders: a folder (`a/mod.rs` with `a/b.rs`, `a/c.rs`, ...) is one node
//! seen from outside it, and its children are the nodes seen from inside it. So cycles are looked
//! for at every level separately: among the top-level modules of the crate (each folder taken
//! whole, an edge into or out of any of its files being the folder's), and among the children of
//! each folder (sub-folders again taken whole). Edges from or to the level's own `mod.rs` (or the
//! crate root's `lib.rs` / `main.rs`) do not count at that level: the folder's `mod.rs` declares,
//! dispatches to and re-exports its children, and what it holds for them (`super::Row` in
//! `speed/report.rs`) is the folder's own; at the level above, that traffic is inside one node.
//! Two children of one folder that import each other (`commands/eval.rs` <-> `commands/render.rs`)
//! are a cycle, and so is a folder and an outside module importing each other through any files.
//!
//! The one cycle allowed is the core's registration (see `registration_allows`).
//!
//! The reader is in `source.rs` (one file's text), the graph and its cycles in `graph.rs`; this
//! file holds the rule for the registration and the tests.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

mod graph;
mod source;

use graph::{Cycle, Edge, Graph, build, child_holding, cycles, describe, sccs};
use source::Module;

/// The crates of the workspace, by the folder that holds `src/`.
const CRATES: [&str; 7] = [
    "crates/fastbrdf",
    "crates/io",
    "crates/analysis",
    "crates/render",
    "crates/gpu",
    "crates/cli",
    "python",
];

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

// ---------------------------------------------------------------- the registration

/// The top-level modules of the core that the registration cycle may take in, each because
/// the registration needs it:
///
/// - `plan`: its family lists (`LobePlan`, `DistributionPlan`, ...) name the family types;
/// - `entry`: an `Entry` is what a family file declares (its `ENTRY` constant), built from a
///   `Plan`;
/// - `lobes`, `microfacet`, `brdf`: the folders of the family files, whose `ENTRY` constants
///   build a `Plan` and whose types the plan lists name.
///
/// `registry` (the list of entries) imports the families and the plan but nothing in the cycle
/// imports it back, so it is not allowed in: a family that reached for the registry would be a
/// new circle.
const REGISTRATION: [&str; 5] = ["plan", "entry", "lobes", "microfacet", "brdf"];

/// Files of the family folders (relative to `crates/fastbrdf/src`) that are not family files
/// but may lie on the registration cycle, each with its reason. A helper that a family uses and
/// that uses another family (`fits.rs` taking `cubic`'s shape, `ms.rs` taking `env_brdf`'s
/// albedo) lies on the cycle through `plan.rs`: it is named here with why, or it leaves the
/// cycle (what it takes from the family moves to a leaf).
const PULLED_IN: [(&str, &str); 2] = [
    (
        "lobes/fits.rs",
        "the tuned families' fitted constants (power, sg and rational read them; they take \
         cubic's shape): part of the lobe families, split out so that tuned no longer imports \
         the families it builds",
    ),
    (
        "microfacet/ms.rs",
        "Cook-Torrance's energy compensation table (cook_torrance and plan's WGSL library read \
         it; it takes env_brdf's albedo): part of the Cook-Torrance family",
    ),
];

/// The reason `PULLED_IN` gives for the file of `m`, if it names it.
fn pulled_in(m: &Module) -> Option<&'static str> {
    PULLED_IN
        .iter()
        .find(|(file, _)| *file == m.file)
        .map(|(_, why)| *why)
}

/// A family file: a file of `lobes/`, `microfacet/` or `brdf/` (not a folder's `mod.rs`) that
/// declares an `ENTRY` constant.
fn family_file(m: &Module) -> bool {
    matches!(
        m.path.first().map(String::as_str),
        Some("lobes" | "microfacet" | "brdf")
    ) && !m.is_dir_module
        && m.code.iter().collect::<String>().contains("const ENTRY")
}

/// Whether a file may lie on the registration cycle: `plan.rs`, `entry.rs`, a family file, or
/// one of `PULLED_IN`. A folder's `mod.rs` or another helper file there may not.
fn registration_file(m: &Module) -> bool {
    m.path == ["plan"] || m.path == ["entry"] || family_file(m) || pulled_in(m).is_some()
}

/// An edge of the registration itself: a family file importing `plan.rs` or `entry.rs` (its
/// `ENTRY` builds a `Plan`).
fn registration_edge(g: &Graph, e: &Edge) -> bool {
    family_file(&g.modules[e.from])
        && (g.modules[e.to].path == ["plan"] || g.modules[e.to].path == ["entry"])
}

/// Whether a cycle is one of the core's top level made of `REGISTRATION` modules only.
fn registration_modules(g: &Graph, c: &Cycle) -> bool {
    g.label == "fastbrdf"
        && g.modules[c.scope].path.is_empty()
        && c.nodes
            .iter()
            .all(|&n| REGISTRATION.contains(&g.modules[n].path[0].as_str()))
}

/// The edges of a cycle at the level of files: those between two files of the cycle's modules
/// that lie on a cycle of files (a file of a folder that the cycle only passes by, such as one
/// that `plan.rs` uses but that imports nothing of the cycle, is not on it). With `skip`, the
/// edges it names are left out first.
fn file_cycle_edges(g: &Graph, c: &Cycle, skip: &dyn Fn(&Edge) -> bool) -> Vec<Edge> {
    let inside = |f: usize| child_holding(g, c.scope, f).is_some_and(|n| c.nodes.contains(&n));
    let es: Vec<&Edge> = g
        .edges
        .iter()
        .filter(|e| inside(e.from) && inside(e.to) && !skip(e))
        .collect();
    let files: Vec<usize> = (0..g.modules.len()).filter(|&f| inside(f)).collect();
    let pairs: Vec<(usize, usize)> = es.iter().map(|e| (e.from, e.to)).collect();
    let on_cycle: Vec<BTreeSet<usize>> = sccs(&files, &pairs)
        .into_iter()
        .map(|s| s.into_iter().collect())
        .collect();
    es.into_iter()
        .filter(|e| {
            on_cycle
                .iter()
                .any(|s| s.contains(&e.from) && s.contains(&e.to))
        })
        .cloned()
        .collect()
}

/// Why a cycle of registration modules is more than the registration: the edges on a cycle of
/// files that touch a file that is not a registration file, and the cycles of files that are
/// left without the registration's own edges. Empty when it is the registration only.
fn registration_misfits(g: &Graph, c: &Cycle) -> String {
    let mut s = String::new();
    let foreign: Vec<Edge> = file_cycle_edges(g, c, &|_| false)
        .into_iter()
        .filter(|e| !(registration_file(&g.modules[e.from]) && registration_file(&g.modules[e.to])))
        .collect();
    if !foreign.is_empty() {
        s += "  edges on a cycle of files that touch a file that is neither plan.rs, entry.rs, a family file nor PULLED_IN:\n";
        foreign.iter().for_each(|e| s += &g.edge_line(e));
    }
    let left = file_cycle_edges(g, c, &|e| registration_edge(g, e));
    if !left.is_empty() {
        s += "  cycles of files left without the family files' imports of plan.rs and entry.rs:\n";
        left.iter().for_each(|e| s += &g.edge_line(e));
    }
    s
}

/// The registration cycle is allowed in the core only: at its top level, made of
/// `REGISTRATION` modules, every file on it a registration file, and no cycle left without the
/// registration's own edges (every circle goes through a family's `ENTRY` building a `Plan`).
fn registration_allows(g: &Graph, c: &Cycle) -> bool {
    registration_modules(g, c) && registration_misfits(g, c).is_empty()
}

/// The files of the allowed registration cycle (those on a cycle of files), for the summary.
fn registration_files(g: &Graph, c: &Cycle) -> Vec<String> {
    let set: BTreeSet<String> = file_cycle_edges(g, c, &|_| false)
        .iter()
        .flat_map(|e| [g.file(e.from), g.file(e.to)])
        .collect();
    set.into_iter().collect()
}

// ---------------------------------------------------------------- the tests

fn crate_graph(dir: &str) -> Graph {
    let base = repo_root().join(dir).join("src");
    let root = if base.join("lib.rs").is_file() {
        "lib.rs"
    } else {
        "main.rs"
    };
    let label = dir.rsplit('/').next().unwrap();
    let mut g = build(label, &base, root, &|p: &Path| {
        std::fs::read_to_string(p).ok()
    });
    g.prefix = format!("{dir}/src/");
    g
}

#[test]
fn no_import_cycles_but_the_registration() {
    let mut problems = Vec::new();
    let mut on_registration = BTreeSet::new();
    for dir in CRATES {
        let g = crate_graph(dir);
        let found = cycles(&g);
        println!(
            "{dir}: {} modules, {} import edges, {} cycle(s)",
            g.modules.len(),
            g.edges.len(),
            found.len()
        );
        for c in &found {
            let text = describe(&g, c);
            let registration = registration_modules(&g, c);
            if registration {
                on_registration.extend(registration_files(&g, c));
            }
            if registration_allows(&g, c) {
                let files = registration_files(&g, c).join(", ");
                println!("allowed (the registration), its files: {files}");
                for (file, why) in PULLED_IN {
                    println!("  pulled in: {file}: {why}");
                }
                println!("{text}");
            } else if registration {
                problems.push(format!("{dir}: {text}{}", registration_misfits(&g, c)));
            } else {
                problems.push(format!("{dir}: {text}"));
            }
        }
    }
    // An allowance that no longer applies is stale: the file left the cycle (or was renamed).
    for (file, _) in PULLED_IN {
        let file = format!("crates/fastbrdf/src/{file}");
        if !on_registration.contains(&file) {
            problems.push(format!(
                "PULLED_IN names {file}, which is not on the registration cycle: remove it"
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "import cycles (see tests/modules/main.rs for the rules):\n{}",
        problems.join("\n")
    );
}

/// The graph sees the registration's real imports, so a quiet graph is not an empty one.
#[test]
fn the_graph_reads_the_registration() {
    let g = crate_graph("crates/fastbrdf");
    let id = |p: &[&str]| {
        g.find(&p.iter().map(|s| s.to_string()).collect::<Vec<_>>())
            .unwrap_or_else(|| panic!("no module {p:?}"))
    };
    let has = |a: usize, b: usize| g.edges.iter().any(|e| e.from == a && e.to == b);
    let (registry, plan, flog) = (id(&["registry"]), id(&["plan"]), id(&["lobes", "flog"]));
    assert!(has(registry, flog), "registry lists flog's entries");
    assert!(has(flog, plan), "flog's ENTRY builds a Plan");
    assert!(has(plan, flog), "the plan's lobe list names Flog");
    // `crate::ModelSpec` is an edge to spec.rs (followed through lib.rs's `pub use`), not to
    // the crate root.
    let root = id(&[]);
    assert!(g.edges.iter().all(|e| e.to != root || e.from == root));
}

/// The reader on small made-up crates: what counts as an import and what does not.
#[test]
fn the_reader_finds_cycles_and_ignores_tests_and_comments() {
    fn graph(files: &[(&str, &str)]) -> Graph {
        let files: BTreeMap<PathBuf, String> = files
            .iter()
            .map(|(p, s)| (Path::new("/x").join(p), s.to_string()))
            .collect();
        build("k", Path::new("/x"), "lib.rs", &move |p: &Path| {
            files.get(p).cloned()
        })
    }
    let names = |g: &Graph| -> Vec<Vec<String>> {
        cycles(g)
            .iter()
            .map(|c| c.nodes.iter().map(|&n| g.name(n)).collect())
            .collect()
    };
    // Two siblings in a folder that import each other, one through a module alias.
    let g = graph(&[
        ("lib.rs", "mod cmd;\npub use cmd::Thing;\n"),
        ("cmd/mod.rs", "mod a;\nmod b;\npub struct Shared;\n"),
        (
            "cmd/a.rs",
            "use super::Shared;\nuse super::b;\nfn f() { b::g(); }\n",
        ),
        (
            "cmd/b.rs",
            "pub fn g() {}\nfn h() {\n    crate::cmd::a::f();\n}\n",
        ),
    ]);
    assert_eq!(names(&g), [["k::cmd::a", "k::cmd::b"]]);
    let text = describe(&g, &cycles(&g)[0]);
    assert!(text.contains("cmd/a.rs:3 `b::g`"), "{text}");
    assert!(text.contains("cmd/b.rs:3 `crate::cmd::a::f`"), "{text}");
    // Children using their folder's `mod.rs`, and a test module, comments and strings that
    // name a sibling: no cycle.
    let g = graph(&[
        ("lib.rs", "mod cmd;\n"),
        (
            "cmd/mod.rs",
            "mod a;\nmod b;\npub struct Shared;\nfn run() { a::f(); b::g(); }\n",
        ),
        (
            "cmd/a.rs",
            "use super::Shared;\npub fn f() { super::b::g(); }\n",
        ),
        (
            "cmd/b.rs",
            "use super::Shared; // crate::cmd::a::f\n/* use super::a; */\npub fn g() {\n    \
             let _ = \"crate::cmd::a::f\";\n}\n#[cfg(test)]\nmod tests {\n    use super::*;\n    \
             use crate::cmd::a::f;\n}\n",
        ),
    ]);
    assert!(names(&g).is_empty(), "{:?}", names(&g));
    // A folder and an outside module through files on both sides; `crate::Item` is followed
    // through the root's re-export to the file that defines it.
    let g = graph(&[
        ("lib.rs", "mod speed;\nmod plot;\npub use plot::Chart;\n"),
        ("speed/mod.rs", "mod report;\n"),
        ("speed/report.rs", "use crate::Chart;\npub fn row() {}\n"),
        (
            "plot.rs",
            "pub struct Chart;\nfn f() { crate::speed::report::row(); }\n",
        ),
    ]);
    assert_eq!(names(&g), [["k::plot", "k::speed"]]);
}
