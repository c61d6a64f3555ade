//! Relative links name files in the repository; SUMMARY.md lists every chapter.

use super::*;

/// The link targets of a Markdown text: `[..](target)`, `![..](target)`, `[..]: target` and
/// `src="target"`, outside code blocks and code spans.
pub(crate) fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_code = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        // Code spans hold no links.
        let mut plain = String::new();
        for (k, part) in line.split('`').enumerate() {
            if k % 2 == 0 {
                plain.push_str(part);
            }
        }
        let mut rest = plain.as_str();
        while let Some(k) = rest.find("](") {
            let after = &rest[k + 2..];
            let end = after.find(')').unwrap_or(after.len());
            out.push((n + 1, after[..end].to_string()));
            rest = &after[end..];
        }
        let t = plain.trim_start();
        if t.starts_with('[')
            && let Some(k) = t.find("]: ")
        {
            out.push((n + 1, t[k + 3..].trim().to_string()));
        }
        let mut rest = plain.as_str();
        while let Some(k) = rest.find("src=\"") {
            let after = &rest[k + 5..];
            let end = after.find('"').unwrap_or(after.len());
            out.push((n + 1, after[..end].to_string()));
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_names_a_file() {
    let root = root();
    let mut bad = Vec::new();
    let mut count = 0;
    for p in pages() {
        let text = std::fs::read_to_string(root.join(&p)).unwrap();
        for (line, target) in link_targets(&text) {
            let target = target.split_whitespace().next().unwrap_or("");
            if target.is_empty()
                || target.starts_with('#')
                || target.contains("://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            count += 1;
            let file = target.split('#').next().unwrap();
            let resolved = root.join(p.parent().unwrap()).join(file);
            if !resolved.exists() {
                bad.push(format!("{}:{line}: {target} does not exist", p.display()));
            } else if !std::fs::canonicalize(&resolved).unwrap().starts_with(&root) {
                bad.push(format!(
                    "{}:{line}: {target} leaves the repository",
                    p.display()
                ));
            }
        }
    }
    assert!(
        count >= 20,
        "only {count} relative links found: the scan is broken"
    );
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_summary_lists_every_chapter() {
    let root = root();
    let summary = std::fs::read_to_string(root.join(BOOK).join("SUMMARY.md")).unwrap();
    let listed: Vec<String> = link_targets(&summary).into_iter().map(|t| t.1).collect();
    for p in pages() {
        let Ok(rel) = p.strip_prefix(BOOK) else {
            continue;
        };
        let rel = rel.to_string_lossy();
        if rel != "SUMMARY.md" {
            assert!(
                listed.iter().any(|l| *l == rel),
                "docs/book/src/SUMMARY.md does not list {rel}"
            );
        }
    }
    let toml = std::fs::read_to_string(root.join("docs/book/book.toml")).unwrap();
    assert!(toml.contains("[book]"), "book.toml");
}
