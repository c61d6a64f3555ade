//! Reading one source file: comments, strings and `#[cfg(test)]` modules blanked, then the
//! tokens, the `use` trees, the paths in code, the `mod` declarations and the items it defines.

use std::collections::{BTreeMap, BTreeSet};

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The source with comments, string and character literals blanked (newlines kept, so lines
/// and columns stay where they were).
fn strip(src: &str) -> Vec<char> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::with_capacity(c.len());
    let blank = |ch: char| if ch == '\n' { '\n' } else { ' ' };
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        let next = c.get(i + 1).copied();
        let after_ident = i > 0 && is_ident(c[i - 1]);
        if ch == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if ch == '/' && next == Some('*') {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.extend([' ', ' ']);
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.extend([' ', ' ']);
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(c[i]));
                    i += 1;
                }
            }
        } else if !after_ident && (ch == 'r' || (ch == 'b' && next == Some('r'))) && {
            let mut j = i + if ch == 'b' { 2 } else { 1 };
            while c.get(j) == Some(&'#') {
                j += 1;
            }
            c.get(j) == Some(&'"')
        } {
            // Raw string r#"..."#.
            let mut j = i + if ch == 'b' { 2 } else { 1 };
            let mut hashes = 0;
            while c[j] == '#' {
                hashes += 1;
                j += 1;
            }
            out.extend(std::iter::repeat_n(' ', j - i));
            out.push('"');
            j += 1;
            loop {
                if j >= c.len() {
                    break;
                }
                if c[j] == '"' && (1..=hashes).all(|h| c.get(j + h) == Some(&'#')) {
                    out.push('"');
                    out.extend(std::iter::repeat_n(' ', hashes));
                    j += 1 + hashes;
                    break;
                }
                out.push(blank(c[j]));
                j += 1;
            }
            i = j;
        } else if ch == '"' {
            out.push('"');
            i += 1;
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' && i + 1 < c.len() {
                    out.push(' ');
                    i += 1;
                }
                out.push(blank(c[i]));
                i += 1;
            }
            if i < c.len() {
                out.push('"');
                i += 1;
            }
        } else if ch == '\'' && next == Some('\\') {
            // An escaped character literal: '\n', '\'', '\u{..}'.
            out.push('\'');
            let mut j = i + 3;
            while j < c.len() && c[j] != '\'' {
                j += 1;
            }
            out.extend(std::iter::repeat_n(' ', j - i - 1));
            if j < c.len() {
                out.push('\'');
            }
            i = j + 1;
        } else if ch == '\'' && c.get(i + 2) == Some(&'\'') {
            out.extend(['\'', ' ', '\'']);
            i += 3;
        } else {
            out.push(ch);
            i += 1;
        }
    }
    out
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Punct(char),
}

fn tokens(code: &[char]) -> Vec<(Tok, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < code.len() {
        let ch = code[i];
        if ch.is_whitespace() {
            i += 1;
        } else if is_ident(ch) || (ch == '$' && code.get(i + 1).is_some_and(|&c| is_ident(c))) {
            let start = i;
            i += 1;
            while i < code.len() && is_ident(code[i]) {
                i += 1;
            }
            let word: String = code[start..i].iter().collect();
            out.push((Tok::Ident(word.trim_start_matches("r#").to_string()), start));
        } else if ch == ':' && code.get(i + 1) == Some(&':') {
            out.push((Tok::Sep, i));
            i += 2;
        } else {
            out.push((Tok::Punct(ch), i));
            i += 1;
        }
    }
    out
}

fn ident(t: Option<&(Tok, usize)>) -> Option<&str> {
    match t {
        Some((Tok::Ident(s), _)) => Some(s),
        _ => None,
    }
}

fn is_punct(t: Option<&(Tok, usize)>, p: char) -> bool {
    matches!(t, Some((Tok::Punct(q), _)) if *q == p)
}

/// The index of the token that closes the bracket opened at `open`.
fn closing(toks: &[(Tok, usize)], open: usize) -> usize {
    let (o, c) = match toks[open].0 {
        Tok::Punct('{') => ('{', '}'),
        Tok::Punct('[') => ('[', ']'),
        _ => ('(', ')'),
    };
    let mut depth = 0;
    for (k, t) in toks.iter().enumerate().skip(open) {
        if is_punct(Some(t), o) {
            depth += 1;
        } else if is_punct(Some(t), c) {
            depth -= 1;
            if depth == 0 {
                return k;
            }
        }
    }
    toks.len() - 1
}

