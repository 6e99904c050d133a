//! The import-cycle detector of the house rules: the tokens of a Rust file
//! (comments and literals left out), what one file declares, imports and
//! names, and the analysis of module trees into a graph of files with its
//! cycles.

use std::collections::{BTreeMap, BTreeSet};

use petgraph::algo::tarjan_scc;
use petgraph::graphmap::DiGraphMap;

// ---------------------------------------------------------------------
// Tokens
// ---------------------------------------------------------------------

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Tok {
    Ident(String),
    /// `::`
    PathSep,
    Punct(char),
    /// A literal (string, char, number) or a lifetime: never part of a path.
    Other,
}

#[derive(Debug, Clone)]
pub(crate) struct Token {
    pub(crate) tok: Tok,
    pub(crate) line: usize,
}

/// The tokens of `src` that paths are made of; comments, string and char
/// literals, numbers and lifetimes are dropped (literals leave `Other`).
pub(crate) fn lex(src: &str) -> Vec<Token> {
    let c: Vec<char> = src.chars().collect();
    let n = c.len();
    let mut out = Vec::new();
    let mut i = 0;
    let mut line = 1;
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    // Skips a raw string whose `r` is at `i`; returns the index after it.
    let raw_string = |mut i: usize, line: &mut usize| {
        i += 1;
        let mut hashes = 0;
        while at(i) == '#' {
            hashes += 1;
            i += 1;
        }
        i += 1; // the opening quote
        while i < n {
            if c[i] == '\n' {
                *line += 1;
            }
            if c[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#') {
                return i + 1 + hashes;
            }
            i += 1;
        }
        n
    };
    while i < n {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < n && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < n {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if c[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if ch == '"' {
            i += 1;
            while i < n && c[i] != '"' {
                if c[i] == '\\' {
                    i += 1;
                }
                if at(i) == '\n' {
                    line += 1;
                }
                i += 1;
            }
            i += 1;
            out.push(Token {
                tok: Tok::Other,
                line,
            });
        } else if ch == '\'' {
            if at(i + 1) == '\\' {
                // An escaped char literal: past the escaped char, up to
                // the closing quote.
                i += 3;
                while i < n && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3; // 'x'
            } else {
                // A lifetime or label.
                i += 1;
                while at(i).is_alphanumeric() || at(i) == '_' {
                    i += 1;
                }
            }
            out.push(Token {
                tok: Tok::Other,
                line,
            });
        } else if ch.is_ascii_digit() {
            while at(i).is_alphanumeric()
                || at(i) == '_'
                || (at(i) == '.' && at(i + 1).is_ascii_digit())
            {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Other,
                line,
            });
        } else if ch.is_alphabetic() || ch == '_' {
            // String prefixes: b"", r"", r#""#, br"", c"", cr""; byte chars b''.
            let prefix_end = match (ch, at(i + 1), at(i + 2)) {
                ('b' | 'c', 'r', '"' | '#') => Some(i + 1),
                ('r', '"', _) => Some(i),
                ('r', '#', q) if q == '"' || q == '#' => Some(i),
                _ => None,
            };
            if let Some(r) = prefix_end {
                i = raw_string(r, &mut line);
                out.push(Token {
                    tok: Tok::Other,
                    line,
                });
                continue;
            }
            if matches!(ch, 'b' | 'c') && matches!(at(i + 1), '"' | '\'') {
                i += 1; // a byte string or byte char: lexed as the literal next
                continue;
            }
            if ch == 'r' && at(i + 1) == '#' {
                i += 2; // a raw identifier
            }
            let start = i;
            while at(i).is_alphanumeric() || at(i) == '_' {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Ident(c[start..i].iter().collect()),
                line,
            });
        } else if ch == ':' && at(i + 1) == ':' {
            out.push(Token {
                tok: Tok::PathSep,
                line,
            });
            i += 2;
        } else {
            out.push(Token {
                tok: Tok::Punct(ch),
                line,
            });
            i += 1;
        }
    }
    out
}

