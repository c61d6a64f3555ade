//! The WGSL library as items, so that a shader can take just the items it needs: a module for
//! one model, or an exported function, carries no dead code. The sources live in the core crate,
//! each family's `.wgsl` file beside its Rust file, and come from
//! `fastbrdf::plan::library_sources` (collected from the family lists of `fastbrdf::plan`, in
//! dependency order): this crate keeps no list of WGSL files.
//!
//! An item is a run of `///` doc lines followed by a `const`, `struct` or `fn` declaration
//! (ending at its `;`, or at a line that is exactly `}`). Items depend on the items whose names
//! appear as whole words in their code (comments excluded). Written by hand, not with naga,
//! because naga's IR drops the comments that must travel with exported code.
//!
//! The sources generated from tables (`fastbrdf::plan::GeneratedSource`: Kulla-Conty's,
//! sheen's and the split-sum tables, the last 0.5 s of quadrature) are generated only when a
//! shader needs one of their items, known by name beforehand: a GPU render's set-up no longer
//! computes tables its model never reads.

use fastbrdf::plan::{LibraryPart, library_parts};
use std::collections::BTreeSet;
use std::sync::OnceLock;

/// One library item.
#[derive(Clone, Debug)]
pub struct Item {
    pub name: String,
    /// The item's text, its doc comment included.
    pub text: String,
    /// The code only (no comment lines), for dependency scanning.
    code: String,
}

/// One part of the library (a file, or a generated source) and its items, parsed on first use.
struct Part {
    part: LibraryPart,
    /// The names of its items, in order (a generated source's known without generating it).
    names: Vec<String>,
    items: OnceLock<Vec<Item>>,
}

impl Part {
    fn items(&self) -> &[Item] {
        self.items.get_or_init(|| match self.part {
            LibraryPart::Text(_, src) => parse(src),
            LibraryPart::Generated(g) => {
                let items = parse((g.source)());
                let names: Vec<&str> = items.iter().map(|i| i.name.as_str()).collect();
                assert_eq!(
                    names, g.items,
                    "{} defines other items than it says",
                    g.file
                );
                items
            }
        })
    }
}

/// The library's parts in order; the files parsed at once (cheap), the generated ones not.
fn parts() -> &'static [Part] {
    static PARTS: OnceLock<Vec<Part>> = OnceLock::new();
    PARTS.get_or_init(new_parts)
}

fn new_parts() -> Vec<Part> {
    library_parts()
        .into_iter()
        .map(|part| {
            let items = OnceLock::new();
            let names = match part {
                LibraryPart::Text(_, src) => {
                    let parsed = parse(src);
                    let names = parsed.iter().map(|i| i.name.clone()).collect();
                    let _ = items.set(parsed);
                    names
                }
                LibraryPart::Generated(g) => g.items.iter().map(|n| n.to_string()).collect(),
            };
            Part { part, names, items }
        })
        .collect()
}

/// Whether the library has an item of this name (nothing is generated to say so).
pub fn defines(name: &str) -> bool {
    parts().iter().any(|p| p.names.iter().any(|n| n == name))
}

/// The item of this name in `parts`, generating its source if it is a generated one.
fn item<'a>(parts: &'a [Part], name: &str) -> Option<&'a Item> {
    let p = parts.iter().find(|p| p.names.iter().any(|n| n == name))?;
    p.items().iter().find(|i| i.name == name)
}

/// Every item of the library, in the order of `fastbrdf::plan::library_sources` (generating
/// every generated source: for the whole library, not for one shader).
pub fn items() -> &'static [Item] {
    static ITEMS: OnceLock<Vec<Item>> = OnceLock::new();
    ITEMS.get_or_init(|| parts().iter().flat_map(|p| p.items().to_vec()).collect())
}

/// The whole library as one WGSL source.
pub fn source() -> String {
    items()
        .iter()
        .map(|i| i.text.as_str())
        .collect::<Vec<_>>()
        .join("\n")
}

fn parse(src: &str) -> Vec<Item> {
    let mut out = Vec::new();
    let mut doc: Vec<&str> = Vec::new();
    let mut lines = src.lines();
    while let Some(line) = lines.next() {
        if line.starts_with("///") {
            doc.push(line);
            continue;
        }
        let decl = ["const ", "struct ", "fn "]
            .iter()
            .find(|k| line.starts_with(**k))
            .copied();
        let Some(kw) = decl else {
            doc.clear();
            continue;
        };
        let rest = &line[kw.len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let mut body = vec![line];
        if !(kw == "const " && line.trim_end().ends_with(';')) {
            for l in lines.by_ref() {
                body.push(l);
                if l == "}" || (kw == "const " && l.trim_end().ends_with(';')) {
                    break;
                }
            }
        }
        let code = body
            .iter()
            .filter(|l| !l.trim_start().starts_with("//"))
            .copied()
            .collect::<Vec<_>>()
            .join("\n");
        let mut text = doc.join("\n");
        if !text.is_empty() {
            text.push('\n');
        }
        text.push_str(&body.join("\n"));
        text.push('\n');
        out.push(Item { name, text, code });
        doc.clear();
    }
    out
}

/// Whether `word` occurs in `text` as a whole identifier.
fn mentions(text: &str, word: &str) -> bool {
    let is_id = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(word).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        !before.is_some_and(is_id) && !after.is_some_and(is_id)
    })
}