/// Skips a visibility (`pub`, `pub(crate)`, ...) at `i`.
fn skip_vis(toks: &[(Tok, usize)], mut i: usize) -> usize {
    if ident(toks.get(i)) == Some("pub") {
        i += 1;
        if is_punct(toks.get(i), '(') {
            i = closing(toks, i) + 1;
        }
    }
    i
}

/// Blanks every `#[cfg(test)]` module of `code`; returns the names of those that are files.
fn drop_test_modules(code: &mut [char]) -> Vec<String> {
    let mut files = Vec::new();
    loop {
        let toks = tokens(code);
        let mut cut = None;
        for k in 0..toks.len() {
            let is_cfg_test = is_punct(toks.get(k), '#')
                && is_punct(toks.get(k + 1), '[')
                && ident(toks.get(k + 2)) == Some("cfg")
                && is_punct(toks.get(k + 3), '(')
                && ident(toks.get(k + 4)) == Some("test")
                && is_punct(toks.get(k + 5), ')')
                && is_punct(toks.get(k + 6), ']');
            if !is_cfg_test {
                continue;
            }
            let mut i = k + 7;
            while is_punct(toks.get(i), '#') && is_punct(toks.get(i + 1), '[') {
                i = closing(&toks, i + 1) + 1;
            }
            i = skip_vis(&toks, i);
            if ident(toks.get(i)) != Some("mod") {
                continue;
            }
            let Some(name) = ident(toks.get(i + 1)) else {
                continue;
            };
            let end = if is_punct(toks.get(i + 2), '{') {
                closing(&toks, i + 2)
            } else if is_punct(toks.get(i + 2), ';') {
                files.push(name.to_string());
                i + 2
            } else {
                continue;
            };
            cut = Some((toks[k].1, toks[end].1));
            break;
        }
        let Some((a, b)) = cut else {
            return files;
        };
        for ch in &mut code[a..=b] {
            if *ch != '\n' {
                *ch = ' ';
            }
        }
    }
}

/// One leaf of a `use` tree: `use a::b::{c, d as e, f::*}` has three.
#[derive(Clone, Debug)]
pub struct UseLeaf {
    pub segs: Vec<String>,
    /// The name it binds (`None` for `as _` and globs).
    pub alias: Option<String>,
    pub glob: bool,
    /// Character offset of its last segment (for the line).
    pub at: usize,
}

fn parse_use_tree(
    toks: &[(Tok, usize)],
    i: &mut usize,
    mut prefix: Vec<String>,
    out: &mut Vec<UseLeaf>,
) {
    if matches!(toks.get(*i), Some((Tok::Sep, _))) {
        *i += 1;
    }
    loop {
        let Some((t, at)) = toks.get(*i) else {
            return;
        };
        match t {
            Tok::Punct('{') => {
                *i += 1;
                while *i < toks.len() && !is_punct(toks.get(*i), '}') {
                    parse_use_tree(toks, i, prefix.clone(), out);
                    if is_punct(toks.get(*i), ',') {
                        *i += 1;
                    }
                }
                *i += 1;
                return;
            }
            Tok::Punct('*') => {
                *i += 1;
                out.push(UseLeaf {
                    segs: prefix,
                    alias: None,
                    glob: true,
                    at: *at,
                });
                return;
            }
            Tok::Ident(s) => {
                prefix.push(s.clone());
                *i += 1;
                if matches!(toks.get(*i), Some((Tok::Sep, _))) {
                    *i += 1;
                    continue;
                }
                if prefix.last().is_some_and(|l| l == "self") {
                    prefix.pop();
                }
                let mut alias = prefix.last().cloned();
                if ident(toks.get(*i)) == Some("as") {
                    alias = ident(toks.get(*i + 1)).map(String::from);
                    if is_punct(toks.get(*i + 1), '_') {
                        alias = None;
                    }
                    *i += 2;
                }
                out.push(UseLeaf {
                    segs: prefix,
                    alias,
                    glob: false,
                    at: *at,
                });
                return;
            }
            _ => {
                *i += 1;
                return;
            }
        }
    }
}

