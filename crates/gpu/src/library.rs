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

/// Every item of the library, in the order of `fastbrdf::plan::library_sources`.
pub fn items() -> &'static [Item] {
    static ITEMS: OnceLock<Vec<Item>> = OnceLock::new();
    ITEMS.get_or_init(|| {
        fastbrdf::plan::library_sources()
            .iter()
            .flat_map(|(_, src)| parse(src))
            .collect()
    })
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

/// The names of the library items `code` needs, directly or through other items.
pub fn closure(code: &str) -> BTreeSet<String> {
    let all = items();
    let mut need: BTreeSet<String> = BTreeSet::new();
    let mut todo: Vec<String> = all
        .iter()
        .filter(|i| mentions(code, &i.name))
        .map(|i| i.name.clone())
        .collect();
    while let Some(n) = todo.pop() {
        if !need.insert(n.clone()) {
            continue;
        }
        let item = all.iter().find(|i| i.name == n).expect("known item");
        for other in all {
            if other.name != n && !need.contains(&other.name) && mentions(&item.code, &other.name) {
                todo.push(other.name.clone());
            }
        }
    }
    need
}

/// The library items `code` needs, in library order, as one source.
pub fn closure_source(code: &str) -> String {
    let need = closure(code);
    items()
        .iter()
        .filter(|i| need.contains(&i.name))
        .map(|i| i.text.as_str())
        .collect::<Vec<_>>()
        .join("\n")
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