// ---------------------------------------------------------------------
// One file: its module declarations, imports and paths
// ---------------------------------------------------------------------

/// A path written in a file, inside the inline modules `scope`.
#[derive(Debug, Clone)]
struct PathUse {
    scope: Vec<String>,
    segs: Vec<String>,
    line: usize,
}

#[derive(Debug, Default)]
struct FileScan {
    /// `mod name;` declarations: (inline scope, name).
    mods: Vec<(Vec<String>, String)>,
    /// `#[cfg(test)] mod name;` declarations: (inline scope, name).
    test_mods: Vec<(Vec<String>, String)>,
    /// Inline modules `mod name { … }`, as paths from the file's module.
    inline: Vec<Vec<String>>,
    /// Names brought in by `use`: (inline scope, name) -> path.
    imports: BTreeMap<(Vec<String>, String), Vec<String>>,
    paths: Vec<PathUse>,
}

fn ident(toks: &[Token], i: usize) -> Option<&str> {
    match toks.get(i).map(|t| &t.tok) {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

fn is(toks: &[Token], i: usize, tok: &Tok) -> bool {
    toks.get(i).is_some_and(|t| &t.tok == tok)
}

fn punct(toks: &[Token], i: usize, ch: char) -> bool {
    is(toks, i, &Tok::Punct(ch))
}

/// The index after the bracket that closes the one at `i`.
fn after_group(toks: &[Token], i: usize) -> usize {
    let mut depth = 0usize;
    let mut j = i;
    while j < toks.len() {
        match toks[j].tok {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return j + 1;
                }
            }
            _ => {}
        }
        j += 1;
    }
    toks.len()
}

/// The index after the item (or statement) that starts at `i`: after its
/// `;` or its closing `}`, or at the bracket that closes its scope.
fn after_item(toks: &[Token], i: usize) -> usize {
    let mut depth = 0usize;
    let mut j = i;
    while j < toks.len() {
        match toks[j].tok {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(c @ (')' | ']' | '}')) => {
                if depth == 0 {
                    return j;
                }
                depth -= 1;
                if depth == 0 && c == '}' {
                    return j + 1;
                }
            }
            Tok::Punct(';') if depth == 0 => return j + 1,
            _ => {}
        }
        j += 1;
    }
    toks.len()
}

/// One leaf of a use tree: its path and the name it binds (`None` for a
/// glob or `as _`).
struct UseLeaf {
    segs: Vec<String>,
    name: Option<String>,
    line: usize,
}

/// Parses the use tree at `i` under `prefix`; returns the index after it.
fn use_tree(toks: &[Token], mut i: usize, prefix: &[String], out: &mut Vec<UseLeaf>) -> usize {
    let line = toks.get(i).map_or(0, |t| t.line);
    if is(toks, i, &Tok::PathSep) {
        // `::name`: an extern crate, never a file of this crate.
        let mut p = prefix.to_vec();
        if p.is_empty() {
            p.push("::".to_owned());
        }
        return use_tree(toks, i + 1, &p, out);
    }
    if punct(toks, i, '{') {
        i += 1;
        while i < toks.len() && !punct(toks, i, '}') {
            let next = use_tree(toks, i, prefix, out);
            i = if next > i { next } else { i + 1 };
            if punct(toks, i, ',') {
                i += 1;
            }
        }
        return i + 1;
    }
    if punct(toks, i, '*') {
        out.push(UseLeaf {
            segs: prefix.to_vec(),
            name: None,
            line,
        });
        return i + 1;
    }
    let Some(name) = ident(toks, i) else {
        return i + 1;
    };
    let mut segs = prefix.to_vec();
    let mut bound = name.to_owned();
    if name == "self" && !prefix.is_empty() {
        bound = prefix.last().cloned().unwrap_or_default();
    } else {
        segs.push(name.to_owned());
    }
    i += 1;
    if is(toks, i, &Tok::PathSep) {
        return use_tree(toks, i + 1, &segs, out);
    }
    if ident(toks, i) == Some("as") {
        bound = ident(toks, i + 1).unwrap_or("_").to_owned();
        i += 2;
    }
    out.push(UseLeaf {
        segs,
        name: (bound != "_").then_some(bound),
        line,
    });
    i
}

