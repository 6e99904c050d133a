//! The detector's own tests on small made-up crates: a known cycle found
//! and nothing else, a cycle broken by moving an item down, `use` trees,
//! and comments and literals that hide their text.

use std::collections::BTreeMap;

use crate::support::*;

// ---------------------------------------------------------------------
// The detector itself
// ---------------------------------------------------------------------

fn files(list: &[(&str, &str)]) -> BTreeMap<String, String> {
    list.iter()
        .map(|(p, t)| ((*p).to_owned(), (*t).to_owned()))
        .collect()
}

fn edge(a: &Analysis, from: &str, to: &str) -> bool {
    a.edges.contains_key(&(from.to_owned(), to.to_owned()))
}

/// A small crate with one cycle (a.rs <-> b.rs, the second edge through a
/// re-export of lib.rs), paths in comments, strings and test code that
/// must not count, and an inline module.
const TINY: &[(&str, &str)] = &[
    (
        "c/src/lib.rs",
        "//! See [`crate::c`] and [`super::c`].\n\
         mod a;\nmod b;\npub mod c;\npub use a::Thing;\n\
         #[cfg(test)]\nmod tests;\n",
    ),
    ("c/src/a.rs", "use crate::b::helper;\npub struct Thing;\n"),
    (
        "c/src/b.rs",
        "pub fn helper() {\n    let _ = \"crate::c::x\";\n    let _ = r#\"super::c\"#;\n    \
         /* crate::c /* nested */ */\n}\npub fn take(_: super::Thing) {}\n\
         pub fn life<'a>(s: &'a str) -> char { let _ = '\"'; 'c' }\n",
    ),
    (
        "c/src/c/mod.rs",
        "mod inner {\n    use super::super::b;\n}\n\
         #[cfg(test)]\nmod tests {\n    use crate::a::Thing;\n}\n\
         pub fn f() -> usize { 1 }\n",
    ),
    ("c/src/tests.rs", "use crate::c::f;\n"),
];

#[test]
fn the_detector_finds_a_known_cycle_and_nothing_else() {
    let a = analyse(&files(TINY), &["c/src/lib.rs".to_owned()]);
    assert!(a.errors.is_empty(), "{:?}", a.errors);
    assert_eq!(
        a.files.iter().map(String::as_str).collect::<Vec<_>>(),
        ["c/src/a.rs", "c/src/b.rs", "c/src/c/mod.rs", "c/src/lib.rs"],
        "tests.rs is test code"
    );
    assert_eq!(
        a.test_only.iter().map(String::as_str).collect::<Vec<_>>(),
        ["c/src/tests.rs"]
    );
    assert_eq!(
        a.cycles,
        vec![vec!["c/src/a.rs".to_owned(), "c/src/b.rs".to_owned()]]
    );
    // The re-export is followed to the file that defines `Thing`.
    assert!(edge(&a, "c/src/b.rs", "c/src/a.rs"));
    assert!(!edge(&a, "c/src/b.rs", "c/src/lib.rs"));
    // A child's bare name is no edge.
    assert!(!edge(&a, "c/src/lib.rs", "c/src/a.rs"));
    // `super::super` inside the inline module is the crate root.
    assert!(edge(&a, "c/src/c/mod.rs", "c/src/b.rs"));
    // Comments, strings and `#[cfg(test)]` code name nothing.
    assert!(!edge(&a, "c/src/b.rs", "c/src/c/mod.rs"));
    assert!(!edge(&a, "c/src/lib.rs", "c/src/c/mod.rs"));
    assert!(!edge(&a, "c/src/c/mod.rs", "c/src/a.rs"));
    assert_eq!(a.edges.len(), 3, "{:#?}", a.edges);
}

#[test]
fn moving_the_shared_item_down_breaks_the_cycle() {
    let mut tiny = files(TINY);
    tiny.insert(
        "c/src/b.rs".to_owned(),
        "pub fn helper() {}\npub fn take(_: &str) {}\n".to_owned(),
    );
    let a = analyse(&tiny, &["c/src/lib.rs".to_owned()]);
    assert!(a.cycles.is_empty(), "{:?}", a.cycles);
    assert!(edge(&a, "c/src/a.rs", "c/src/b.rs"));
}

#[test]
fn use_trees_resolve_each_leaf() {
    let a = analyse(
        &files(&[
            (
                "d/src/main.rs",
                "mod x;\nmod y;\nmod z;\nuse self::{x::{self as ex, *}, y::Y as _};\nfn main() {}\n",
            ),
            (
                "d/src/x.rs",
                "pub fn f() { ::std::mem::drop(crate::z::Z); }\n",
            ),
            ("d/src/y.rs", "pub(in crate::z) struct Y;\n"),
            ("d/src/z.rs", "pub struct Z;\n"),
        ]),
        &["d/src/main.rs".to_owned()],
    );
    let edges: Vec<_> = a.edges.keys().cloned().collect();
    assert_eq!(
        edges,
        [
            ("d/src/main.rs".to_owned(), "d/src/x.rs".to_owned()),
            ("d/src/main.rs".to_owned(), "d/src/y.rs".to_owned()),
            ("d/src/x.rs".to_owned(), "d/src/z.rs".to_owned()),
        ]
    );
}

#[test]
fn literals_and_comments_hide_their_text() {
    let idents = |src: &str| -> Vec<String> {
        lex(src)
            .into_iter()
            .filter_map(|t| match t.tok {
                Tok::Ident(s) => Some(s),
                _ => None,
            })
            .collect()
    };
    assert_eq!(
        idents(
            "a '\\'' b \"\\\" c\" d r##\"e\"#f\"## g b'\\\\' h br#\"i\"# j\n\
             /* k /* l */ m */ n // o\n/// p\n//! q\np<'r, 's> 't' u '\\u{1F600}' v r#w"
        ),
        ["a", "b", "d", "g", "h", "j", "n", "p", "u", "v", "w"]
    );
    let lines: Vec<usize> = lex("x\n\"\n\"\ny /*\n*/ z")
        .iter()
        .map(|t| t.line)
        .collect();
    assert_eq!(lines, [1, 3, 4, 5]);
}
