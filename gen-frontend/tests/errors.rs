//! Syntax and include diagnostics: code, message, help and the exact
//! 1-based line and column of the primary span for typical mistakes; error
//! recovery; include problems (missing file, cycle, diamond, directory, an
//! error inside an included file).

use std::path::Path;

use gen_frontend::ast::{AttrValue, Include, Item};
use gen_frontend::{MemoryLoader, ParserReturn, parse_file, parse_str};
use genom_model::{Code, Diagnostic, FileId, Span};

/// The 1-based line and column where `span` starts, in its own file.
fn line_col(r: &ParserReturn, span: Span) -> (usize, usize) {
    let Some(located) = r.sources.locate(span) else {
        panic!("{span:?} is in no file")
    };
    let Some(file) = r.sources.file(located.file) else {
        panic!("no file {:?}", located.file)
    };
    file.line_col(located.offset)
}

/// Parses `text` as `t.gen` and returns its only diagnostic.
fn single(text: &str) -> (ParserReturn, Diagnostic) {
    let r = parse_str("t.gen", text);
    assert_eq!(
        r.diagnostics.len(),
        1,
        "expected one diagnostic: {:#?}",
        r.diagnostics
    );
    let d = r.diagnostics[0].clone();
    (r, d)
}

/// Checks the only diagnostic of `text`: code, message, line and column,
/// and the text under the primary span.
fn expect_one(
    text: &str,
    code: Code,
    message: &str,
    at: (usize, usize),
    covers: &str,
) -> Diagnostic {
    let (r, d) = single(text);
    assert_eq!(d.code, code, "{d:#?}");
    assert_eq!(d.message, message);
    // With base 0 the global offset is the local one.
    let Some(file) = r.sources.file(FileId(0)) else {
        panic!("no main file")
    };
    assert_eq!(file.line_col(d.span().start), at, "position of {d:#?}");
    assert_eq!(r.sources.slice(d.span()), covers);
    assert!(!r.is_complete() || code != Code::Syntax);
    d
}

// ---------------------------------------------------------------- typical mistakes

#[test]
fn missing_semicolon_before_closing_brace_points_after_the_last_token() {
    let d = expect_one(
        "component c {\n  lang: C\n}\n",
        Code::Syntax,
        "expected `;`, found `}`",
        (2, 10),
        "",
    );
    assert_eq!(d.labels[0].message, "expected `;`");
}

#[test]
fn missing_colon() {
    expect_one(
        "thread t {\n  period 10ms;\n}\n",
        Code::Syntax,
        "expected `:`, found `10ms`",
        (2, 10),
        "10ms",
    );
}

#[test]
fn duration_without_unit() {
    expect_one(
        "thread t {\n  period: 10;\n}\n",
        Code::Syntax,
        "expected a duration such as `10ms`, found `10`",
        (2, 11),
        "10",
    );
}

#[test]
fn duration_that_is_not_whole_nanoseconds() {
    let text = "thread t {\n  period: 0.5ns;\n}\n";
    let d = expect_one(
        text,
        Code::InvalidAttribute,
        "duration `0.5ns` is not a whole number of nanoseconds",
        (2, 11),
        "0.5ns",
    );
    assert!(d.help.is_some());
    // The item is still built, with no value for the duration.
    let r = parse_str("t.gen", text);
    let Some(Item::Thread(t)) = r.ast.items().next() else {
        panic!("{:#?}", r.ast)
    };
    assert!(
        matches!(&t.attributes[0].value, AttrValue::Duration(d) if d.ns.is_none() && d.text == "0.5ns")
    );
    assert!(r.is_complete());
}

#[test]
fn literals_too_large_are_invalid_attributes() {
    let r = parse_str(
        "t.gen",
        "thread t {\n  period: 1e30s;\n  priority: 99999999999999999999;\n  stack: 99999999999999999999M;\n}\n",
    );
    let got: Vec<(Code, &str, (usize, usize))> = r
        .diagnostics
        .iter()
        .map(|d| (d.code, d.message.as_str(), line_col(&r, d.span())))
        .collect();
    assert_eq!(
        got,
        [
            (Code::InvalidAttribute, "`1e30s` is too large", (2, 11)),
            (
                Code::InvalidAttribute,
                "`99999999999999999999` is too large",
                (3, 13)
            ),
            (
                Code::InvalidAttribute,
                "`99999999999999999999M` is too large",
                (4, 10)
            ),
        ]
    );
    // The thread is still built, with no values.
    let Some(Item::Thread(t)) = r.ast.items().next() else {
        panic!("{:#?}", r.ast)
    };
    assert!(matches!(&t.attributes[0].value, AttrValue::Duration(d) if d.ns.is_none()));
    assert!(matches!(&t.attributes[1].value, AttrValue::Integer(i) if i.value.is_none()));
    assert!(matches!(&t.attributes[2].value, AttrValue::Size(s) if s.bytes.is_none()));
}