fn scan(src: &str) -> FileScan {
    let toks = lex(src);
    let mut out = FileScan::default();
    // Inline modules open around the current token: (name, brace depth
    // inside it).
    let mut stack: Vec<(String, usize)> = Vec::new();
    let scope =
        |stack: &[(String, usize)]| stack.iter().map(|(m, _)| m.clone()).collect::<Vec<_>>();
    let mut depth = 0usize;
    let mut test_only = false;
    let mut i = 0;
    while i < toks.len() {
        // Attributes: `#[cfg(test)]` leaves out the item it marks,
        // `#![cfg(test)]` the rest of its scope.
        if punct(&toks, i, '#') {
            let inner = punct(&toks, i + 1, '!');
            let open = if inner { i + 2 } else { i + 1 };
            if punct(&toks, open, '[') {
                let end = after_group(&toks, open);
                let body: Vec<&Tok> = toks[open + 1..end - 1].iter().map(|t| &t.tok).collect();
                let cfg_test = body.len() == 4
                    && body[0] == &Tok::Ident("cfg".to_owned())
                    && body[1] == &Tok::Punct('(')
                    && body[2] == &Tok::Ident("test".to_owned())
                    && body[3] == &Tok::Punct(')');
                i = end;
                if cfg_test && inner {
                    while i < toks.len() && !punct(&toks, i, '}') {
                        i = after_item(&toks, i).max(i + 1);
                    }
                } else if cfg_test {
                    test_only = true;
                }
                continue;
            }
        }
        if test_only {
            test_only = false;
            let mut j = i;
            if ident(&toks, j) == Some("pub") {
                j += 1;
                if punct(&toks, j, '(') {
                    j = after_group(&toks, j);
                }
            }
            if let (Some("mod"), Some(name)) = (ident(&toks, j), ident(&toks, j + 1)) {
                if punct(&toks, j + 2, ';') {
                    out.test_mods.push((scope(&stack), name.to_owned()));
                }
            }
            i = after_item(&toks, i);
            continue;
        }
        match &toks[i].tok {
            Tok::Ident(kw) if kw == "mod" => {
                if let Some(name) = ident(&toks, i + 1) {
                    if punct(&toks, i + 2, ';') {
                        out.mods.push((scope(&stack), name.to_owned()));
                        i += 3;
                        continue;
                    }
                    if punct(&toks, i + 2, '{') {
                        stack.push((name.to_owned(), depth + 1));
                        out.inline.push(scope(&stack));
                        depth += 1;
                        i += 3;
                        continue;
                    }
                }
                i += 1;
            }
            // `pub(crate)`, `pub(in crate::x)`: a visibility, not a use.
            Tok::Ident(kw) if kw == "pub" && punct(&toks, i + 1, '(') => {
                i = after_group(&toks, i + 1);
            }
            Tok::Ident(kw) if kw == "use" => {
                let mut leaves = Vec::new();
                let end = use_tree(&toks, i + 1, &[], &mut leaves);
                let here = scope(&stack);
                for leaf in leaves {
                    if let Some(name) = leaf.name {
                        out.imports.insert((here.clone(), name), leaf.segs.clone());
                    }
                    out.paths.push(PathUse {
                        scope: here.clone(),
                        segs: leaf.segs,
                        line: leaf.line,
                    });
                }
                i = end.max(i + 1);
            }
            // `$crate::…` in a macro, `.method::<T>()`, `<T>::f`, `::std`:
            // no module of this crate.
            Tok::Punct('$' | '.') | Tok::PathSep => {
                i += if ident(&toks, i + 1).is_some() { 2 } else { 1 };
            }
            Tok::Ident(first) if is(&toks, i + 1, &Tok::PathSep) => {
                let line = toks[i].line;
                let mut segs = vec![first.clone()];
                let mut j = i + 1;
                while is(&toks, j, &Tok::PathSep) {
                    match ident(&toks, j + 1) {
                        Some(s) => segs.push(s.to_owned()),
                        None => break,
                    }
                    j += 2;
                }
                out.paths.push(PathUse {
                    scope: scope(&stack),
                    segs,
                    line,
                });
                i = j;
            }
            Tok::Punct('{') => {
                depth += 1;
                i += 1;
            }
            Tok::Punct('}') => {
                if stack.last().is_some_and(|(_, d)| *d == depth) {
                    stack.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            _ => i += 1,
        }
    }
    out
}

// ---------------------------------------------------------------------
// Module trees and the file graph
// ---------------------------------------------------------------------

/// What the check found in a set of files.
#[derive(Debug, Default)]
pub(crate) struct Analysis {
    /// Files in some crate's module tree.
    pub(crate) files: BTreeSet<String>,
    /// Files of modules only compiled for tests (not checked).
    pub(crate) test_only: BTreeSet<String>,
    /// (from, to) -> the first path that makes the edge (`line: path`).
    pub(crate) edges: BTreeMap<(String, String), String>,
    /// Strongly connected sets of more than one file, each sorted.
    pub(crate) cycles: Vec<Vec<String>>,
    /// Module declarations whose file is missing.
    pub(crate) errors: Vec<String>,
}

/// One crate's module tree: module path -> file.
struct Tree<'a> {
    modules: BTreeMap<Vec<String>, &'a str>,
    /// (module, name) -> the path `use` binds it to, relative to module.
    imports: BTreeMap<(Vec<String>, String), Vec<String>>,
}

impl<'a> Tree<'a> {
    /// `segs` written in module `scope`, as a path from the crate root;
    /// `None` when it leaves the crate.
    fn absolute(&self, scope: &[String], segs: &[String]) -> Option<Vec<String>> {
        let (first, rest) = segs.split_first()?;
        let mut path = match first.as_str() {
            "crate" => Vec::new(),
            "self" => scope.to_vec(),
            "super" => scope.split_last()?.1.to_vec(),
            name => {
                let mut child = scope.to_vec();
                child.push(name.to_owned());
                if !self.modules.contains_key(&child) {
                    return None;
                }
                child
            }
        };
        for s in rest {
            match s.as_str() {
                "super" => {
                    path.pop()?;
                }
                "self" => {}
                _ => path.push(s.clone()),
            }
        }
        Some(path)
    }

    /// The file that defines what the absolute `path` names.
    fn file(&self, path: &[String], fuel: usize) -> Option<&'a str> {
        let k = (0..=path.len())
            .rev()
            .find(|k| self.modules.contains_key(&path[..*k]))?;
        let module = &path[..k];
        let file = self.modules[module];
        let Some(name) = path.get(k) else {
            return Some(file);
        };
        match self.imports.get(&(module.to_vec(), name.clone())) {
            // Only imported here: the file that defines it, if in the crate.
            Some(target) if fuel > 0 => {
                let mut full = self.absolute(module, target)?;
                full.extend_from_slice(&path[k + 1..]);
                self.file(&full, fuel - 1)
            }
            _ => Some(file),
        }
    }
}

