//! Repository paths named in the documentation exist (issue 28: files split into folders left
//! their old names in the prose).
//!
//! The rule. A code span (`` `...` ``, outside fenced blocks) of README.md, ARCHITECTURE.md or
//! the book is a path when it has no spaces and either contains a `/` and ends in `.rs`, `.md`,
//! `.wgsl`, `.py`, `.sh`, `.toml` or `/`, or starts with `crates/`, `src/`, `tests/`, `docs/`,
//! `python/` or `tools/`. One `{a,b}` is expanded; spans with `*`, `<`, `$`, `...`, `::` or
//! `://` are patterns, items or addresses and are skipped; a `#anchor` or `:line` suffix is
//! dropped. A path names something when it exists:
//! - from the repository root (`crates/gpu/src/render/`);
//! - else, for `src/...`, `tests/...`, `benches/...`, `examples/...`, from a crate's root
//!   (`crates/*/` or `python/`): the core's `src/plan.rs`;
//! - else as the end of an existing path (a module named from its parent folder, as the prose
//!   does: `view/api/query.rs`, `batch/cook_torrance.rs`).
//!
//! `ILLUSTRATIVE` lists the spans that name on purpose what is not in the repository (an
//! example file a reader would create, a folder a command writes: a folder covers every path
//! under it), each with its reason.

use super::*;
use std::path::Path;

/// Spans that are not meant to exist in the repository, and why.
const ILLUSTRATIVE: &[(&str, &str)] = &[
    (
        "fastbrdf-out/",
        "the folder `fastbrdf demo` writes its pictures into",
    ),
    (
        "docs/book/book/",
        "the folder `mdbook build docs/book` writes",
    ),
    (
        "target/",
        "cargo's build folder and what the tests write under it (`target/docs-run/`): absent \
         from a fresh clone until something is built, so any path under it",
    ),
];

const EXTS: &[&str] = &[".rs", ".md", ".wgsl", ".py", ".sh", ".toml"];
const PREFIXES: &[&str] = &["crates/", "src/", "tests/", "docs/", "python/", "tools/"];
const CRATE_RELATIVE: &[&str] = &["src/", "tests/", "benches/", "examples/"];

/// The pages whose paths are checked: README.md, ARCHITECTURE.md and the book.
fn path_pages() -> Vec<PathBuf> {
    let mut v = pages();
    v.insert(1, PathBuf::from("ARCHITECTURE.md"));
    v
}

/// The code spans of a Markdown text outside fenced blocks, with their 1-based lines. A span
/// opens with a run of backticks and closes at the next run of the same length (so spans may
/// wrap lines).
pub(crate) fn code_spans(text: &str) -> Vec<(usize, String)> {
    // Fenced blocks become empty lines (line numbers kept).
    let mut plain = String::new();
    let mut fence: Option<String> = None;
    for l in text.lines() {
        let t = l.trim_start();
        let run = t.len() - t.trim_start_matches('`').len();
        match &fence {
            Some(f) if t.trim_end() == f => fence = None,
            Some(_) => {}
            None if run >= 3 => fence = Some(t[..run].to_string()),
            None => plain.push_str(l),
        }
        plain.push('\n');
    }
    let b = plain.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] != b'`' {
            i += 1;
            continue;
        }
        let n = b[i..].iter().take_while(|&&c| c == b'`').count();
        let start = i + n;
        let mut j = start;
        let mut close = None;
        while j < b.len() {
            if b[j] == b'`' {
                let m = b[j..].iter().take_while(|&&c| c == b'`').count();
                if m == n {
                    close = Some(j);
                    break;
                }
                j += m;
            } else {
                j += 1;
            }
        }
        let Some(end) = close else {
            i = start;
            continue;
        };
        let line = 1 + plain[..start].matches('\n').count();
        out.push((line, plain[start..end].trim().to_string()));
        i = end + n;
    }
    out
}