#[test]
fn unknown_attribute_suggests_the_closest_name() {
    let text = "thread t {\n  perod: 10ms;\n}\n";
    let d = expect_one(
        text,
        Code::InvalidAttribute,
        "unknown attribute `perod`",
        (2, 3),
        "perod",
    );
    assert_eq!(d.help.as_deref(), Some("did you mean `period`?"));
    let r = parse_str("t.gen", text);
    let Some(Item::Thread(t)) = r.ast.items().next() else {
        panic!("{:#?}", r.ast)
    };
    assert_eq!(t.attributes[0].name.name, "perod");
    assert!(matches!(&t.attributes[0].value, AttrValue::Unknown(v) if v == "10ms"));

    // A name close to nothing gets no suggestion.
    let d = expect_one(
        "service s {\n  zzzzzz: 1;\n}\n",
        Code::InvalidAttribute,
        "unknown attribute `zzzzzz`",
        (2, 3),
        "zzzzzz",
    );
    assert_eq!(d.help, None);
}

#[test]
fn unterminated_string() {
    // The string runs to the end of the line, where `"` was expected.
    expect_one(
        "service s {\n  doc: \"abc;\n}\n",
        Code::Syntax,
        "expected `\"`, found end of line",
        (2, 13),
        "\n",
    );
    // No message ever holds a raw newline.
    let r = parse_str("t.gen", "service s {\n  doc: \"abc;\n}\n");
    assert!(r.diagnostics.iter().all(|d| !d.message.contains('\n')));
}

#[test]
fn unterminated_comment() {
    let d = expect_one(
        "component c {\n  lang: C; /* never closed\n}\n",
        Code::Syntax,
        "unterminated block comment",
        (2, 12),
        "/*",
    );
    assert!(d.help.as_deref().is_some_and(|h| h.contains("*/")));
}

#[test]
fn stray_closing_brace_at_top_level() {
    let text = "component c { lang: C; }\n}\nthread t { period: 1s; }\n";
    expect_one(
        text,
        Code::Syntax,
        "expected a top-level item, found `}`",
        (2, 1),
        "}",
    );
    // Parsing resumes on the next item line.
    let r = parse_str("t.gen", text);
    let kinds: Vec<_> = r
        .ast
        .items()
        .map(|i| matches!(i, Item::Thread(_)))
        .collect();
    assert_eq!(kinds, [false, true]);
}

#[test]
fn missing_closing_brace_at_end_of_file() {
    let text = "component c {\n  lang: C;\n";
    let d = expect_one(
        text,
        Code::Syntax,
        "expected `}` or an attribute, found end of file",
        (2, 11),
        "",
    );
    // A secondary label shows the brace left open.
    let r = parse_str("t.gen", text);
    let open = d.labels.get(1).expect("a label on the open brace");
    assert_eq!(r.sources.slice(open.span), "{");
    assert_eq!(line_col(&r, open.span), (1, 13));

    // Inside a codel inside a service, the innermost open brace is named.
    let r = parse_str("t.gen", "service s {\n  start codel {\n    next: ;\n");
    let d = &r.diagnostics[0];
    assert!(d.message.ends_with("found end of file"), "{}", d.message);
    assert_eq!(line_col(&r, d.labels[1].span), (2, 15));
}

#[test]
fn start_codel_with_a_name() {
    expect_one(
        "service s {\n  start codel foo {\n  }\n}\n",
        Code::Syntax,
        "expected `{`, found `foo`",
        (2, 15),
        "foo",
    );
}

#[test]
fn trailing_comma_in_codel_arguments() {
    expect_one(
        "service s {\n  exec codel foo {\n    exec: f(a,);\n  }\n}\n",
        Code::Syntax,
        "expected a data reference, found `)`",
        (3, 15),
        ")",
    );
}

#[test]
fn names_without_comma() {
    expect_one(
        "service s {\n  report: A B;\n}\n",
        Code::Syntax,
        "expected `;` or `,`, found `B`",
        (2, 13),
        "B",
    );
}

#[test]
fn missing_value_after_assign() {
    expect_one(
        "ids i {\n  double x := ;\n}\n",
        Code::Syntax,
        "expected a value, found `;`",
        (2, 15),
        ";",
    );
}

#[test]
fn bad_size_unit() {
    expect_one(
        "thread t {\n  stack: 64kb;\n}\n",
        Code::Syntax,
        "expected a size such as `64k`, found `64kb`",
        (2, 10),
        "64kb",
    );
}

#[test]
fn misspelt_top_level_keyword() {
    expect_one(
        "servce s {}\n",
        Code::Syntax,
        "expected a top-level item, found `servce`",
        (1, 1),
        "servce",
    );
}

