//! Every `.gen`/`.idl` file of the GenoM3 corpus parses with no syntax
//! error, and every real component loads (with the interface stubs) with no
//! error at all. Skipped (with a note) when the corpus is not on this
//! machine.

use std::path::{Path, PathBuf};

use genom_model::{Code, Severity};
use genom_render::human::{HumanOptions, render_diagnostic};
use genom3_frontend::{Genom3Options, load};

fn corpus() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus/genom3");
    dir.is_dir().then_some(dir)
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files(&p, out);
        } else if p.extension().is_some_and(|e| e == "gen" || e == "idl") {
            out.push(p);
        }
    }
}

fn stubs() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/genom3/include")
}

#[test]
fn every_corpus_file_parses_without_syntax_errors() {
    let Some(dir) = corpus() else {
        return;
    };
    let mut all = Vec::new();
    files(&dir, &mut all);
    assert!(all.len() >= 20, "corpus too small: {}", all.len());
    let mut failures = Vec::new();
    for path in &all {
        let out = load(path, &Genom3Options::default()).expect("readable");
        for d in out.diagnostics.iter().filter(|d| d.code == Code::Syntax) {
            failures.push(render_diagnostic(&out.sources, d, HumanOptions::default()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_component_loads_without_errors_with_the_stubs() {
    let Some(dir) = corpus() else {
        return;
    };
    if !stubs().is_dir() {
        return;
    }
    let mut all = Vec::new();
    files(&dir, &mut all);
    let options = Genom3Options {
        include_dirs: vec![stubs()],
        ..Genom3Options::default()
    };
    let mut failures = Vec::new();
    let mut components = 0;
    for path in all
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
    {
        let out = load(path, &options).expect("readable");
        if out.component.is_some() {
            components += 1;
        }
        for d in out
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
        {
            failures.push(render_diagnostic(&out.sources, d, HumanOptions::default()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(components >= 16, "only {components} components lowered");
}
