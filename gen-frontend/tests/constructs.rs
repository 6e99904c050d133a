//! One test per construct of LANGUAGE.md sections 1 and 2: each parses a
//! small snippet and checks the AST (field values) and the spans of the node
//! and of its names, by the exact text each span covers.

use std::path::Path;

use gen_frontend::ast::*;
use gen_frontend::{MemoryLoader, ParserReturn, parse_file, parse_str};
use genom_model::{FileId, Span};

// ---------------------------------------------------------------- helpers

/// Parses `text` as `t.gen` and requires no diagnostic at all.
fn parse_clean(text: &str) -> ParserReturn {
    let r = parse_str("t.gen", text);
    assert!(
        r.diagnostics.is_empty(),
        "unexpected diagnostics: {:#?}",
        r.diagnostics
    );
    r
}

/// The text a span covers.
fn at(r: &ParserReturn, span: Span) -> &str {
    r.sources.slice(span)
}

fn items(r: &ParserReturn) -> Vec<&Item> {
    r.ast.items().collect()
}

fn component(r: &ParserReturn) -> &Component {
    r.ast
        .items()
        .find_map(|i| match i {
            Item::Component(c) => Some(c),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no component in {:#?}", r.ast))
}

fn services(r: &ParserReturn) -> Vec<&Service> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Service(s) => Some(s),
            _ => None,
        })
        .collect()
}

fn service(r: &ParserReturn) -> &Service {
    let all = services(r);
    assert_eq!(all.len(), 1, "expected one service");
    all[0]
}

fn threads(r: &ParserReturn) -> Vec<&Thread> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Thread(t) => Some(t),
            _ => None,
        })
        .collect()
}

fn data_blocks(r: &ParserReturn) -> Vec<&DataBlock> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Data(d) => Some(d),
            _ => None,
        })
        .collect()
}

fn typedefs(r: &ParserReturn) -> Vec<&Typedef> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Typedef(t) => Some(t),
            _ => None,
        })
        .collect()
}

fn attr<'a>(attributes: &'a [Attribute], name: &str) -> &'a Attribute {
    attributes
        .iter()
        .find(|a| a.name.name == name)
        .unwrap_or_else(|| panic!("no attribute `{name}` in {attributes:#?}"))
}

fn ident_names(idents: &[Ident]) -> Vec<&str> {
    idents.iter().map(|i| i.name.as_str()).collect()
}

fn int(v: &Value) -> i128 {
    match v {
        Value::Number(NumberLit {
            value: Number::Int(n),
            ..
        }) => *n,
        other => panic!("not an integer: {other:?}"),
    }
}

fn float(v: &Value) -> f64 {
    match v {
        Value::Number(NumberLit {
            value: Number::Float(x),
            ..
        }) => *x,
        other => panic!("not a decimal: {other:?}"),
    }
}

fn const_int(e: &ConstExpr) -> i128 {
    match e {
        ConstExpr::Number(NumberLit {
            value: Number::Int(n),
            ..
        }) => *n,
        other => panic!("not an integer: {other:?}"),
    }
}

fn duration_ns(a: &Attribute) -> Option<i64> {
    match &a.value {
        AttrValue::Duration(d) => d.ns,
        other => panic!("not a duration: {other:?}"),
    }
}

fn base(t: &TypeSpec) -> BaseType {
    match t {
        TypeSpec::Base(b, _) => *b,
        other => panic!("not a base type: {other:?}"),
    }
}

fn named(t: &TypeSpec) -> &ScopedName {
    match t {
        TypeSpec::Named(n) => n,
        other => panic!("not a named type: {other:?}"),
    }
}

fn path_text(d: &DataRef) -> String {
    d.to_string()
}

// ---------------------------------------------------------------- 2.1 component