/// A path in code that may lead into the crate: its segments and where it starts.
#[derive(Debug)]
pub struct CodePath {
    pub segs: Vec<String>,
    pub at: usize,
}

pub struct Module {
    /// Path from the crate root (`["lobes", "flog"]`; empty for the root).
    pub path: Vec<String>,
    /// The file relative to the crate's `src/`.
    pub file: String,
    pub code: Vec<char>,
    line_starts: Vec<usize>,
    pub children: BTreeMap<String, usize>,
    pub uses: Vec<UseLeaf>,
    pub paths: Vec<CodePath>,
    /// Character ranges of the inline (non-test) `mod x { .. }` blocks.
    pub inline: Vec<(usize, usize)>,
    /// Whether the file is a folder's `mod.rs` (or the crate root): its children live beside it.
    pub is_dir_module: bool,
    pub defines: BTreeSet<String>,
}

impl Module {
    pub fn line(&self, at: usize) -> usize {
        self.line_starts.partition_point(|&s| s <= at)
    }
}

/// Reads one file: the module and the names of the child modules it declares (not the tests).
pub fn analyse(
    path: Vec<String>,
    file: String,
    src: &str,
    is_dir_module: bool,
) -> (Module, Vec<String>) {
    let mut code = strip(src);
    let test_files = drop_test_modules(&mut code);
    let toks = tokens(&code);
    let mut line_starts = vec![0];
    line_starts.extend(
        code.iter()
            .enumerate()
            .filter(|(_, c)| **c == '\n')
            .map(|(k, _)| k + 1),
    );
    let mut children_decl = Vec::new();
    let mut uses = Vec::new();
    let mut paths = Vec::new();
    let mut inline = Vec::new();
    let mut defines = BTreeSet::new();
    let mut in_use = vec![false; toks.len()];
    let mut k = 0;
    while k < toks.len() {
        let word = ident(toks.get(k));
        let prev_sep = k > 0 && matches!(toks[k - 1].0, Tok::Sep);
        if word == Some("use") && !prev_sep {
            let start = k;
            k += 1;
            parse_use_tree(&toks, &mut k, Vec::new(), &mut uses);
            while k < toks.len() && !is_punct(toks.get(k), ';') {
                k += 1;
            }
            in_use[start..k.min(toks.len())].fill(true);
            continue;
        }
        if word == Some("mod")
            && let Some(name) = ident(toks.get(k + 1))
        {
            if is_punct(toks.get(k + 2), ';') {
                if !test_files.iter().any(|t| t == name) {
                    children_decl.push(name.to_string());
                }
            } else if is_punct(toks.get(k + 2), '{') {
                inline.push((toks[k].1, toks[closing(&toks, k + 2)].1));
            }
        }
        if let Some(w) = word
            && matches!(
                w,
                "fn" | "struct" | "enum" | "trait" | "const" | "static" | "type" | "union" | "mod"
            )
            && let Some(name) = ident(toks.get(k + 1))
        {
            defines.insert(name.to_string());
        }
        if word == Some("macro_rules")
            && is_punct(toks.get(k + 1), '!')
            && let Some(name) = ident(toks.get(k + 2))
        {
            defines.insert(name.to_string());
        }
        k += 1;
    }
    // Paths in code: `a::b::c` not inside a `use` and not the tail of a longer path.
    let mut k = 0;
    while k < toks.len() {
        let starts = !in_use[k]
            && ident(toks.get(k)).is_some()
            && matches!(toks.get(k + 1), Some((Tok::Sep, _)))
            && !(k > 0 && matches!(toks[k - 1].0, Tok::Sep));
        if !starts {
            k += 1;
            continue;
        }
        let at = toks[k].1;
        let mut segs = vec![ident(toks.get(k)).unwrap().to_string()];
        k += 1;
        while matches!(toks.get(k), Some((Tok::Sep, _)))
            && let Some(s) = ident(toks.get(k + 1))
        {
            segs.push(s.to_string());
            k += 2;
        }
        paths.push(CodePath { segs, at });
    }
    let module = Module {
        path,
        file,
        code,
        line_starts,
        children: BTreeMap::new(),
        uses,
        paths,
        inline,
        is_dir_module,
        defines,
    };
    (module, children_decl)
}