/// The folder of the children of the module in `file`.
fn child_dir(file: &str, is_root: bool) -> String {
    let (dir, name) = file.rsplit_once('/').unwrap_or(("", file));
    let stem = name.trim_end_matches(".rs");
    if is_root || stem == "mod" {
        dir.to_owned()
    } else {
        format!("{dir}/{stem}")
    }
}

/// The file of module `name`, declared in the inline modules `scope` of
/// a file whose children are in `dir`.
fn child_file<'a>(
    sources: &'a BTreeMap<String, String>,
    dir: &str,
    scope: &[String],
    name: &str,
) -> Option<&'a str> {
    let base = std::iter::once(dir.to_owned())
        .chain(scope.iter().cloned())
        .collect::<Vec<_>>()
        .join("/");
    [format!("{base}/{name}.rs"), format!("{base}/{name}/mod.rs")]
        .iter()
        .find_map(|c| sources.get_key_value(c))
        .map(|(f, _)| f.as_str())
}

/// Checks the crates whose root files are `roots` among `sources` (path
/// -> text, paths with `/`).
pub(crate) fn analyse(sources: &BTreeMap<String, String>, roots: &[String]) -> Analysis {
    let mut out = Analysis::default();
    let mut scans: BTreeMap<&str, FileScan> = BTreeMap::new();
    let mut graph: DiGraphMap<&str, (), std::hash::RandomState> = DiGraphMap::new();
    for root in roots {
        let Some((root, _)) = sources.get_key_value(root) else {
            out.errors.push(format!("no crate root {root}"));
            continue;
        };
        let mut tree = Tree {
            modules: BTreeMap::new(),
            imports: BTreeMap::new(),
        };
        // (file, its module path, whether it is the crate root)
        let mut queue: Vec<(&str, Vec<String>, bool)> = vec![(root.as_str(), Vec::new(), true)];
        let mut in_tree: Vec<(&str, Vec<String>)> = Vec::new();
        let mut test_queue: Vec<&str> = Vec::new();
        while let Some((file, module, is_root)) = queue.pop() {
            let s = scans.entry(file).or_insert_with(|| scan(&sources[file]));
            tree.modules.insert(module.clone(), file);
            for inline in &s.inline {
                tree.modules
                    .insert([module.clone(), inline.clone()].concat(), file);
            }
            for ((scope, name), target) in &s.imports {
                tree.imports.insert(
                    ([module.clone(), scope.clone()].concat(), name.clone()),
                    target.clone(),
                );
            }
            let dir = child_dir(file, is_root);
            for (scope, name) in &s.mods {
                match child_file(sources, &dir, scope, name) {
                    Some(child) => {
                        let path = [module.clone(), scope.clone(), vec![name.clone()]].concat();
                        queue.push((child, path, false));
                    }
                    None => out
                        .errors
                        .push(format!("{file}: no file for `mod {name};`")),
                }
            }
            for (scope, name) in &s.test_mods {
                if let Some(child) = child_file(sources, &dir, scope, name) {
                    test_queue.push(child);
                }
            }
            in_tree.push((file, module));
        }
        // Test modules and whatever they declare.
        while let Some(file) = test_queue.pop() {
            if out.test_only.insert(file.to_owned()) {
                let s = scans.entry(file).or_insert_with(|| scan(&sources[file]));
                let dir = child_dir(file, false);
                for (scope, name) in s.mods.iter().chain(&s.test_mods) {
                    test_queue.extend(child_file(sources, &dir, scope, name));
                }
            }
        }
        for (file, module) in in_tree {
            out.files.insert(file.to_owned());
            graph.add_node(file);
            for p in &scans[file].paths {
                let scope = [module.clone(), p.scope.clone()].concat();
                // Only paths written from `crate`, `super` or `self` are
                // edges; a child's bare name serves re-exports alone.
                if !matches!(p.segs[0].as_str(), "crate" | "super" | "self") {
                    continue;
                }
                let Some(abs) = tree.absolute(&scope, &p.segs) else {
                    continue;
                };
                let Some(to) = tree.file(&abs, 16) else {
                    continue;
                };
                if to != file {
                    graph.add_edge(file, to, ());
                    out.edges
                        .entry((file.to_owned(), to.to_owned()))
                        .or_insert_with(|| format!("line {}: {}", p.line, p.segs.join("::")));
                }
            }
        }
    }
    for set in tarjan_scc(&graph) {
        if set.len() > 1 {
            let mut set: Vec<String> = set.into_iter().map(str::to_owned).collect();
            set.sort();
            out.cycles.push(set);
        }
    }
    out.cycles.sort();
    out
}