#[test]
fn component_with_every_attribute() {
    let text = "component pilot {\n  category: default;   // engine\n  lang: C;\n  version: \"1.0\";\n  doc: \"Mobile base pilot\"; /* trailing */\n  credentials: none < user < admin;\n}\n";
    let r = parse_clean(text);
    let c = component(&r);
    assert_eq!(c.name.name, "pilot");
    assert_eq!(at(&r, c.name.span), "pilot");
    assert!(at(&r, c.span).starts_with("component pilot {"));
    assert!(at(&r, c.span).ends_with("admin;\n}"));
    let names: Vec<_> = c.attributes.iter().map(|a| a.name.name.as_str()).collect();
    assert_eq!(names, ["category", "lang", "version", "doc", "credentials"]);

    let category = attr(&c.attributes, "category");
    assert_eq!(at(&r, category.span), "category: default;");
    assert_eq!(at(&r, category.name.span), "category");
    match &category.value {
        AttrValue::Ident(i) => {
            assert_eq!(i.name, "default");
            assert_eq!(at(&r, i.span), "default");
        }
        other => panic!("{other:?}"),
    }
    let lang = attr(&c.attributes, "lang");
    assert!(matches!(&lang.value, AttrValue::Ident(i) if i.name == "C"));
    assert_eq!(at(&r, lang.span), "lang: C;");

    let version = attr(&c.attributes, "version");
    match &version.value {
        AttrValue::Str(s) => {
            assert_eq!(s.value, "1.0");
            assert_eq!(at(&r, s.span), "\"1.0\"");
        }
        other => panic!("{other:?}"),
    }
    let doc = attr(&c.attributes, "doc");
    assert_eq!(at(&r, doc.span), "doc: \"Mobile base pilot\";");
    assert!(matches!(&doc.value, AttrValue::Str(s) if s.value == "Mobile base pilot"));

    let credentials = attr(&c.attributes, "credentials");
    assert_eq!(
        at(&r, credentials.span),
        "credentials: none < user < admin;"
    );
    match &credentials.value {
        AttrValue::Credentials(order) => {
            assert_eq!(ident_names(order), ["none", "user", "admin"]);
            assert_eq!(at(&r, order[1].span), "user");
            assert_eq!(at(&r, order[2].span), "admin");
        }
        other => panic!("{other:?}"),
    }
}

// ---------------------------------------------------------------- 2.2 include

#[test]
fn include_forms_resolve_relative_to_the_including_file() {
    let main =
        "include \"x.idl\";\n#include \"y.idl\"\n#include <sub/z.idl>\ncomponent c { lang: C; }\n";
    let loader = MemoryLoader::new()
        .with("dir/a.gen", main)
        .with("dir/x.idl", "typedef double X;\n")
        .with("dir/y.idl", "typedef double Y;")
        .with(
            "dir/sub/z.idl",
            "#include \"../other.idl\"\ntypedef other Z;\n",
        )
        .with("dir/other.idl", "typedef long other;\n")
        // Same names elsewhere must not be picked up.
        .with("x.idl", "this is not IDL")
        .with("dir/sub/other.idl", "this is not IDL either");
    let r = parse_file(Path::new("dir/a.gen"), &loader).expect("main file loads");
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);

    let paths: Vec<String> = r.sources.files().map(|(_, f)| f.display_path()).collect();
    assert_eq!(
        paths,
        [
            "dir/a.gen",
            "dir/x.idl",
            "dir/y.idl",
            "dir/sub/z.idl",
            "dir/other.idl"
        ]
    );
    assert_eq!(r.ast.units.len(), 5);
    assert!(!r.ast.units[0].is_idl);
    assert!(r.ast.units[1..].iter().all(|u| u.is_idl));

    let includes: Vec<&Include> = r.ast.units[0]
        .items
        .iter()
        .filter_map(|i| match i {
            Item::Include(inc) => Some(inc),
            _ => None,
        })
        .collect();
    assert_eq!(includes.len(), 3);

    assert_eq!(includes[0].path.value, "x.idl");
    assert!(!includes[0].angle);
    assert_eq!(at(&r, includes[0].path.span), "\"x.idl\"");
    assert_eq!(at(&r, includes[0].span), "include \"x.idl\";");
    assert_eq!(includes[0].file, Some(FileId(1)));

    assert_eq!(includes[1].path.value, "y.idl");
    assert!(!includes[1].angle);
    assert_eq!(at(&r, includes[1].span), "#include \"y.idl\"");
    assert_eq!(includes[1].file, Some(FileId(2)));

    assert_eq!(includes[2].path.value, "sub/z.idl");
    assert!(includes[2].angle);
    assert_eq!(at(&r, includes[2].path.span), "<sub/z.idl>");
    assert_eq!(at(&r, includes[2].span), "#include <sub/z.idl>");
    assert_eq!(includes[2].file, Some(FileId(3)));

    // The nested include names the file one directory up.
    let nested = match &r.ast.units[3].items[0] {
        Item::Include(inc) => inc,
        other => panic!("{other:?}"),
    };
    assert_eq!(nested.path.value, "../other.idl");
    assert_eq!(nested.file, Some(FileId(4)));
    assert_eq!(
        r.sources.locate(nested.span).map(|l| l.file),
        Some(FileId(3))
    );
    assert_eq!(at(&r, nested.path.span), "\"../other.idl\"");

    // Items of included files carry spans in their own file's range.
    let other_def = &r.ast.units[4].items[0];
    assert_eq!(
        r.sources.locate(other_def.span()).map(|l| l.file),
        Some(FileId(4))
    );
    assert_eq!(at(&r, other_def.span()), "typedef long other;");
}