#[test]
fn gen_items_are_not_allowed_in_an_idl_file() {
    let loader = MemoryLoader::new()
        .with("a.gen", "include \"t.idl\";\ncomponent c { lang: C; }\n")
        .with("t.idl", "typedef double T;\nservice s {}\n");
    let r = parse_file(Path::new("a.gen"), &loader).expect("loads");
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    let d = &r.diagnostics[0];
    assert_eq!(d.code, Code::Syntax);
    assert!(d.message.starts_with("expected "), "{}", d.message);
    assert!(d.message.ends_with("found `service`"), "{}", d.message);
    assert_eq!(r.sources.locate(d.span()).map(|l| l.file), Some(FileId(1)));
    assert_eq!(line_col(&r, d.span()), (2, 1));
}

// ---------------------------------------------------------------- recovery

#[test]
fn three_errors_in_three_services_are_all_reported_in_order() {
    let text = "service a {\n  thread t;\n}\nservice b {\n  period: 10;\n}\nservice c {\n  exec codel x { next: a b; }\n}\ncomponent ok { lang: C; }\n";
    let r = parse_str("t.gen", text);
    let got: Vec<(Code, String, (usize, usize))> = r
        .diagnostics
        .iter()
        .map(|d| (d.code, d.message.clone(), line_col(&r, d.span())))
        .collect();
    assert_eq!(
        got,
        [
            (Code::Syntax, "expected `:`, found `t`".to_owned(), (2, 10)),
            (
                Code::Syntax,
                "expected a duration such as `10ms`, found `10`".to_owned(),
                (5, 11)
            ),
            (
                Code::Syntax,
                "expected `;` or `,`, found `b`".to_owned(),
                (8, 26)
            ),
        ]
    );
    // The item after the broken ones is still parsed.
    assert!(
        r.ast
            .items()
            .any(|i| matches!(i, Item::Component(c) if c.name.name == "ok"))
    );
    assert!(!r.is_complete());
}

#[test]
fn errors_and_invalid_attributes_interleave_in_source_order() {
    let text = "thread t { perod: 1s; }\nservice s { doc: ; }\nthread u { period: 0.5ns; }\n";
    let r = parse_str("t.gen", text);
    let got: Vec<(Code, (usize, usize))> = r
        .diagnostics
        .iter()
        .map(|d| (d.code, line_col(&r, d.span())))
        .collect();
    assert_eq!(
        got,
        [
            (Code::InvalidAttribute, (1, 12)),
            (Code::Syntax, (2, 18)),
            (Code::InvalidAttribute, (3, 20))
        ]
    );
}

// ---------------------------------------------------------------- includes

fn include_items(r: &ParserReturn, unit: usize) -> Vec<&Include> {
    r.ast.units[unit]
        .items
        .iter()
        .filter_map(|i| match i {
            Item::Include(inc) => Some(inc),
            _ => None,
        })
        .collect()
}

#[test]
fn missing_include_points_at_the_path() {
    let loader = MemoryLoader::new().with(
        "dir/a.gen",
        "component c { lang: C; }\ninclude \"missing.idl\";\n",
    );
    let r = parse_file(Path::new("dir/a.gen"), &loader).expect("main file loads");
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    let d = &r.diagnostics[0];
    assert_eq!(d.code, Code::IncludeNotFound);
    assert_eq!(d.message, "cannot include `dir/missing.idl`: no such file");
    assert_eq!(r.sources.slice(d.span()), "\"missing.idl\"");
    assert_eq!(line_col(&r, d.span()), (2, 9));
    assert!(d.help.is_some());
    assert_eq!(include_items(&r, 0)[0].file, None);
    assert_eq!(r.sources.files().count(), 1);
    assert!(!r.is_complete());
}

#[test]
fn missing_main_file_is_a_load_error() {
    let err = parse_file(Path::new("nope.gen"), &MemoryLoader::new()).expect_err("no file");
    assert_eq!(err, gen_frontend::LoadError::NotFound);
}

