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

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

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

// ---------------------------------------------------------------- text

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

// ---------------------------------------------------------------- files and modules

/// One leaf of a `use` tree: `use a::b::{c, d as e, f::*}` has three.
#[derive(Clone, Debug)]
struct UseLeaf {
    segs: Vec<String>,
    /// The name it binds (`None` for `as _` and globs).
    alias: Option<String>,
    glob: bool,
    /// Character offset of its last segment (for the line).
    at: usize,
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
struct CodePath {
    segs: Vec<String>,
    at: usize,
}

struct Module {
    /// Path from the crate root (`["lobes", "flog"]`; empty for the root).
    path: Vec<String>,
    /// Repository-relative file, for messages.
    file: String,
    code: Vec<char>,
    line_starts: Vec<usize>,
    children: BTreeMap<String, usize>,
    uses: Vec<UseLeaf>,
    paths: Vec<CodePath>,
    /// Character ranges of the inline (non-test) `mod x { .. }` blocks.
    inline: Vec<(usize, usize)>,
    /// Whether the file is a folder's `mod.rs` (or the crate root): its children live beside it.
    is_dir_module: bool,
    defines: BTreeSet<String>,
}

impl Module {
    fn line(&self, at: usize) -> usize {
        self.line_starts.partition_point(|&s| s <= at)
    }
}

fn analyse(
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

struct Graph {
    label: String,
    /// The crate's `src/` folder relative to the repository, for messages.
    prefix: String,
    modules: Vec<Module>,
    /// (from, to, file:line and the path) for every import between two different modules.
    edges: Vec<Edge>,
}

#[derive(Clone, Debug)]
struct Edge {
    from: usize,
    to: usize,
    line: usize,
    what: String,
}

/// Reads the crate whose root file is `root_file` (relative to `base`) with `read`.
fn build(
    label: &str,
    base: &Path,
    root_file: &str,
    read: &dyn Fn(&Path) -> Option<String>,
) -> Graph {
    let mut modules: Vec<Module> = Vec::new();
    // (path, file) still to read.
    let mut todo = vec![(
        Vec::<String>::new(),
        PathBuf::from(root_file),
        None::<usize>,
    )];
    while let Some((path, file, parent)) = todo.pop() {
        let src = read(&base.join(&file))
            .unwrap_or_else(|| panic!("{label}: cannot read {}", base.join(&file).display()));
        let is_dir_module = path.is_empty() || file.file_name().is_some_and(|f| f == "mod.rs");
        let (module, children) = analyse(
            path.clone(),
            file.display().to_string(),
            &src,
            is_dir_module,
        );
        let me = modules.len();
        modules.push(module);
        if let Some(p) = parent {
            modules[p].children.insert(path.last().unwrap().clone(), me);
        }
        let dir = if is_dir_module {
            file.parent().unwrap().to_path_buf()
        } else {
            file.with_extension("")
        };
        for c in children {
            let flat = dir.join(format!("{c}.rs"));
            let folder = dir.join(&c).join("mod.rs");
            let child_file = if read(&base.join(&flat)).is_some() {
                flat
            } else {
                folder
            };
            let mut p = path.clone();
            p.push(c);
            todo.push((p, child_file, Some(me)));
        }
    }
    let mut g = Graph {
        label: label.to_string(),
        prefix: String::new(),
        modules,
        edges: Vec::new(),
    };
    g.edges = edges(&g);
    g
}

impl Graph {
    /// The file of module `m`, relative to the repository.
    fn file(&self, m: usize) -> String {
        format!("{}{}", self.prefix, self.modules[m].file)
    }

    fn name(&self, m: usize) -> String {
        std::iter::once(self.label.as_str())
            .chain(self.modules[m].path.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join("::")
    }

    fn find(&self, path: &[String]) -> Option<usize> {
        self.modules.iter().position(|m| m.path == path)
    }

    /// Walks `segs` (absolute) down the module tree: the module reached and the first segment
    /// that is not a module (an item of it), if any.
    fn walk(&self, segs: &[String]) -> (usize, Option<String>) {
        let mut m = self.find(&[]).unwrap();
        for s in segs {
            match self.modules[m].children.get(s) {
                Some(&c) => m = c,
                None => return (m, Some(s.clone())),
            }
        }
        (m, None)
    }

    /// The absolute path of `segs` as written in module `m` at offset `at`, if it leads into
    /// the crate.
    fn absolute(&self, m: usize, segs: &[String], at: usize, depth: usize) -> Option<Vec<String>> {
        let module = &self.modules[m];
        let first = segs.first()?;
        let mut base = module.path.clone();
        let rest;
        match first.as_str() {
            "crate" | "$crate" => {
                base.clear();
                rest = &segs[1..];
            }
            "self" => rest = &segs[1..],
            "super" => {
                // The inline modules around `at` come first.
                let mut inline = module
                    .inline
                    .iter()
                    .filter(|(a, b)| *a < at && at < *b)
                    .count();
                let mut k = 0;
                while segs.get(k).is_some_and(|s| s == "super") {
                    if inline > 0 {
                        inline -= 1;
                    } else {
                        base.pop();
                    }
                    k += 1;
                }
                rest = &segs[k..];
            }
            name => {
                if module.children.contains_key(name) {
                    rest = segs;
                } else if depth < 8
                    && let Some(target) = self.module_alias(m, name, depth + 1)
                {
                    base = self.modules[target].path.clone();
                    rest = &segs[1..];
                } else {
                    return None;
                }
            }
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// The module that a `use` in `m` binds to `name`, if any (`use super::render;`, or a
    /// child of a module glob-imported with `use super::*`).
    fn module_alias(&self, m: usize, name: &str, depth: usize) -> Option<usize> {
        let module = &self.modules[m];
        for u in module
            .uses
            .iter()
            .filter(|u| !u.glob && u.alias.as_deref() == Some(name))
        {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth)
                && let (t, None) = self.walk(&abs)
            {
                return Some(t);
            }
        }
        for u in module.uses.iter().filter(|u| u.glob) {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth)
                && let (t, None) = self.walk(&abs)
                && let Some(&c) = self.modules[t].children.get(name)
            {
                return Some(c);
            }
        }
        None
    }

    /// The module that defines item `name` seen in module `m`, following its `use`s.
    fn owner(&self, m: usize, name: &str, depth: usize) -> Option<usize> {
        if depth > 8 {
            return None;
        }
        let module = &self.modules[m];
        for u in module
            .uses
            .iter()
            .filter(|u| !u.glob && u.alias.as_deref() == Some(name))
        {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth + 1) {
                return Some(match self.walk(&abs) {
                    (t, None) => t,
                    (t, Some(item)) => self.owner(t, &item, depth + 1).unwrap_or(t),
                });
            }
        }
        if module.defines.contains(name) {
            return Some(m);
        }
        for u in module.uses.iter().filter(|u| u.glob) {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth + 1)
                && let (t, None) = self.walk(&abs)
                && let Some(o) = self.owner(t, name, depth + 1)
            {
                return Some(o);
            }
        }
        None
    }

    /// The module a path written in `m` imports from.
    fn target(&self, m: usize, segs: &[String], at: usize) -> Option<(usize, bool)> {
        let abs = self.absolute(m, segs, at, 0)?;
        Some(match self.walk(&abs) {
            (t, None) => (t, true),
            (t, Some(item)) => (self.owner(t, &item, 0).unwrap_or(t), false),
        })
    }
}

fn edges(g: &Graph) -> Vec<Edge> {
    let mut out = Vec::new();
    let mut seen = BTreeSet::new();
    for (m, module) in g.modules.iter().enumerate() {
        let mut add = |to: usize, at: usize, what: String| {
            let line = module.line(at);
            if to != m && seen.insert((m, to, line)) {
                out.push(Edge {
                    from: m,
                    to,
                    line,
                    what,
                });
            }
        };
        for u in &module.uses {
            match g.target(m, &u.segs, u.at) {
                // `use a::b;` naming a module binds a name; its uses are the edges. A glob
                // import takes the module's items.
                Some((_, true)) if !u.glob => {}
                Some((t, _)) => add(t, u.at, format!("use {}", u.segs.join("::"))),
                None => {}
            }
        }
        for p in &module.paths {
            if let Some((t, _)) = g.target(m, &p.segs, p.at) {
                add(t, p.at, p.segs.join("::"));
            }
        }
    }
    out
}

// ---------------------------------------------------------------- cycles

/// A cycle found at one level: the scope (folder) and the nodes (its children) in it, with the
/// edges between them.
struct Cycle {
    scope: usize,
    nodes: Vec<usize>,
    edges: Vec<Edge>,
}

/// Whether `a` is `anc` or inside it.
fn within(g: &Graph, a: usize, anc: usize) -> bool {
    g.modules[a].path.starts_with(&g.modules[anc].path)
}

/// The child of `scope` that holds `a` (a strict descendant of `scope`).
fn child_holding(g: &Graph, scope: usize, a: usize) -> Option<usize> {
    let depth = g.modules[scope].path.len();
    if a == scope || !within(g, a, scope) {
        return None;
    }
    g.find(&g.modules[a].path[..=depth])
}

/// The strongly connected components of more than one node.
fn sccs(nodes: &[usize], edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let reach = |from: usize| {
        let mut seen = BTreeSet::from([from]);
        let mut stack = vec![from];
        while let Some(x) = stack.pop() {
            for (a, b) in edges {
                if *a == x && seen.insert(*b) {
                    stack.push(*b);
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<usize, BTreeSet<usize>> = nodes.iter().map(|&n| (n, reach(n))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for &n in nodes {
        if done.contains(&n) {
            continue;
        }
        let scc: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&o| reaches[&n].contains(&o) && reaches[&o].contains(&n))
            .collect();
        done.extend(scc.iter().copied());
        if scc.len() > 1 {
            out.push(scc);
        }
    }
    out
}

fn cycles(g: &Graph) -> Vec<Cycle> {
    let mut found = Vec::new();
    for scope in 0..g.modules.len() {
        let nodes: Vec<usize> = g.modules[scope].children.values().copied().collect();
        if nodes.len() < 2 {
            continue;
        }
        // Edges lifted to the scope's children; the scope's own file takes no part.
        let mut lifted: Vec<(usize, usize, Edge)> = Vec::new();
        for e in &g.edges {
            if let (Some(a), Some(b)) = (
                child_holding(g, scope, e.from),
                child_holding(g, scope, e.to),
            ) && a != b
            {
                lifted.push((a, b, e.clone()));
            }
        }
        let pairs: Vec<(usize, usize)> = lifted.iter().map(|(a, b, _)| (*a, *b)).collect();
        for scc in sccs(&nodes, &pairs) {
            let edges = lifted
                .iter()
                .filter(|(a, b, _)| scc.contains(a) && scc.contains(b))
                .map(|(_, _, e)| e.clone())
                .collect();
            found.push(Cycle {
                scope,
                nodes: scc,
                edges,
            });
        }
    }
    found
}

fn describe(g: &Graph, c: &Cycle) -> String {
    let names: Vec<String> = c.nodes.iter().map(|&n| g.name(n)).collect();
    let mut s = format!(
        "cycle among the modules of `{}`: {}\n",
        g.name(c.scope),
        names.join(", ")
    );
    // Edges grouped by the pair of nodes they join, a few lines each.
    let mut by_pair: BTreeMap<(String, String), Vec<&Edge>> = BTreeMap::new();
    for e in &c.edges {
        let a = child_holding(g, c.scope, e.from).unwrap();
        let b = child_holding(g, c.scope, e.to).unwrap();
        by_pair.entry((g.name(a), g.name(b))).or_default().push(e);
    }
    for ((a, b), es) in &by_pair {
        s += &format!("  {a} -> {b}:\n");
        for e in es.iter().take(4) {
            s += &format!(
                "    {}:{} `{}` (-> {})\n",
                g.file(e.from),
                e.line,
                e.what,
                g.file(e.to)
            );
        }
        if es.len() > 4 {
            s += &format!("    (+{} more)\n", es.len() - 4);
        }
    }
    s
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
const PULLED_IN: [&str; 0] = [];

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
    m.path == ["plan"]
        || m.path == ["entry"]
        || family_file(m)
        || PULLED_IN.contains(&m.file.as_str())
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
    let line = |e: &Edge| {
        format!(
            "    {}:{} `{}` (-> {})\n",
            g.file(e.from),
            e.line,
            e.what,
            g.file(e.to)
        )
    };
    let mut s = String::new();
    let foreign: Vec<Edge> = file_cycle_edges(g, c, &|_| false)
        .into_iter()
        .filter(|e| !(registration_file(&g.modules[e.from]) && registration_file(&g.modules[e.to])))
        .collect();
    if !foreign.is_empty() {
        s += "  edges on a cycle of files that touch a file that is neither plan.rs, entry.rs, a family file nor PULLED_IN:\n";
        foreign.iter().for_each(|e| s += &line(e));
    }
    let left = file_cycle_edges(g, c, &|e| registration_edge(g, e));
    if !left.is_empty() {
        s += "  cycles of files left without the family files' imports of plan.rs and entry.rs:\n";
        left.iter().for_each(|e| s += &line(e));
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
            let allowed = registration_allows(&g, c);
            let text = describe(&g, c);
            if allowed {
                println!(
                    "allowed (the registration), its files: {}\n{text}",
                    registration_files(&g, c).join(", ")
                );
            } else {
                let why = if registration_modules(&g, c) {
                    registration_misfits(&g, c)
                } else {
                    String::new()
                };
                problems.push(format!("{dir}: {text}{why}"));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "import cycles (see tests/modules.rs for the rules):\n{}",
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