// ---------------------------------------------------------------- 2.2 IDL

#[test]
fn typedef_struct_with_tag() {
    let text = "typedef struct DEMO_STATE_STR {\n  double position;   /* current position */\n  double speed, accel[2];\n} DEMO_STATE;\n";
    let r = parse_clean(text);
    let t = typedefs(&r)[0];
    assert_eq!(at(&r, t.span), text.trim_end());
    let TypedefTarget::Struct(Some(tag), members) = &t.target else {
        panic!("{:?}", t.target)
    };
    assert_eq!(tag.name, "DEMO_STATE_STR");
    assert_eq!(at(&r, tag.span), "DEMO_STATE_STR");
    assert_eq!(t.declarators.len(), 1);
    assert_eq!(t.declarators[0].name.name, "DEMO_STATE");
    assert_eq!(at(&r, t.declarators[0].span), "DEMO_STATE");
    assert_eq!(members.len(), 2);
    assert_eq!(at(&r, members[0].span), "double position;");
    assert_eq!(base(&members[0].ty), BaseType::Double);
    assert_eq!(at(&r, members[0].ty.span()), "double");
    assert_eq!(members[0].declarators[0].name.name, "position");
    assert_eq!(at(&r, members[1].span), "double speed, accel[2];");
    let names: Vec<_> = members[1]
        .declarators
        .iter()
        .map(|d| d.name.name.as_str())
        .collect();
    assert_eq!(names, ["speed", "accel"]);
    assert_eq!(at(&r, members[1].declarators[1].span), "accel[2]");
    assert_eq!(const_int(&members[1].declarators[1].dims[0]), 2);
}

