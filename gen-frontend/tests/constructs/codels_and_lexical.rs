//! LANGUAGE.md section 2.7 and section 1: the four codel kinds, durations
//! in every unit, the lexical rules (comments, string escapes, keywords as
//! names, optional semicolons), and the canonical pilot example.

use std::path::Path;

use gen_frontend::ast::*;
use gen_frontend::{MemoryLoader, parse_file, parse_str};

use crate::support::*;

// ---------------------------------------------------------------- 2.7 codels

#[test]
fn the_four_codel_kinds_with_every_attribute() {
    let text = "service s {\n  control codel {\n    exec: demoControlDistance(demoIds.distRef);\n  }\n  start codel {\n    exec: demoStartMobile();\n    on-inter: stop;\n    next: goto, stop;\n  };\n  exec codel goto {\n    exec: demoGotoPosition(const demoIds.distRef, demoExport.state, a.b[2].c);\n    update: demoExport.state, a.b[2].c;\n    on-inter: stop;\n    max-time: 20ms;          // worst-case execution time\n    next: goto, stop, TOO_FAR_AWAY;\n  }\n  inter codel stop {\n    exec: demoStopMobile(demoExport.state);\n    update: demoExport.state;\n    next: ;                  // empty\n  }   /* after */\n}\n";
    let r = parse_clean(text);
    let s = service(&r);
    assert!(s.attributes.is_empty());
    let kinds: Vec<_> = s
        .codels
        .iter()
        .map(|c| (c.kind, c.name.name.as_str()))
        .collect();
    assert_eq!(
        kinds,
        [
            (CodelKind::Control, "control"),
            (CodelKind::Start, "start"),
            (CodelKind::Exec, "goto"),
            (CodelKind::Inter, "stop")
        ]
    );

    // Control: the name's span is the keyword.
    let control = &s.codels[0];
    assert_eq!(at(&r, control.name.span), "control");
    assert_eq!(
        at(&r, control.span),
        "control codel {\n    exec: demoControlDistance(demoIds.distRef);\n  }"
    );
    let AttrValue::Call(call) = &attr(&control.attributes, "exec").value else {
        panic!()
    };
    assert_eq!(call.function.name, "demoControlDistance");
    assert_eq!(at(&r, call.function.span), "demoControlDistance");
    assert_eq!(at(&r, call.span), "demoControlDistance(demoIds.distRef)");
    assert_eq!(call.args.len(), 1);
    assert!(!call.args[0].is_const);

    // Start: empty argument list; the optional `;` after `}` is in the span.
    let start = &s.codels[1];
    assert_eq!(at(&r, start.name.span), "start");
    assert!(at(&r, start.span).starts_with("start codel {"));
    assert!(at(&r, start.span).ends_with("next: goto, stop;\n  };"));
    let AttrValue::Call(call) = &attr(&start.attributes, "exec").value else {
        panic!()
    };
    assert_eq!(call.function.name, "demoStartMobile");
    assert!(call.args.is_empty());
    let on_inter = attr(&start.attributes, "on-inter");
    assert_eq!(at(&r, on_inter.span), "on-inter: stop;");
    assert_eq!(at(&r, on_inter.name.span), "on-inter");
    assert!(matches!(&on_inter.value, AttrValue::Ident(i) if i.name == "stop"));
    let AttrValue::Idents(next) = &attr(&start.attributes, "next").value else {
        panic!()
    };
    assert_eq!(ident_names(next), ["goto", "stop"]);
    assert_eq!(at(&r, next[0].span), "goto");

    // Exec: const and path arguments, update, max-time, next with a report.
    let goto = &s.codels[2];
    assert_eq!(at(&r, goto.name.span), "goto");
    assert!(at(&r, goto.span).starts_with("exec codel goto {"));
    assert!(at(&r, goto.span).ends_with("TOO_FAR_AWAY;\n  }"));
    let AttrValue::Call(call) = &attr(&goto.attributes, "exec").value else {
        panic!()
    };
    let args: Vec<(bool, String)> = call
        .args
        .iter()
        .map(|a| (a.is_const, path_text(&a.data)))
        .collect();
    assert_eq!(
        args,
        [
            (true, "demoIds.distRef".to_owned()),
            (false, "demoExport.state".to_owned()),
            (false, "a.b[2].c".to_owned())
        ]
    );
    assert_eq!(at(&r, call.args[0].span), "const demoIds.distRef");
    assert_eq!(at(&r, call.args[0].data.span), "demoIds.distRef");
    let path = &call.args[2].data;
    assert_eq!(path.root.name, "a");
    match &path.path[..] {
        [
            PathElem::Field(b),
            PathElem::Index(2, index_span),
            PathElem::Field(c),
        ] => {
            assert_eq!(b.name, "b");
            assert_eq!(at(&r, *index_span), "2");
            assert_eq!(c.name, "c");
            assert_eq!(at(&r, c.span), "c");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(at(&r, path.span), "a.b[2].c");
    let update = attr(&goto.attributes, "update");
    assert_eq!(at(&r, update.span), "update: demoExport.state, a.b[2].c;");
    let AttrValue::DataRefs(refs) = &update.value else {
        panic!()
    };
    assert_eq!(
        refs.iter().map(path_text).collect::<Vec<_>>(),
        ["demoExport.state", "a.b[2].c"]
    );
    let max_time = attr(&goto.attributes, "max-time");
    assert_eq!(at(&r, max_time.span), "max-time: 20ms;");
    assert_eq!(duration_ns(max_time), Some(20_000_000));
    let AttrValue::Idents(next) = &attr(&goto.attributes, "next").value else {
        panic!()
    };
    assert_eq!(ident_names(next), ["goto", "stop", "TOO_FAR_AWAY"]);

    // Inter: an empty `next`; the span stops at `}` before blanks and comments.
    let stop = &s.codels[3];
    assert_eq!(at(&r, stop.name.span), "stop");
    assert!(at(&r, stop.span).starts_with("inter codel stop {"));
    assert!(at(&r, stop.span).ends_with("// empty\n  }"));
    let next = attr(&stop.attributes, "next");
    assert_eq!(at(&r, next.span), "next: ;");
    assert!(matches!(&next.value, AttrValue::Idents(v) if v.is_empty()));
}

#[test]
fn durations_in_every_unit() {
    let text = "thread a { period: 7ns; }\nthread b { period: 250us; }\nthread c { period: 10ms; }\nthread d { period: 1s; }\nthread e { period: 2min; }\nthread f { period: 0.5s; }\nthread g { period: 1.5e-3s; }\nthread h { period: .25ms; }\nthread i { period: 1E3us; }\nthread j { period: 1.5min; }\n";
    let r = parse_clean(text);
    let got: Vec<(String, Option<i64>, String)> = threads(&r)
        .iter()
        .map(|t| {
            let a = attr(&t.attributes, "period");
            let AttrValue::Duration(d) = &a.value else {
                panic!("{a:?}")
            };
            assert_eq!(at(&r, d.span), d.text);
            (t.name.name.clone(), d.ns, d.text.clone())
        })
        .collect();
    let expected = [
        ("a", 7, "7ns"),
        ("b", 250_000, "250us"),
        ("c", 10_000_000, "10ms"),
        ("d", 1_000_000_000, "1s"),
        ("e", 120_000_000_000, "2min"),
        ("f", 500_000_000, "0.5s"),
        ("g", 1_500_000, "1.5e-3s"),
        ("h", 250_000, ".25ms"),
        ("i", 1_000_000, "1E3us"),
        ("j", 90_000_000_000, "1.5min"),
    ];
    let expected: Vec<(String, Option<i64>, String)> = expected
        .iter()
        .map(|(n, ns, t)| ((*n).to_owned(), Some(*ns), (*t).to_owned()))
        .collect();
    assert_eq!(got, expected);
}

// ---------------------------------------------------------------- 1 lexical rules

#[test]
fn comments_of_both_styles_anywhere_between_tokens() {
    let text = "/* leading */ component /* a */ c /* b */ { // line\n  lang /* c */ : /* d */ C /* e */ ; // trailing\n} /* after */\n// last line without newline";
    let r = parse_clean(text);
    let c = component(&r);
    assert_eq!(c.name.name, "c");
    assert_eq!(at(&r, c.name.span), "c");
    assert!(at(&r, c.span).starts_with("component /* a */ c"));
    assert!(at(&r, c.span).ends_with("; // trailing\n}"));
    let lang = &c.attributes[0];
    assert_eq!(at(&r, lang.span), "lang /* c */ : /* d */ C /* e */ ;");
    assert!(matches!(&lang.value, AttrValue::Ident(i) if i.name == "C"));

    // A file with nothing after the last `//` comment, and a `*` inside a block comment.
    let r = parse_clean("thread t { period: 1s; } /* a * b ** / */ // end");
    assert_eq!(threads(&r).len(), 1);
}

#[test]
fn string_escapes() {
    let text = r#"component c { doc: "say \"hi\" \\ back\\slash"; version: "a\nb"; }"#;
    let r = parse_clean(text);
    let c = component(&r);
    let AttrValue::Str(doc) = &attr(&c.attributes, "doc").value else {
        panic!()
    };
    assert_eq!(doc.value, r#"say "hi" \ back\slash"#);
    assert_eq!(at(&r, doc.span), r#""say \"hi\" \\ back\\slash""#);
    // Other backslash sequences are kept as written.
    let AttrValue::Str(version) = &attr(&c.attributes, "version").value else {
        panic!()
    };
    assert_eq!(version.value, r"a\nb");
    // An escaped quote at the end does not end the string early.
    let r = parse_clean(r#"ids i { string s := "\\" "\"";  }"#);
    let m = &data_blocks(&r)[0].members[0];
    assert!(matches!(&m.init, Some(Value::Str(s)) if s.value == "\\"));
    assert_eq!(m.doc.as_ref().map(|d| d.value.as_str()), Some("\""));
}

#[test]
fn keywords_are_names_outside_their_position() {
    let text = "service init {}\nauto service auto {}\nservice stop {\n  start codel { next: start, stop; }\n  exec codel start { next: stop; }\n  exec codel exec {}\n  inter codel stop { next: ; }\n  inter codel codel {}\n}\nthread service { start: start; stop: stop; }\nids ids { long component; double thread; }\n";
    let r = parse_clean(text);
    let s = services(&r);
    assert_eq!(s.len(), 3);
    // A service named `init` is a plain service.
    assert_eq!(
        (s[0].kind, s[0].name.name.as_str()),
        (ServiceKind::Plain, "init")
    );
    assert_eq!(at(&r, s[0].name.span), "init");
    assert_eq!(
        (s[1].kind, s[1].name.name.as_str()),
        (ServiceKind::Auto, "auto")
    );
    assert_eq!(at(&r, s[1].name.span), "auto");
    assert_eq!(at(&r, s[1].kind_span.expect("auto")), "auto");
    assert_ne!(s[1].name.span, s[1].kind_span.expect("auto"));

    // `exec codel start` is an exec codel named `start` (the name clash with
    // the start codel is for the resolver to report); codels named `exec`,
    // `stop` and `codel` are ordinary names.
    let codels: Vec<_> = s[2]
        .codels
        .iter()
        .map(|c| (c.kind, c.name.name.as_str()))
        .collect();
    assert_eq!(
        codels,
        [
            (CodelKind::Start, "start"),
            (CodelKind::Exec, "start"),
            (CodelKind::Exec, "exec"),
            (CodelKind::Inter, "stop"),
            (CodelKind::Inter, "codel")
        ]
    );
    assert_eq!(at(&r, s[2].codels[1].name.span), "start");
    assert!(at(&r, s[2].codels[1].span).starts_with("exec codel start"));
    let AttrValue::Idents(next) = &attr(&s[2].codels[0].attributes, "next").value else {
        panic!()
    };
    assert_eq!(ident_names(next), ["start", "stop"]);

    let t = threads(&r)[0];
    assert_eq!(t.name.name, "service");
    assert!(
        matches!(&attr(&t.attributes, "start").value, AttrValue::Ident(i) if i.name == "start")
    );
    assert!(matches!(&attr(&t.attributes, "stop").value, AttrValue::Ident(i) if i.name == "stop"));
    let ids = data_blocks(&r)[0];
    assert_eq!(ids.name.name, "ids");
    let members: Vec<_> = ids
        .members
        .iter()
        .map(|m| m.decl.name.name.as_str())
        .collect();
    assert_eq!(members, ["component", "thread"]);
}

#[test]
fn optional_semicolon_after_a_top_level_brace() {
    let text = "component c { lang: C; };\nids i { long x; }\nthread t { period: 1s; } ;\nservice s {}\nmodule m { struct a { long x; }; };\nenum e { A };\n";
    let r = parse_clean(text);
    let spans: Vec<&str> = r.ast.items().map(|i| at(&r, i.span())).collect();
    assert_eq!(
        spans,
        [
            "component c { lang: C; };",
            "ids i { long x; }",
            "thread t { period: 1s; } ;",
            "service s {}",
            "module m { struct a { long x; }; };",
            "enum e { A };"
        ]
    );
    // Attributes inside braces need their `;`: a second `;` is an error.
    let r = parse_str("t.gen", "component c { lang: C; };;\n");
    assert_eq!(r.diagnostics.len(), 1);
    assert_eq!(r.diagnostics[0].code, genom_model::Code::Syntax);
    assert_eq!(at(&r, r.diagnostics[0].span()), ";");
}

// ---------------------------------------------------------------- the canonical example

#[test]
fn pilot_example_parses_clean_with_its_include() {
    let loader = MemoryLoader::new()
        .with("specs/pilot.gen", include_str!("../../../specs/pilot.gen"))
        .with(
            "specs/demoStruct.idl",
            include_str!("../../../specs/demoStruct.idl"),
        );
    let r = parse_file(Path::new("specs/pilot.gen"), &loader).expect("pilot loads");
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    assert!(r.is_complete());
    assert_eq!(r.sources.files().count(), 2);
    let s = services(&r);
    let pilot = s
        .iter()
        .find(|s| s.name.name == "moveDistance")
        .expect("moveDistance");
    assert_eq!(at(&r, pilot.name.span), "moveDistance");
    let kinds: Vec<_> = pilot.codels.iter().map(|c| c.kind).collect();
    assert_eq!(
        kinds,
        [
            CodelKind::Control,
            CodelKind::Start,
            CodelKind::Exec,
            CodelKind::Inter
        ]
    );
    assert!(
        r.ast.units[1].items.iter().any(
            |i| matches!(i, Item::Typedef(t) if t.declarators[0].name.name == "DEMO_STATE_STR")
        )
    );
}
