//! LANGUAGE.md sections 2.1 and 2.2: the component with every attribute,
//! the forms of include, and the IDL (typedefs, structs, enums, consts,
//! arrays, sequences, strings, base types, modules, inline IDL).

use std::path::Path;

use gen_frontend::ast::*;
use gen_frontend::{MemoryLoader, parse_file};
use genom_model::FileId;

use crate::support::*;

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
