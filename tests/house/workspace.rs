//! The house rules checked on the workspace itself: no import cycle
//! between the files of the crates' `src/` folders, and no source file over
//! the line limit.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::support::analyse;

/// A source file may have this many lines.
const MAX_LINES: usize = 850;

/// Files over [`MAX_LINES`] whose split is out of scope today (path from
/// the workspace root, with the line count allowed).
const LONG_FILES: &[(&str, usize)] = &[];

// ---------------------------------------------------------------------
// The workspace
// ---------------------------------------------------------------------

/// The `src/` folders of the workspace's crates, from the workspace root.
fn crate_sources() -> Vec<String> {
    let manifest = std::fs::read_to_string("Cargo.toml").unwrap();
    let manifest: toml::Table = manifest.parse().unwrap();
    let members = manifest["workspace"]["members"].as_array().unwrap();
    let mut dirs = vec!["src".to_owned()];
    for m in members {
        let m = m.as_str().unwrap();
        if !m.starts_with("target") && !m.starts_with("fuzz") {
            dirs.push(format!("{m}/src"));
        }
    }
    dirs
}

fn rust_files(dir: &Path, out: &mut Vec<String>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path.to_str().unwrap().replace('\\', "/"));
        }
    }
}

/// Every `.rs` file under the crates' `src/` folders, with its text, and
/// the crate roots among them.
fn workspace() -> (BTreeMap<String, String>, Vec<String>) {
    let mut sources = BTreeMap::new();
    let mut roots = Vec::new();
    for src in crate_sources() {
        let mut files = Vec::new();
        rust_files(Path::new(&src), &mut files);
        for f in files {
            let rel = f.strip_prefix(&src).unwrap_or(&f);
            let bin = rel.strip_prefix("/bin/").is_some_and(|b| {
                !b.contains('/') || b.ends_with("/main.rs") && b.matches('/').count() == 1
            });
            if rel == "/lib.rs" || rel == "/main.rs" || bin {
                roots.push(f.clone());
            }
            let text = std::fs::read_to_string(&f).unwrap();
            sources.insert(f, text);
        }
    }
    (sources, roots)
}

#[test]
fn no_import_cycle_between_files() {
    let (sources, roots) = workspace();
    let found = analyse(&sources, &roots);
    assert!(found.errors.is_empty(), "{:#?}", found.errors);
    let unread: Vec<&String> = sources
        .keys()
        .filter(|f| !found.files.contains(*f) && !found.test_only.contains(*f))
        .collect();
    assert!(
        unread.is_empty(),
        "files in no module tree and no `#[cfg(test)]` module: {unread:?}"
    );
    assert!(
        found.files.len() > 200,
        "only {} files found: is the walk right?",
        found.files.len()
    );
    let mut report = String::new();
    for set in &found.cycles {
        writeln!(report, "cycle between {} files:", set.len()).unwrap();
        for ((from, to), why) in &found.edges {
            if set.contains(from) && set.contains(to) {
                writeln!(report, "  {from} -> {to}  ({why})").unwrap();
            }
        }
    }
    assert!(
        found.cycles.is_empty(),
        "{} import cycles between files (move the shared item down, or into \
         a module both import):\n{report}",
        found.cycles.len()
    );
    eprintln!(
        "house: {} files in module trees ({} more test-only), {} edges between files",
        found.files.len(),
        found.test_only.len(),
        found.edges.len()
    );
}

#[test]
fn no_source_file_over_the_limit() {
    let (sources, _) = workspace();
    let mut over = Vec::new();
    for (file, text) in &sources {
        let lines = text.lines().count();
        let allowed = LONG_FILES
            .iter()
            .find(|(f, _)| f == file)
            .map_or(MAX_LINES, |(_, n)| *n);
        if lines > allowed {
            over.push(format!("{file}: {lines} lines (at most {allowed})"));
        }
    }
    for (file, allowed) in LONG_FILES {
        let lines = sources.get(*file).map_or(0, |t| t.lines().count());
        if lines <= MAX_LINES {
            over.push(format!(
                "{file}: {lines} lines, no longer over {MAX_LINES}: take it out of LONG_FILES (allowed {allowed})"
            ));
        }
    }
    assert!(
        over.is_empty(),
        "files too long: split them\n{}",
        over.join("\n")
    );
}
