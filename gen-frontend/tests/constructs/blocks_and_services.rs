//! LANGUAGE.md sections 2.3 to 2.6: data blocks (ids, exports, imports,
//! values), threads and their stack sizes, and services with their kinds,
//! attributes and parameters.

use gen_frontend::ast::*;

use crate::support::*;

// ---------------------------------------------------------------- 2.3/2.4 data blocks

#[test]
fn ids_members_with_defaults_and_docs() {
    let text = "ids demoIds {\n  double distRef := 0.0 \"Distance reference\";\n  long   mode;   // no default\n  long count := -3;\n  string<8> name \"just a doc\";\n  double m[2][3];\n}\n";
    let r = parse_clean(text);
    let ids = data_blocks(&r)[0];
    assert_eq!(ids.kind, DataKind::Ids);
    assert_eq!(ids.name.name, "demoIds");
    assert_eq!(at(&r, ids.name.span), "demoIds");
    assert_eq!(at(&r, ids.span), text.trim_end());
    assert_eq!(ids.members.len(), 5);

    let dist = &ids.members[0];
    assert_eq!(
        at(&r, dist.span),
        "double distRef := 0.0 \"Distance reference\";"
    );
    assert_eq!(dist.decl.name.name, "distRef");
    assert_eq!(at(&r, dist.decl.name.span), "distRef");
    let init = dist.init.as_ref().expect("a default");
    assert_eq!(float(init), 0.0);
    assert_eq!(at(&r, init.span()), "0.0");
    let doc = dist.doc.as_ref().expect("a doc");
    assert_eq!(doc.value, "Distance reference");
    assert_eq!(at(&r, doc.span), "\"Distance reference\"");

    let mode = &ids.members[1];
    assert_eq!(at(&r, mode.span), "long   mode;");
    assert_eq!(base(&mode.ty), BaseType::Long);
    assert!(mode.init.is_none() && mode.doc.is_none());

    assert_eq!(int(ids.members[2].init.as_ref().expect("default")), -3);

    let name = &ids.members[3];
    assert!(name.init.is_none());
    assert_eq!(
        name.doc.as_ref().map(|d| d.value.as_str()),
        Some("just a doc")
    );

    assert_eq!(ids.members[4].decl.dims.len(), 2);
    assert_eq!(at(&r, ids.members[4].decl.span), "m[2][3]");
}

#[test]
fn export_with_nested_struct_initialiser_by_field() {
    let text = "export demoExport {\n  DEMO_STATE_STR state {\n    position := 0.0 \"Current position\";\n    speed    := 1.5 \"Current speed\";\n    limits { low := -1; high := 1; }\n  }\n  double battery := 12.0 \"Battery voltage\";\n}\n";
    let r = parse_clean(text);
    let export = data_blocks(&r)[0];
    assert_eq!(export.kind, DataKind::Export);
    assert_eq!(export.name.name, "demoExport");
    assert_eq!(export.members.len(), 2);

    let state = &export.members[0];
    assert_eq!(state.decl.name.name, "state");
    assert!(at(&r, state.span).starts_with("DEMO_STATE_STR state {"));
    assert!(at(&r, state.span).ends_with("high := 1; }\n  }"));
    let Some(Value::Fields(fields, fields_span)) = &state.init else {
        panic!("{:?}", state.init)
    };
    assert!(at(&r, *fields_span).starts_with('{') && at(&r, *fields_span).ends_with('}'));
    assert!(state.doc.is_none());
    let names: Vec<_> = fields.iter().map(|f| f.name.name.as_str()).collect();
    assert_eq!(names, ["position", "speed", "limits"]);
    assert_eq!(at(&r, fields[0].name.span), "position");
    assert_eq!(
        at(&r, fields[0].span),
        "position := 0.0 \"Current position\";"
    );
    assert_eq!(float(&fields[1].value), 1.5);
    assert_eq!(
        fields[1].doc.as_ref().map(|d| d.value.as_str()),
        Some("Current speed")
    );
    let Value::Fields(limits, _) = &fields[2].value else {
        panic!("{:?}", fields[2].value)
    };
    assert_eq!(limits.len(), 2);
    assert_eq!(limits[0].name.name, "low");
    assert_eq!(int(&limits[0].value), -1);
    assert_eq!(int(&limits[1].value), 1);
    assert_eq!(at(&r, fields[2].span), "limits { low := -1; high := 1; }");

    let battery = &export.members[1];
    assert_eq!(float(battery.init.as_ref().expect("default")), 12.0);
    assert_eq!(
        battery.doc.as_ref().map(|d| d.value.as_str()),
        Some("Battery voltage")
    );
}

