//! Markdown's fenced blocks: language, marks (`full`, `no-run`, `gpu`) and the comment that
//! gives a mark's reason; the README's length.

use super::*;
use std::path::Path;

#[derive(Debug, Clone)]
pub(crate) struct Block {
    pub(crate) page: PathBuf,
    /// 1-based line of the opening fence.
    pub(crate) line: usize,
    pub(crate) lang: String,
    pub(crate) attrs: Vec<String>,
    /// The HTML comment on the line before the fence, if any.
    pub(crate) comment: Option<String>,
    pub(crate) body: String,
}

impl Block {
    pub(crate) fn is(&self, attr: &str) -> bool {
        self.attrs.iter().any(|a| a == attr)
    }
    pub(crate) fn at(&self) -> String {
        format!("{}:{}", self.page.display(), self.line)
    }
}

pub(crate) fn blocks_of(page: &Path, text: &str) -> Vec<Block> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i];
        let fence_len = l.len() - l.trim_start_matches('`').len();
        if fence_len >= 3 && !l.starts_with("    ") {
            let fence = &l[..fence_len];
            let info = l[fence_len..].trim();
            let mut words = info.split([' ', ',']).filter(|w| !w.is_empty());
            let lang = words.next().unwrap_or("").to_string();
            let attrs = words.map(str::to_string).collect();
            let comment = lines[..i]
                .iter()
                .rev()
                .find(|l| !l.trim().is_empty())
                .map(|l| l.trim())
                .filter(|l| l.starts_with("<!--") && l.ends_with("-->"))
                .map(|l| l[4..l.len() - 3].trim().to_string());
            let start = i;
            let mut body = String::new();
            i += 1;
            while i < lines.len() && lines[i].trim_end() != fence {
                body.push_str(lines[i]);
                body.push('\n');
                i += 1;
            }
            assert!(
                i < lines.len(),
                "{}:{}: unclosed code block",
                page.display(),
                start + 1
            );
            out.push(Block {
                page: page.to_path_buf(),
                line: start + 1,
                lang,
                attrs,
                comment,
                body,
            });
        }
        i += 1;
    }
    out
}

pub(crate) fn all_blocks() -> Vec<Block> {
    let root = root();
    pages()
        .iter()
        .flat_map(|p| blocks_of(p, &std::fs::read_to_string(root.join(p)).unwrap()))
        .collect()
}

#[test]
fn every_block_has_a_known_language_and_its_marks_give_a_reason() {
    let mut bad = Vec::new();
    for b in all_blocks() {
        if !RUN.contains(&b.lang.as_str()) && !SHOWN.contains(&b.lang.as_str()) {
            bad.push(format!(
                "{}: a block needs a language (sh, console, python, text, ...), not {:?}",
                b.at(),
                b.lang
            ));
        }
        for a in &b.attrs {
            if !["full", "no-run", "gpu"].contains(&a.as_str()) {
                bad.push(format!(
                    "{}: unknown mark {a:?} (full, no-run, gpu)",
                    b.at()
                ));
                continue;
            }
            if !RUN.contains(&b.lang.as_str()) {
                bad.push(format!("{}: {a} on a block that is not run", b.at()));
            }
            if a == "gpu" {
                continue;
            }
            let reason = b
                .comment
                .as_deref()
                .and_then(|c| c.strip_prefix(&format!("{a}:")));
            if reason.is_none_or(|r| r.trim().len() < 10) {
                bad.push(format!(
                    "{}: a block marked {a} needs `<!-- {a}: the reason -->` on the line before",
                    b.at()
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_readme_is_a_front_door() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let n = readme.lines().count();
    assert!(
        n <= 400,
        "README.md has {n} lines: at most 400; move the detail into the book (docs/book/src)"
    );
}