#[test]
fn include_cycle_is_reported_at_the_closing_include() {
    let loader = MemoryLoader::new()
        .with(
            "dir/a.gen",
            "include \"b.idl\";\ncomponent c { lang: C; }\n",
        )
        .with("dir/b.idl", "#include \"c.idl\"\ntypedef double B;\n")
        .with("dir/c.idl", "typedef double C;\n#include \"b.idl\"\n");
    let r = parse_file(Path::new("dir/a.gen"), &loader).expect("main file loads");
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    let d = &r.diagnostics[0];
    assert_eq!(d.code, Code::IncludeCycle);
    assert_eq!(
        d.message,
        "`dir/b.idl` includes itself: dir/b.idl -> dir/c.idl -> dir/b.idl"
    );
    let located = r.sources.locate(d.span()).expect("located");
    assert_eq!(
        r.sources.file(located.file).map(|f| f.display_path()),
        Some("dir/c.idl".to_owned())
    );
    assert_eq!(r.sources.slice(d.span()), "\"b.idl\"");
    assert_eq!(line_col(&r, d.span()), (2, 10));
    // Each file is loaded once; the cycle-closing include has no file.
    assert_eq!(r.sources.files().count(), 3);
    let c_unit = r
        .ast
        .units
        .iter()
        .position(|u| u.file == located.file)
        .expect("unit");
    assert_eq!(include_items(&r, c_unit)[0].file, None);
    assert!(!r.is_complete());
}

#[test]
fn a_file_including_itself_is_a_cycle() {
    let loader =
        MemoryLoader::new().with("a.gen", "include \"./a.gen\";\ncomponent c { lang: C; }\n");
    let r = parse_file(Path::new("a.gen"), &loader).expect("loads");
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    assert_eq!(r.diagnostics[0].code, Code::IncludeCycle);
    assert_eq!(line_col(&r, r.diagnostics[0].span()), (1, 9));
}

#[test]
fn diamond_includes_are_not_a_cycle_and_load_once() {
    let loader = MemoryLoader::new()
        .with(
            "a.gen",
            "include \"b.idl\";\ninclude \"c.idl\";\ncomponent c { lang: C; }\n",
        )
        .with("b.idl", "include \"d.idl\";\ntypedef D B;\n")
        .with("c.idl", "include \"sub/../d.idl\";\ntypedef D C;\n")
        .with("d.idl", "typedef double D;\n");
    let r = parse_file(Path::new("a.gen"), &loader).expect("loads");
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    assert_eq!(r.sources.files().count(), 4);
    let d_files: Vec<FileId> = r
        .sources
        .files()
        .filter(|(_, f)| f.display_path() == "d.idl")
        .map(|(id, _)| id)
        .collect();
    assert_eq!(d_files.len(), 1);
    // Both includes of d resolve to the one loaded file.
    let targets: Vec<Option<FileId>> = r
        .ast
        .units
        .iter()
        .flat_map(|u| u.items.iter())
        .filter_map(|i| match i {
            Item::Include(inc) if inc.path.value.ends_with("d.idl") => Some(inc.file),
            _ => None,
        })
        .collect();
    assert_eq!(targets, [Some(d_files[0]), Some(d_files[0])]);
    // d's typedef appears once in the whole AST.
    let d_defs = r
        .ast
        .items()
        .filter(|i| matches!(i, Item::Typedef(t) if t.declarators[0].name.name == "D"))
        .count();
    assert_eq!(d_defs, 1);
    assert!(r.is_complete());
}

#[test]
fn including_a_directory_is_include_not_found() {
    let loader = MemoryLoader::new()
        .with("a.gen", "#include <idl>\ncomponent c { lang: C; }\n")
        .with("idl/x.idl", "typedef double X;\n");
    let r = parse_file(Path::new("a.gen"), &loader).expect("loads");
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    let d = &r.diagnostics[0];
    assert_eq!(d.code, Code::IncludeNotFound);
    assert_eq!(d.message, "cannot include `idl`: it is a directory");
    assert_eq!(r.sources.slice(d.span()), "<idl>");
    assert_eq!(line_col(&r, d.span()), (1, 10));
}

#[test]
fn syntax_error_in_an_included_file_points_into_that_file() {
    let loader = MemoryLoader::new()
        .with(
            "dir/a.gen",
            "component c { lang: C; }\ninclude \"types.idl\";\n",
        )
        .with(
            "dir/types.idl",
            "typedef struct S {\n  double x\n  double y;\n} S;\ntypedef long L;\n",
        );
    let r = parse_file(Path::new("dir/a.gen"), &loader).expect("loads");
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    let d = &r.diagnostics[0];
    assert_eq!(d.code, Code::Syntax);
    assert!(d.message.starts_with("expected "), "{}", d.message);
    let located = r.sources.locate(d.span()).expect("located");
    assert_eq!(located.file, FileId(1));
    assert_eq!(
        r.sources.file(located.file).map(|f| f.display_path()),
        Some("dir/types.idl".to_owned())
    );
    // Right after `x`, where the `;` is missing.
    assert_eq!(line_col(&r, d.span()), (2, 11));
    let idl = r.sources.file_span(FileId(1));
    assert!(idl.start <= d.span().start && d.span().end <= idl.end);
    // Recovery in the included file: the next typedef is parsed.
    assert!(
        r.ast.units[1]
            .items
            .iter()
            .any(|i| matches!(i, Item::Typedef(t) if t.declarators[0].name.name == "L"))
    );
}