#[test]
fn import_block_with_doc() {
    let r = parse_clean(
        "import demoImport {\n  DEMO_STATE_STR target \"Target published by another component\";\n}\n",
    );
    let import = data_blocks(&r)[0];
    assert_eq!(import.kind, DataKind::Import);
    assert_eq!(import.kind.keyword(), "import");
    assert_eq!(import.name.name, "demoImport");
    let target = &import.members[0];
    assert_eq!(named(&target.ty).parts, ["DEMO_STATE_STR"]);
    assert!(target.init.is_none());
    assert_eq!(
        target.doc.as_ref().map(|d| d.value.as_str()),
        Some("Target published by another component")
    );
    assert_eq!(
        at(&r, target.span),
        "DEMO_STATE_STR target \"Target published by another component\";"
    );
}

#[test]
fn values_lists_enum_names_booleans_and_inline_fields() {
    let text = "ids v {\n  long a[3] := {1, 2, 3};\n  mode m := RUN;\n  mode q := geo::RUN;\n  mode p := ::geo::RUN;\n  boolean t := TRUE;\n  boolean f := false;\n  P pt := { x := 1, y := { z := 2 } };\n  long e[0] := {};\n  long h := 0x1F;\n  string s := \"str\";\n  double d := 1.5e-3;\n}\n";
    let r = parse_clean(text);
    let m = &data_blocks(&r)[0].members;
    let init = |i: usize| m[i].init.as_ref().expect("a value");

    match init(0) {
        Value::List(values, span) => {
            assert_eq!(values.iter().map(int).collect::<Vec<_>>(), [1, 2, 3]);
            assert_eq!(at(&r, *span), "{1, 2, 3}");
            assert_eq!(at(&r, values[2].span()), "3");
        }
        other => panic!("{other:?}"),
    }
    match init(1) {
        Value::Name(n) => {
            assert!(!n.absolute);
            assert_eq!(n.parts, ["RUN"]);
            assert_eq!(at(&r, n.span), "RUN");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(init(2), Value::Name(n) if !n.absolute && n.parts == ["geo", "RUN"]));
    match init(3) {
        Value::Name(n) => {
            assert!(n.absolute);
            assert_eq!(n.parts, ["geo", "RUN"]);
            assert_eq!(at(&r, n.span), "::geo::RUN");
        }
        other => panic!("{other:?}"),
    }
    match init(4) {
        Value::Bool(b, span) => {
            assert!(*b);
            assert_eq!(at(&r, *span), "TRUE");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(init(5), Value::Bool(false, _)));
    match init(6) {
        Value::Fields(fields, span) => {
            assert_eq!(at(&r, *span), "{ x := 1, y := { z := 2 } }");
            assert_eq!(fields[0].name.name, "x");
            assert_eq!(int(&fields[0].value), 1);
            let Value::Fields(inner, _) = &fields[1].value else {
                panic!("{:?}", fields[1])
            };
            assert_eq!(inner[0].name.name, "z");
            assert_eq!(int(&inner[0].value), 2);
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(init(7), Value::List(v, _) if v.is_empty()));
    assert_eq!(int(init(8)), 31);
    assert!(matches!(init(9), Value::Str(s) if s.value == "str"));
    assert!((float(init(10)) - 1.5e-3).abs() < 1e-18);
    match init(10) {
        Value::Number(n) => assert_eq!(n.text, "1.5e-3"),
        other => panic!("{other:?}"),
    }
}

// ---------------------------------------------------------------- 2.5 thread

#[test]
fn thread_with_every_attribute() {
    let text = "thread motionTask {\n  priority: -2;\n  period: 10ms;\n  stack: 64k;\n  start: motionInit;\n  stop: motionEnd;\n}\n";
    let r = parse_clean(text);
    let t = threads(&r)[0];
    assert_eq!(t.name.name, "motionTask");
    assert_eq!(at(&r, t.name.span), "motionTask");
    assert_eq!(at(&r, t.span), text.trim_end());

    let priority = attr(&t.attributes, "priority");
    assert_eq!(at(&r, priority.span), "priority: -2;");
    match &priority.value {
        AttrValue::Integer(i) => {
            assert_eq!(i.value, Some(-2));
            assert_eq!(at(&r, i.span), "-2");
        }
        other => panic!("{other:?}"),
    }
    let period = attr(&t.attributes, "period");
    assert_eq!(duration_ns(period), Some(10_000_000));
    let stack = attr(&t.attributes, "stack");
    match &stack.value {
        AttrValue::Size(s) => {
            assert_eq!(s.bytes, Some(65_536));
            assert_eq!(s.text, "64k");
            assert_eq!(at(&r, s.span), "64k");
        }
        other => panic!("{other:?}"),
    }
    let start = attr(&t.attributes, "start");
    assert!(matches!(&start.value, AttrValue::Ident(i) if i.name == "motionInit"));
    assert_eq!(at(&r, start.span), "start: motionInit;");
    let stop = attr(&t.attributes, "stop");
    assert!(matches!(&stop.value, AttrValue::Ident(i) if i.name == "motionEnd"));
}

#[test]
fn stack_sizes() {
    let r = parse_clean(
        "thread a { stack: 64k; }\nthread b { stack: 64K; }\nthread c { stack: 1M; }\nthread d { stack: 8192; }\n",
    );
    let sizes: Vec<Option<u64>> = threads(&r)
        .iter()
        .map(|t| match &t.attributes[0].value {
            AttrValue::Size(s) => s.bytes,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        sizes,
        [Some(65_536), Some(65_536), Some(1_048_576), Some(8192)]
    );
}

// ---------------------------------------------------------------- 2.6 service

#[test]
fn service_kinds() {
    let text = "service plain {}\ninit service setup {}\nauto service watch {}\n";
    let r = parse_clean(text);
    let s = services(&r);
    assert_eq!(s.len(), 3);
    assert_eq!((s[0].kind, s[0].kind_span), (ServiceKind::Plain, None));
    assert_eq!(at(&r, s[0].span), "service plain {}");

    assert_eq!(s[1].kind, ServiceKind::Init);
    assert_eq!(s[1].name.name, "setup");
    assert_eq!(at(&r, s[1].kind_span.expect("init keyword")), "init");
    assert_eq!(at(&r, s[1].span), "init service setup {}");

    assert_eq!(s[2].kind, ServiceKind::Auto);
    assert_eq!(at(&r, s[2].kind_span.expect("auto keyword")), "auto");
    assert_eq!(at(&r, s[2].name.span), "watch");
}

#[test]
fn service_with_every_attribute() {
    let text = "service moveDistance {\n  doc: \"short description\";\n  thread: motionTask;\n  report: R1, R2;\n  max-time: 2s;   // deadline\n  credential: admin;\n  stops: S1, S2;\n  delays: S3;\n  forbids: S4;\n  input: demoIds.distRef := 0.0 \"Distance to move\", double speed := 0.1;\n  output: double reached \"Final position\", demoIds.distRef;\n  import: DEMO_STATE_STR target;\n  export: DEMO_STATE_STR state, double other;\n}\n";
    let r = parse_clean(text);
    let s = service(&r);
    assert_eq!(s.name.name, "moveDistance");
    assert_eq!(at(&r, s.name.span), "moveDistance");
    assert_eq!(at(&r, s.span), text.trim_end());
    assert!(s.codels.is_empty());
    let names: Vec<_> = s.attributes.iter().map(|a| a.name.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "doc",
            "thread",
            "report",
            "max-time",
            "credential",
            "stops",
            "delays",
            "forbids",
            "input",
            "output",
            "import",
            "export"
        ]
    );

    assert!(
        matches!(&attr(&s.attributes, "doc").value, AttrValue::Str(d) if d.value == "short description")
    );
    let thread = attr(&s.attributes, "thread");
    assert_eq!(at(&r, thread.span), "thread: motionTask;");
    assert!(matches!(&thread.value, AttrValue::Ident(i) if i.name == "motionTask"));

    let idents = |name: &str| match &attr(&s.attributes, name).value {
        AttrValue::Idents(v) => ident_names(v)
            .into_iter()
            .map(str::to_owned)
            .collect::<Vec<_>>(),
        other => panic!("{other:?}"),
    };
    assert_eq!(idents("report"), ["R1", "R2"]);
    assert_eq!(idents("stops"), ["S1", "S2"]);
    assert_eq!(idents("delays"), ["S3"]);
    assert_eq!(idents("forbids"), ["S4"]);
    let AttrValue::Idents(report) = &attr(&s.attributes, "report").value else {
        panic!()
    };
    assert_eq!(at(&r, report[1].span), "R2");

    let max_time = attr(&s.attributes, "max-time");
    // The span ends at the `;`: no blanks, no comment.
    assert_eq!(at(&r, max_time.span), "max-time: 2s;");
    assert_eq!(at(&r, max_time.name.span), "max-time");
    assert_eq!(duration_ns(max_time), Some(2_000_000_000));
    assert!(
        matches!(&attr(&s.attributes, "credential").value, AttrValue::Ident(i) if i.name == "admin")
    );

    let import = attr(&s.attributes, "import");
    match &import.value {
        AttrValue::Typed(list) => {
            assert_eq!(list.len(), 1);
            assert_eq!(named(&list[0].ty).parts, ["DEMO_STATE_STR"]);
            assert_eq!(list[0].name.name, "target");
            assert_eq!(at(&r, list[0].span), "DEMO_STATE_STR target");
        }
        other => panic!("{other:?}"),
    }
    match &attr(&s.attributes, "export").value {
        AttrValue::Typed(list) => {
            let names: Vec<_> = list.iter().map(|t| t.name.name.as_str()).collect();
            assert_eq!(names, ["state", "other"]);
            assert_eq!(base(&list[1].ty), BaseType::Double);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn input_and_output_parameters() {
    let text = "service s {\n  input: demoIds.distRef := 0.0 \"Distance to move\", double speed := 0.1, long n , ids.a.b[2].c;\n  output: double reached \"Final position\", demoIds.distRef;\n}\n";
    let r = parse_clean(text);
    let s = service(&r);
    let AttrValue::Params(input) = &attr(&s.attributes, "input").value else {
        panic!()
    };
    assert_eq!(input.len(), 4);

    let dist = &input[0];
    assert_eq!(
        at(&r, dist.span),
        "demoIds.distRef := 0.0 \"Distance to move\""
    );
    let ParamTarget::Data(d) = &dist.target else {
        panic!("{:?}", dist.target)
    };
    assert_eq!(d.root.name, "demoIds");
    assert_eq!(at(&r, d.root.span), "demoIds");
    assert_eq!(path_text(d), "demoIds.distRef");
    assert_eq!(at(&r, d.span), "demoIds.distRef");
    assert!(matches!(&d.path[..], [PathElem::Field(f)] if f.name == "distRef"));
    assert_eq!(float(dist.default.as_ref().expect("default")), 0.0);
    assert_eq!(
        dist.doc.as_ref().map(|x| x.value.as_str()),
        Some("Distance to move")
    );

    let speed = &input[1];
    assert_eq!(at(&r, speed.span), "double speed := 0.1");
    let ParamTarget::Typed(ty, decl) = &speed.target else {
        panic!("{:?}", speed.target)
    };
    assert_eq!(base(ty), BaseType::Double);
    assert_eq!(decl.name.name, "speed");
    assert_eq!(at(&r, decl.name.span), "speed");
    assert_eq!(float(speed.default.as_ref().expect("default")), 0.1);
    assert!(speed.doc.is_none());

    // A parameter followed by blanks: the span stops at its last token.
    let n = &input[2];
    assert_eq!(at(&r, n.span), "long n");
    assert!(n.default.is_none());

    let ParamTarget::Data(deep) = &input[3].target else {
        panic!("{:?}", input[3].target)
    };
    assert_eq!(path_text(deep), "ids.a.b[2].c");
    assert!(matches!(deep.path[2], PathElem::Index(2, _)));

    let AttrValue::Params(output) = &attr(&s.attributes, "output").value else {
        panic!()
    };
    assert_eq!(output.len(), 2);
    assert!(matches!(&output[0].target, ParamTarget::Typed(_, d) if d.name.name == "reached"));
    assert_eq!(
        output[0].doc.as_ref().map(|x| x.value.as_str()),
        Some("Final position")
    );
    assert!(output[0].default.is_none());
    assert!(matches!(&output[1].target, ParamTarget::Data(d) if path_text(d) == "demoIds.distRef"));
    assert_eq!(at(&r, output[1].span), "demoIds.distRef");
}
