//! The in-process preprocessor through the public API: include search
//! order, per-file spans, pragmas, guards, and dialect detection.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use genom_model::{Code, FileId};
use genom3_frontend::{MemoryLoader, load_with, looks_like_genom3};

fn loader(files: &[(&str, &str)]) -> MemoryLoader {
    files
        .iter()
        .fold(MemoryLoader::new(), |l, (p, t)| l.with(p, *t))
}

#[test]
fn includes_search_the_including_folder_then_each_dir_in_order() {
    let l = loader(&[
        ("a/x.idl", "struct from_a { long v; };\n"),
        ("b/x.idl", "struct from_b { long v; };\n"),
        ("c/y.idl", "struct from_c { long v; };\n"),
        ("b/y.idl", "struct from_b_y { long v; };\n"),
    ]);
    let main =
        "#include \"x.idl\"\n#include <y.idl>\ncomponent m { ids { from_a a; from_b_y b; }; };\n";
    let search = [PathBuf::from("b"), PathBuf::from("c")];
    let out = load_with(Path::new("a/m.gen"), main.to_owned(), &search, &l);
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    let paths: Vec<String> = out.sources.files().map(|(_, f)| f.display_path()).collect();
    assert_eq!(paths[..3], ["a/m.gen", "a/x.idl", "b/y.idl"]);
}

#[test]
fn a_missing_include_names_the_folders_searched_and_suggests_dash_i() {
    let l = loader(&[]);
    let main = "#include \"or/pose/p.gen\"\ncomponent m { ids { or_pose::state s; }; };\n";
    let out = load_with(
        Path::new("src/m.gen"),
        main.to_owned(),
        &[PathBuf::from("inc")],
        &l,
    );
    let d = out
        .diagnostics
        .iter()
        .find(|d| d.code == Code::IncludeNotFound)
        .unwrap();
    assert_eq!(d.labels[0].message, "searched in: src, inc");
    assert!(d.help.as_deref().unwrap().contains("-I"));
    // The rest of the file is still read, without the cascade of names
    // the missing file would define.
    assert!(out.component.is_some());
    assert!(!out.is_complete());
    assert!(out.diagnostics.iter().all(|d| d.code != Code::UnknownType));
}

#[test]
fn diagnostics_in_included_files_point_into_them_with_the_include_chain() {
    let l = loader(&[
        ("i/outer.gen", "#include \"inner.idl\"\n"),
        ("i/inner.idl", "struct s { nope_t f; };\n"),
    ]);
    let main = "#include \"i/outer.gen\"\ncomponent m { };\n";
    let out = load_with(Path::new("m.gen"), main.to_owned(), &[], &l);
    let d = out
        .diagnostics
        .iter()
        .find(|d| d.code == Code::UnknownType)
        .unwrap();
    let file = out.sources.file_of(d.span().start).unwrap();
    assert_eq!(
        out.sources.file(file).unwrap().display_path(),
        "i/inner.idl"
    );
    let located = out.sources.locate(d.span()).unwrap();
    assert_eq!(located.offset, 11);
    // Two "included from here" labels: in outer.gen, then in m.gen.
    let chain: Vec<FileId> = d.labels[1..]
        .iter()
        .map(|l| out.sources.file_of(l.span.start).unwrap())
        .collect();
    assert_eq!(chain, [FileId(1), FileId(0)]);
}

#[test]
fn guards_read_a_file_once_and_pragmas_are_recorded_in_order() {
    let guarded = "#ifndef G\n#define G\nstruct g { long v; };\n#endif\n";
    let l = loader(&[("g.idl", guarded)]);
    let main = "#pragma require \"pkg >= 1\"\n#include \"g.idl\"\n#include \"g.idl\"\n#pragma provides demo\ncomponent m { ids { g x; }; };\n";
    let out = load_with(Path::new("m.gen"), main.to_owned(), &[], &l);
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    let pragmas: Vec<(&str, &str)> = out
        .pragmas
        .iter()
        .map(|p| (p.kind.as_str(), p.args.as_str()))
        .collect();
    assert_eq!(pragmas, [("require", "\"pkg >= 1\""), ("provides", "demo")]);
}

#[test]
fn include_cycles_are_diagnosed() {
    let l = loader(&[
        ("a.gen", "#include \"b.gen\"\n"),
        ("b.gen", "#include \"a.gen\"\n"),
    ]);
    let out = load_with(
        Path::new("a.gen"),
        "#include \"b.gen\"\ncomponent a {};\n".to_owned(),
        &[],
        &l,
    );
    assert!(out.diagnostics.iter().any(|d| d.code == Code::IncludeCycle));
}

#[test]
fn dialect_detection_tells_the_corpus_from_the_specs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let specs = root.join("../specs");
    for e in std::fs::read_dir(&specs).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "gen") {
            let text = std::fs::read_to_string(&p).unwrap();
            assert!(!looks_like_genom3(&text), "{} is LANGUAGE.md", p.display());
        }
    }
    let corpus = root.join("../../shared/corpus/genom3");
    let Ok(dirs) = std::fs::read_dir(&corpus) else {
        return;
    };
    for d in dirs {
        let d = d.unwrap().path();
        for e in std::fs::read_dir(&d).into_iter().flatten() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "gen") {
                let text = std::fs::read_to_string(&p).unwrap();
                assert!(looks_like_genom3(&text), "{} is GenoM3", p.display());
            }
        }
    }
}
