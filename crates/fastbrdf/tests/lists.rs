//! Hand-kept lists that used to go stale silently (issue 28): each is held here to what it
//! lists, so forgetting a line fails a test.
//!
//! - `registry::REGISTRY`: every `ENTRY` constant a family file declares is registered (a
//!   family left out compiled and passed every other test), and every variant of the plan
//!   family lists (`LobePlan::VARIANTS`, ...) is built by some registry entry.
//! - The `//!` header of `src/brdf/cook_torrance.rs`: its lists of `d` and `g` choices (and
//!   of those with an anisotropic form) are the registry's.

use fastbrdf::plan::Plan;
use fastbrdf::{Kind, ModelSpec, registry};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// The names of the constants of type `Entry` that `src` declares (`pub const ENTRY_X: Entry
/// = ...`), with comments ignored.
fn entry_consts(src: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in src.lines() {
        let code = line.split("//").next().unwrap_or("");
        let Some(i) = code.find("const ") else {
            continue;
        };
        let rest = &code[i + "const ".len()..];
        let Some((name, ty)) = rest.split_once(':') else {
            continue;
        };
        let ty = ty.split('=').next().unwrap_or("").trim();
        if ty == "Entry" || ty.ends_with("::Entry") {
            out.push(name.trim().to_string());
        }
    }
    out
}

/// The `module::CONST` items of the `REGISTRY` array in `registry.rs` (for the message: the
/// count check below does not depend on this reading).
fn registry_lines(src: &str) -> Option<Vec<String>> {
    let start = src.find("pub static REGISTRY")?;
    let body = &src[start..];
    let body = &body[body.find("= &[")? + 4..];
    let body = &body[..body.find("];")?];
    Some(
        body.lines()
            .map(|l| {
                l.split("//")
                    .next()
                    .unwrap_or("")
                    .trim()
                    .trim_end_matches(',')
            })
            .filter(|l| !l.is_empty())
            .map(|l| {
                // The last two path segments: `module::ENTRY`.
                let parts: Vec<&str> = l.split("::").map(str::trim).collect();
                parts[parts.len().saturating_sub(2)..].join("::")
            })
            .collect(),
    )
}

/// Issue 28: a family's `ENTRY` left out of `REGISTRY` compiled and passed every test. Every
/// constant of type `Entry` declared under `src/` is counted against `REGISTRY`, and each is
/// named with its file's module, so the message says which line is missing.
#[test]
fn every_declared_entry_is_registered() {
    let mut declared = BTreeSet::new();
    for path in rust_files(&src_dir()) {
        let src = std::fs::read_to_string(&path).unwrap();
        let module = path.file_stem().unwrap().to_str().unwrap().to_string();
        for name in entry_consts(&src) {
            declared.insert(format!("{module}::{name}"));
        }
    }
    assert!(
        declared.len() > 40,
        "the scan found only {} Entry constants under src/: is the declaration form \
         `pub const ENTRY: Entry = ...` still used?",
        declared.len()
    );
    let registry_src = std::fs::read_to_string(src_dir().join("registry.rs")).unwrap();
    let listed: Option<BTreeSet<String>> =
        registry_lines(&registry_src).map(|l| l.into_iter().collect());
    let detail = match &listed {
        Some(listed) => format!(
            "declared but not in REGISTRY: {:?}; in REGISTRY but not declared: {:?}",
            declared.difference(listed).collect::<Vec<_>>(),
            listed.difference(&declared).collect::<Vec<_>>()
        ),
        None => "(REGISTRY's lines could not be read from registry.rs)".into(),
    };
    assert_eq!(
        declared.len(),
        registry::REGISTRY.len(),
        "src/ declares {} Entry constants, REGISTRY holds {}: add each family's ENTRY to \
         REGISTRY (src/registry.rs). {detail}",
        declared.len(),
        registry::REGISTRY.len()
    );
    if let Some(listed) = &listed {
        assert!(&declared == listed, "{detail}");
    }
    // One line per id: a line registered twice cannot stand in for a missing one.
    let ids: BTreeSet<&str> = registry::REGISTRY.iter().map(|e| e.info.id).collect();
    assert_eq!(
        ids.len(),
        registry::REGISTRY.len(),
        "REGISTRY repeats an id"
    );
}

/// The plans a registry entry builds: at its defaults, and with each value of each of its
/// choice parameters alone (values that need other choices are refused and skipped).
fn plans_of(e: &fastbrdf::entry::Entry) -> Vec<Plan> {
    let id = e.info.id;
    let mut out = vec![*ModelSpec::parse(id, &[]).unwrap().plan().unwrap()];
    for p in e.info.params {
        if let fastbrdf::params::ParamKind::Choice { options, .. } = p.kind {
            for v in options.names() {
                if let Ok(spec) = ModelSpec::parse(id, &[(p.name, v)])
                    && let Ok(plan) = spec.plan()
                {
                    out.push(*plan);
                }
            }
        }
    }
    out
}