#[test]
fn typedef_struct_without_tag_and_typedef_enum() {
    let r = parse_clean("typedef struct { long a; } A;\ntypedef enum mode { IDLE, RUN } mode_t;\n");
    let t = typedefs(&r);
    assert!(matches!(&t[0].target, TypedefTarget::Struct(None, m) if m.len() == 1));
    match &t[1].target {
        TypedefTarget::Enum(Some(tag), values) => {
            assert_eq!(tag.name, "mode");
            assert_eq!(ident_names(values), ["IDLE", "RUN"]);
            assert_eq!(at(&r, values[1].span), "RUN");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(t[1].declarators[0].name.name, "mode_t");
}

#[test]
fn plain_struct_and_enum() {
    let text = "struct pos { double x; double y; };\nenum color { RED, GREEN, BLUE, };\nstruct bare { octet o; }\n";
    let r = parse_clean(text);
    let all = items(&r);
    assert_eq!(all.len(), 3);
    let Item::Struct(s) = all[0] else {
        panic!("{:?}", all[0])
    };
    assert_eq!(s.name.name, "pos");
    assert_eq!(at(&r, s.name.span), "pos");
    assert_eq!(at(&r, s.span), "struct pos { double x; double y; };");
    assert_eq!(s.members.len(), 2);
    assert_eq!(s.members[1].declarators[0].name.name, "y");

    let Item::Enum(e) = all[1] else {
        panic!("{:?}", all[1])
    };
    assert_eq!(e.name.name, "color");
    assert_eq!(ident_names(&e.enumerators), ["RED", "GREEN", "BLUE"]);
    assert_eq!(at(&r, e.enumerators[2].span), "BLUE");
    assert_eq!(at(&r, e.span), "enum color { RED, GREEN, BLUE, };");

    // Without the optional `;`, the span ends at the `}`.
    let Item::Struct(bare) = all[2] else {
        panic!("{:?}", all[2])
    };
    assert_eq!(at(&r, bare.span), "struct bare { octet o; }");
    assert_eq!(base(&bare.members[0].ty), BaseType::Octet);
}

#[test]
fn const_with_expressions() {
    let text = "const long N = 2 * 3 + 1;\nconst double E = -(1.5 - 0.5) / 2;\nconst long M = N % 4;\nconst string S = \"s\";\nconst boolean B = TRUE;\n";
    let r = parse_clean(text);
    let consts: Vec<&ConstDef> = r
        .ast
        .items()
        .filter_map(|i| match i {
            Item::Const(c) => Some(c),
            _ => None,
        })
        .collect();
    assert_eq!(consts.len(), 5);

    let n = consts[0];
    assert_eq!(n.name.name, "N");
    assert_eq!(at(&r, n.name.span), "N");
    assert_eq!(base(&n.ty), BaseType::Long);
    assert_eq!(at(&r, n.span), "const long N = 2 * 3 + 1;");
    assert_eq!(at(&r, n.value.span()), "2 * 3 + 1");
    // `*` binds tighter than `+`: (2 * 3) + 1.
    let ConstExpr::Binary(lhs, BinOp::Add, rhs, _) = &n.value else {
        panic!("{:?}", n.value)
    };
    assert_eq!(const_int(rhs), 1);
    assert_eq!(at(&r, lhs.span()), "2 * 3");
    let ConstExpr::Binary(a, BinOp::Mul, b, _) = lhs.as_ref() else {
        panic!("{lhs:?}")
    };
    assert_eq!((const_int(a), const_int(b)), (2, 3));

    // -(1.5 - 0.5) / 2: negation of a parenthesised expression, then `/`.
    let ConstExpr::Binary(neg, BinOp::Div, two, _) = &consts[1].value else {
        panic!("{:?}", consts[1].value)
    };
    assert_eq!(const_int(two), 2);
    let ConstExpr::Neg(inner, neg_span) = neg.as_ref() else {
        panic!("{neg:?}")
    };
    assert_eq!(at(&r, *neg_span), "-(1.5 - 0.5)");
    assert!(matches!(
        inner.as_ref(),
        ConstExpr::Binary(_, BinOp::Sub, _, _)
    ));

    let ConstExpr::Binary(name, BinOp::Rem, four, _) = &consts[2].value else {
        panic!("{:?}", consts[2].value)
    };
    assert!(matches!(name.as_ref(), ConstExpr::Name(s) if s.parts == ["N"]));
    assert_eq!(const_int(four), 4);

    assert!(matches!(&consts[3].ty, TypeSpec::String(None, _)));
    assert!(matches!(&consts[3].value, ConstExpr::Str(s) if s.value == "s"));
    assert!(matches!(&consts[4].value, ConstExpr::Bool(true, _)));
}

#[test]
fn typedef_arrays_one_and_several_dimensions() {
    let r = parse_clean("typedef double vec3[3];\ntypedef float mat[3][4], row[4];\n");
    let t = typedefs(&r);
    assert_eq!(at(&r, t[0].span), "typedef double vec3[3];");
    assert!(matches!(
        &t[0].target,
        TypedefTarget::Type(TypeSpec::Base(BaseType::Double, _))
    ));
    assert_eq!(t[0].declarators[0].name.name, "vec3");
    assert_eq!(at(&r, t[0].declarators[0].name.span), "vec3");
    assert_eq!(at(&r, t[0].declarators[0].span), "vec3[3]");
    assert_eq!(
        t[0].declarators[0]
            .dims
            .iter()
            .map(const_int)
            .collect::<Vec<_>>(),
        [3]
    );

    assert_eq!(t[1].declarators.len(), 2);
    let mat = &t[1].declarators[0];
    assert_eq!(mat.name.name, "mat");
    assert_eq!(at(&r, mat.span), "mat[3][4]");
    assert_eq!(mat.dims.iter().map(const_int).collect::<Vec<_>>(), [3, 4]);
    assert_eq!(at(&r, mat.dims[1].span()), "4");
    assert_eq!(
        t[1].declarators[1]
            .dims
            .iter()
            .map(const_int)
            .collect::<Vec<_>>(),
        [4]
    );
}

#[test]
fn sequence_and_string_types() {
    let text = "struct s {\n  sequence<double> a;\n  sequence<long, 8> b;\n  string c;\n  string<32> d;\n  sequence<sequence<string<4> >, N> e;\n};\n";
    let r = parse_clean(text);
    let Item::Struct(s) = items(&r)[0] else {
        panic!()
    };
    let ty = |i: usize| &s.members[i].ty;

    match ty(0) {
        TypeSpec::Sequence(elem, None, span) => {
            assert_eq!(base(elem), BaseType::Double);
            assert_eq!(at(&r, *span), "sequence<double>");
        }
        other => panic!("{other:?}"),
    }
    match ty(1) {
        TypeSpec::Sequence(elem, Some(bound), span) => {
            assert_eq!(base(elem), BaseType::Long);
            assert_eq!(const_int(bound), 8);
            assert_eq!(at(&r, *span), "sequence<long, 8>");
        }
        other => panic!("{other:?}"),
    }
    match ty(2) {
        TypeSpec::String(None, span) => assert_eq!(at(&r, *span), "string"),
        other => panic!("{other:?}"),
    }
    assert_eq!(at(&r, s.members[2].span), "string c;");
    match ty(3) {
        TypeSpec::String(Some(bound), span) => {
            assert_eq!(const_int(bound), 32);
            assert_eq!(at(&r, *span), "string<32>");
        }
        other => panic!("{other:?}"),
    }
    match ty(4) {
        TypeSpec::Sequence(elem, Some(bound), span) => {
            assert_eq!(at(&r, *span), "sequence<sequence<string<4> >, N>");
            assert!(matches!(bound.as_ref(), ConstExpr::Name(n) if n.parts == ["N"]));
            let TypeSpec::Sequence(inner, None, _) = elem.as_ref() else {
                panic!("{elem:?}")
            };
            assert!(matches!(inner.as_ref(), TypeSpec::String(Some(_), _)));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn every_base_type() {
    let text = "struct all {\n  double a; float b; short c; long d; long long e;\n  unsigned short f; unsigned long g; unsigned long long h;\n  char i; boolean j; octet k;\n  long longitude; unsigned   long\tlong spaced; long long_name; doubles l; longer m;\n  unsigned /* u */ long // l\n long commented; long /* not a type */ alone;\n};\n";
    let r = parse_clean(text);
    let Item::Struct(s) = items(&r)[0] else {
        panic!()
    };
    let got: Vec<(String, String)> = s
        .members
        .iter()
        .map(|m| {
            let ty = match &m.ty {
                TypeSpec::Base(b, _) => b.idl().to_owned(),
                TypeSpec::Named(n) => format!("named {n}"),
                other => format!("{other:?}"),
            };
            (ty, m.declarators[0].name.name.clone())
        })
        .collect();
    let expected = [
        ("double", "a"),
        ("float", "b"),
        ("short", "c"),
        ("long", "d"),
        ("long long", "e"),
        ("unsigned short", "f"),
        ("unsigned long", "g"),
        ("unsigned long long", "h"),
        ("char", "i"),
        ("boolean", "j"),
        ("octet", "k"),
        // `long` ends at a word boundary: `longitude` is the member name.
        ("long", "longitude"),
        ("unsigned long long", "spaced"),
        ("long", "long_name"),
        // Names that merely start with a base type are named types.
        ("named doubles", "l"),
        ("named longer", "m"),
        // Comments may sit between the words of a base type.
        ("unsigned long long", "commented"),
        ("long", "alone"),
    ];
    let expected: Vec<(String, String)> = expected
        .iter()
        .map(|(t, n)| ((*t).to_owned(), (*n).to_owned()))
        .collect();
    assert_eq!(got, expected);

    let longitude = &s.members[11];
    assert_eq!(at(&r, longitude.ty.span()), "long");
    assert_eq!(at(&r, longitude.declarators[0].name.span), "longitude");
    assert_eq!(at(&r, s.members[4].ty.span()), "long long");
    assert_eq!(at(&r, s.members[12].ty.span()), "unsigned   long\tlong");
    assert_eq!(
        at(&r, s.members[16].ty.span()),
        "unsigned /* u */ long // l\n long"
    );
    assert_eq!(at(&r, s.members[17].ty.span()), "long");
}

#[test]
fn modules_nested_and_scoped_names() {
    let text = "module geo {\n  enum mode { IDLE, RUN };\n  module inner {\n    typedef double T;\n  };\n  struct P { inner::T x; ::geo::inner::T y; };\n};\ntypedef geo::P Q;\n";
    let r = parse_clean(text);
    let all = items(&r);
    assert_eq!(all.len(), 2);
    let Item::Module(geo) = all[0] else {
        panic!("{:?}", all[0])
    };
    assert_eq!(geo.name.name, "geo");
    assert_eq!(at(&r, geo.name.span), "geo");
    assert!(at(&r, geo.span).starts_with("module geo {"));
    assert!(at(&r, geo.span).ends_with("};\n};"));
    assert_eq!(geo.items.len(), 3);
    assert!(matches!(&geo.items[0], Item::Enum(e) if e.name.name == "mode"));
    let Item::Module(inner) = &geo.items[1] else {
        panic!("{:?}", geo.items[1])
    };
    assert_eq!(inner.name.name, "inner");
    assert_eq!(
        at(&r, inner.span),
        "module inner {\n    typedef double T;\n  };"
    );
    assert!(matches!(&inner.items[0], Item::Typedef(_)));

    let Item::Struct(p) = &geo.items[2] else {
        panic!("{:?}", geo.items[2])
    };
    let x = named(&p.members[0].ty);
    assert!(!x.absolute);
    assert_eq!(x.parts, ["inner", "T"]);
    assert_eq!(x.last(), "T");
    assert_eq!(at(&r, x.span), "inner::T");
    let y = named(&p.members[1].ty);
    assert!(y.absolute);
    assert_eq!(y.parts, ["geo", "inner", "T"]);
    assert_eq!(y.to_string(), "::geo::inner::T");
    assert_eq!(at(&r, y.span), "::geo::inner::T");

    let Item::Typedef(q) = all[1] else {
        panic!("{:?}", all[1])
    };
    let TypedefTarget::Type(ty) = &q.target else {
        panic!("{:?}", q.target)
    };
    assert_eq!(named(ty).parts, ["geo", "P"]);
}

#[test]
fn inline_idl_in_a_gen_file() {
    let text = "component c { lang: C; }\ntypedef struct DEMO_STATE_STR {\n  double position;   /* current position */\n  double speed;      /* current speed */\n} DEMO_STATE_STR;\nids i { DEMO_STATE_STR state; }\n";
    let r = parse_clean(text);
    assert_eq!(r.ast.units.len(), 1);
    assert!(!r.ast.units[0].is_idl);
    let all = items(&r);
    assert_eq!(all.len(), 3);
    assert!(matches!(all[0], Item::Component(_)));
    let Item::Typedef(t) = all[1] else {
        panic!("{:?}", all[1])
    };
    assert!(at(&r, t.span).starts_with("typedef struct DEMO_STATE_STR {"));
    assert!(at(&r, t.span).ends_with("} DEMO_STATE_STR;"));
    assert!(
        matches!(&t.target, TypedefTarget::Struct(Some(tag), m) if tag.name == "DEMO_STATE_STR" && m.len() == 2)
    );
    let ids = data_blocks(&r)[0];
    assert_eq!(named(&ids.members[0].ty).parts, ["DEMO_STATE_STR"]);
}

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
        .with("specs/pilot.gen", include_str!("../../specs/pilot.gen"))
        .with(
            "specs/demoStruct.idl",
            include_str!("../../specs/demoStruct.idl"),
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