/// The names of the library items `code` needs, directly or through other items (generating
/// only the generated sources among them).
pub fn closure(code: &str) -> BTreeSet<String> {
    closure_in(parts(), code)
}

fn closure_in(parts: &[Part], code: &str) -> BTreeSet<String> {
    let names: Vec<&str> = parts
        .iter()
        .flat_map(|p| p.names.iter().map(String::as_str))
        .collect();
    let mut need: BTreeSet<String> = BTreeSet::new();
    let mut todo: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| mentions(code, n))
        .collect();
    while let Some(n) = todo.pop() {
        if !need.insert(n.to_string()) {
            continue;
        }
        let item = item(parts, n).expect("known item");
        for &other in &names {
            if other != n && !need.contains(other) && mentions(&item.code, other) {
                todo.push(other);
            }
        }
    }
    need
}

/// The texts of the items named in `need`, in library order (generating only the generated
/// sources among them).
pub fn texts_of(need: &BTreeSet<String>) -> Vec<&'static str> {
    parts()
        .iter()
        .filter(|p| p.names.iter().any(|n| need.contains(n)))
        .flat_map(|p| p.items())
        .filter(|i| need.contains(&i.name))
        .map(|i| i.text.as_str())
        .collect()
}

/// The library items `code` needs, in library order, as one source.
pub fn closure_source(code: &str) -> String {
    texts_of(&closure(code)).join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_are_found_with_their_docs() {
        let names: Vec<&str> = items().iter().map(|i| i.name.as_str()).collect();
        for n in [
            "FB_COS_MIN",
            "FbPair",
            "fb_pair",
            "fb_lobe_pow",
            "fb_f_conductor",
        ] {
            assert!(names.contains(&n), "{n} missing from {names:?}");
        }
        let pair = items().iter().find(|i| i.name == "fb_pair").unwrap();
        assert!(pair.text.starts_with("/// Normalises"));
        assert!(pair.text.trim_end().ends_with('}'));
    }

    #[test]
    fn generated_sources_define_what_they_say() {
        // `Part::items` asserts it for each part it generates.
        let mut generated = 0;
        for p in new_parts() {
            p.items();
            generated += usize::from(matches!(p.part, LibraryPart::Generated(_)));
        }
        // Kulla-Conty's, sheen's and the four split-sum tables.
        assert_eq!(generated, 6);
    }

    /// A shader's closure generates the generated sources it needs and no other: GGX alone
    /// none; Kulla-Conty's energy compensation its table; the 32 x 32 split-sum table that one
    /// table. The same items, in the same order, as from the whole library.
    #[test]
    fn only_the_needed_tables_are_generated() {
        let generated = |parts: &[Part]| -> Vec<&'static str> {
            parts
                .iter()
                .filter_map(|p| match p.part {
                    LibraryPart::Generated(g) if p.items.get().is_some() => Some(g.file),
                    _ => None,
                })
                .collect()
        };
        for (id, given, want) in [
            ("cook-torrance", vec![("d", "ggx")], vec![]),
            (
                "cook-torrance",
                vec![
                    ("d", "ggx"),
                    ("g", "smith-ggx-correlated"),
                    ("ms", "kulla-conty"),
                ],
                vec!["microfacet/ms.wgsl"],
            ),
            (
                "env-brdf-table",
                vec![("size", "32")],
                vec!["microfacet/env_table_data.wgsl (32)"],
            ),
        ] {
            let spec = fastbrdf::ModelSpec::parse(id, &given).unwrap();
            let wrapper = crate::spec::Instance::new(&spec).unwrap().wrapper;
            let parts = new_parts();
            let need = closure_in(&parts, &wrapper);
            assert_eq!(generated(&parts), want, "{id} {given:?}");
            // The whole library's closure: the same items.
            let all: BTreeSet<String> = items()
                .iter()
                .filter(|i| need.contains(&i.name))
                .map(|i| i.name.clone())
                .collect();
            assert_eq!(all, need);
            assert_eq!(
                texts_of(&need),
                items()
                    .iter()
                    .filter(|i| need.contains(&i.name))
                    .map(|i| i.text.as_str())
                    .collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn every_item_is_defined_once() {
        // `closure` finds items by name: a second definition (two families' files) would be
        // dropped silently from every shader that needs the first.
        let mut seen: std::collections::BTreeMap<String, &str> = Default::default();
        for (file, src) in fastbrdf::plan::library_sources() {
            for item in parse(src) {
                if let Some(first) = seen.insert(item.name.clone(), file) {
                    panic!("{} is defined in {first} and in {file}", item.name);
                }
            }
        }
        assert_eq!(seen.len(), items().len());
    }

    #[test]
    fn closure_follows_calls_not_comments() {
        let c = closure(
            "fn f(wi: vec3<f32>, wo: vec3<f32>) -> f32 { return fb_brdf_ward_power16(wi, wo, 1.0, 1.0); }",
        );
        for n in [
            "fb_brdf_ward_power16",
            "fb_pair",
            "FbPair",
            "FB_COS_MIN",
            "fb_pow16",
            "fb_pow8",
            "fb_pow4",
        ] {
            assert!(c.contains(n), "{n} not in {c:?}");
        }
        assert!(!c.contains("fb_lobe_pow"));
        assert!(!mentions("fb_lobe_power4", "fb_lobe_pow"));
    }
}