/// Issue 28: every variant of the plan family lists (one line per family in `plan.rs`) is
/// built by some registry entry, so a family on a list but never registered fails here.
#[test]
fn every_family_variant_is_built_by_the_registry() {
    let mut built: BTreeMap<String, BTreeSet<&'static str>> = BTreeMap::new();
    for e in registry::all() {
        for plan in plans_of(e) {
            assert_eq!(plan.kind(), e.info.kind, "{}", e.info.id);
            built
                .entry(plan.kind().name().to_string())
                .or_default()
                .insert(plan.variant());
        }
    }
    let mut missing = Vec::new();
    for (kind, variants) in Plan::variants() {
        for v in variants {
            if !built.get(kind.name()).is_some_and(|b| b.contains(v)) {
                missing.push(format!("{} {v}", kind.name()));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "family list variants no registry entry builds (add an ENTRY and its REGISTRY \
         line): {missing:?}"
    );
}

/// The backquoted names in `text`, with the header's abbreviations expanded:
/// `smith-ggx(-correlated)` is `smith-ggx` and `smith-ggx-correlated`, and
/// `beckmann-power4/8/16` is `beckmann-power4`, `beckmann-power8` and `beckmann-power16`.
fn listed_ids(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, name) in text.split('`').enumerate() {
        if i % 2 == 0 {
            continue;
        }
        if let Some((base, opt)) = name.split_once("(") {
            out.push(base.to_string());
            out.push(format!("{base}{}", opt.trim_end_matches(')')));
        } else if name.contains('/') {
            let mut parts = name.split('/');
            let first = parts.next().unwrap();
            let stem = first.trim_end_matches(|c: char| c.is_ascii_digit());
            out.push(first.to_string());
            out.extend(parts.map(|p| format!("{stem}{p}")));
        } else {
            out.push(name.to_string());
        }
    }
    out
}

/// The cells of the header table row of parameter `name` in `src`'s `//!` lines.
fn header_row<'a>(src: &'a str, name: &str) -> Vec<&'a str> {
    let prefix = format!("//! | `{name}` |");
    let line = src
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no header row for `{name}` in cook_torrance.rs"));
    line.trim_start_matches("//!")
        .trim()
        .trim_matches('|')
        .split(" | ")
        .map(str::trim)
        .collect()
}

fn cook_torrance_src() -> String {
    std::fs::read_to_string(src_dir().join("brdf/cook_torrance.rs")).unwrap()
}

/// Registered ids of `kind` whose plan has an anisotropic form (`DistForm::ANISO`,
/// `ShadowForm::ANISO`).
fn aniso_ids(kind: Kind) -> Vec<&'static str> {
    registry::ids_of(kind)
        .into_iter()
        .filter(
            |id| match ModelSpec::parse(id, &[]).unwrap().plan().unwrap() {
                Plan::Distribution(d) => d.aniso(),
                Plan::Shadowing(g) => g.aniso(),
                _ => false,
            },
        )
        .collect()
}

/// Issue 28: the Cook-Torrance header's lists of `d` and `g` choices are the registry's
/// distributions and shadowing terms, in registry order.
#[test]
fn cook_torrance_header_lists_every_d_and_g() {
    let src = cook_torrance_src();
    let d = header_row(&src, "d");
    assert_eq!(
        listed_ids(d.last().unwrap()),
        registry::ids_of(Kind::Distribution),
        "the `d` row of cook_torrance.rs's header"
    );
    let g = header_row(&src, "g");
    let meaning = g.last().unwrap();
    let list = meaning.split_once(':').map_or(*meaning, |(_, list)| list);
    assert_eq!(
        listed_ids(list),
        registry::ids_of(Kind::Shadowing),
        "the `g` row of cook_torrance.rs's header"
    );
}

/// The header's `alpha_x`, `alpha_y` row names the D and G with an anisotropic form: the
/// families' `ANISO` constants.
#[test]
fn cook_torrance_header_lists_the_anisotropic_d_and_g() {
    let src = cook_torrance_src();
    let row = header_row(&src, "alpha_x`, `alpha_y");
    let meaning = row.last().unwrap();
    let (_, after_d) = meaning
        .split_once("only with `d` in ")
        .expect("the row names the allowed `d`");
    let (ds, after_g) = after_d
        .split_once("a Smith `g`")
        .expect("the row names the allowed `g`");
    let gs = &after_g[..after_g
        .find(") and")
        .expect("the `g` list ends with `) and`")];
    assert_eq!(
        listed_ids(ds),
        aniso_ids(Kind::Distribution),
        "the `alpha_x` row's `d` list"
    );
    assert_eq!(
        listed_ids(gs),
        aniso_ids(Kind::Shadowing),
        "the `alpha_x` row's `g` list"
    );
}

#[test]
fn the_header_abbreviations_expand() {
    assert_eq!(
        listed_ids("`a`, `b(-c)`, `p4/8/16`"),
        ["a", "b", "b-c", "p4", "p8", "p16"]
    );
}