/// The paths a span names under the rule above (none when it is not a path).
pub(crate) fn span_paths(span: &str) -> Vec<String> {
    if span.is_empty()
        || span.contains(char::is_whitespace)
        || ["*", "<", "$", "...", "://", "::"]
            .iter()
            .any(|p| span.contains(p))
    {
        return Vec::new();
    }
    let span = span.split('#').next().unwrap();
    let span = match span.rsplit_once(':') {
        Some((p, n)) if n.chars().all(|c| c.is_ascii_digit()) => p,
        _ => span,
    };
    let looks = (span.contains('/')
        && (EXTS.iter().any(|e| span.ends_with(e)) || span.ends_with('/')))
        || PREFIXES.iter().any(|p| span.starts_with(p));
    if !looks {
        return Vec::new();
    }
    // One brace group: `view/{state,request}.rs`.
    if let (Some(a), Some(b)) = (span.find('{'), span.find('}'))
        && a < b
    {
        return span[a + 1..b]
            .split(',')
            .map(|x| format!("{}{x}{}", &span[..a], &span[b + 1..]))
            .collect();
    }
    vec![span.to_string()]
}

/// Every file and folder of the repository (relative, `/`-separated, folders ending in `/`),
/// without hidden folders and build outputs.
fn repository_paths(root: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy();
            if name.starts_with('.') || name == "target" || name == "node_modules" {
                continue;
            }
            let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
            if p.is_dir() {
                out.push(format!("{rel}/"));
                walk(root, &p, out);
            } else {
                out.push(rel);
            }
        }
    }
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out
}

/// Does `path` name something, under the rule above?
fn resolves(root: &Path, all: &[String], path: &str) -> bool {
    if root.join(path).exists() {
        return true;
    }
    if CRATE_RELATIVE.iter().any(|p| path.starts_with(p)) {
        let crates = std::fs::read_dir(root.join("crates"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .chain([root.join("python")]);
        return crates.into_iter().any(|c| c.join(path).exists());
    }
    let file = path.trim_end_matches('/');
    let want = if path.ends_with('/') {
        format!("/{file}/")
    } else {
        format!("/{file}")
    };
    all.iter().any(|p| p.ends_with(&want))
}

fn stale_paths(root: &Path) -> (usize, Vec<String>) {
    let all = repository_paths(root);
    let mut count = 0;
    let mut bad = Vec::new();
    for page in path_pages() {
        let text = std::fs::read_to_string(root.join(&page)).unwrap();
        for (line, span) in code_spans(&text) {
            for path in span_paths(&span) {
                if ILLUSTRATIVE
                    .iter()
                    .any(|(p, _)| *p == path || (p.ends_with('/') && path.starts_with(p)))
                {
                    continue;
                }
                count += 1;
                if !resolves(root, &all, &path) {
                    bad.push(format!(
                        "{}:{line}: `{path}` names no file or folder",
                        page.display()
                    ));
                }
            }
        }
    }
    (count, bad)
}

#[test]
fn every_path_in_the_documentation_exists() {
    let (count, bad) = stale_paths(&root());
    assert!(count >= 100, "only {count} paths found: the scan is broken");
    assert!(
        bad.is_empty(),
        "{} stale path(s) (the rule: crates/cli/tests/docs_support/paths.rs):\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn the_path_rule_finds_paths_and_fails_on_a_stale_one() {
    let text = "See `crates/fastbrdf/src/plan.rs`, `src/spec.rs` and `view/api/query.rs`;\n\
                not `fastbrdf models`, `a/b`, `crates/*/tests/` or `x.rs`.\n\
                ```text\n`crates/none.rs`\n```\n`view/{state,request}.rs` and ``a `b` c``";
    let spans: Vec<String> = code_spans(text)
        .into_iter()
        .flat_map(|(_, s)| span_paths(&s))
        .collect();
    assert_eq!(
        spans,
        [
            "crates/fastbrdf/src/plan.rs",
            "src/spec.rs",
            "view/api/query.rs",
            "view/state.rs",
            "view/request.rs"
        ]
    );
    assert_eq!(code_spans(text).last().unwrap().0, 6, "a span's line");
    let root = root();
    let all = repository_paths(&root);
    for ok in [
        "crates/fastbrdf/src/plan.rs",
        "src/spec.rs",
        "tests/kernels.rs",
        "crates/cli/src/commands/",
        "view/api/query.rs",
    ] {
        assert!(resolves(&root, &all, ok), "{ok}");
    }
    for stale in [
        "crates/gpu/src/render.rs",
        "tests/reference.rs",
        "src/accuracy.rs",
        "view/api.rs",
        "commands/nowhere/",
    ] {
        assert!(!resolves(&root, &all, stale), "{stale}");
    }
}
