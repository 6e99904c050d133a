//! The parser never panics, never overflows its stack and always finishes
//! with a bounded number of diagnostics, whatever the input: arbitrary
//! strings, random sequences of grammar tokens, every truncation of the
//! canonical example, megabytes of garbage, pathological nesting.

use std::path::Path;

use gen_frontend::ast::Item;
use gen_frontend::{
    MAX_NESTING, MAX_SYNTAX_ERRORS, MemoryLoader, ParserReturn, parse_source, parse_str,
};
use genom_model::{Code, Span};
use proptest::prelude::*;

const PILOT: &str = include_str!("../../specs/pilot.gen");
const DEMO_STRUCT: &str = include_str!("../../specs/demoStruct.idl");

/// Checks what must hold for every parse of `text` as the only file: spans
/// inside the text and on character boundaries, diagnostics sorted, and at
/// most `MAX_SYNTAX_ERRORS` syntax errors plus the "too many" notice.
fn check_invariants(text: &str, r: &ParserReturn) {
    let Ok(len) = u32::try_from(text.len()) else {
        panic!("input too large")
    };
    let in_text = |s: Span| {
        s.start <= s.end && s.end <= len && text.get(s.start as usize..s.end as usize).is_some()
    };
    for d in &r.diagnostics {
        assert!(!d.labels.is_empty(), "{d:#?}");
        for l in &d.labels {
            assert!(
                in_text(l.span),
                "label span {:?} outside the text: {d:#?}",
                l.span
            );
        }
        assert!(
            !d.message.contains('\n'),
            "multi-line message: {:?}",
            d.message
        );
    }
    for item in r.ast.items() {
        assert!(
            in_text(item.span()),
            "item span {:?} outside the text",
            item.span()
        );
        assert!(!item.span().is_empty());
    }
    let starts: Vec<u32> = r.diagnostics.iter().map(|d| d.span().start).collect();
    assert!(
        starts.windows(2).all(|w| w[0] <= w[1]),
        "diagnostics not sorted: {starts:?}"
    );
    let syntax = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Syntax)
        .count();
    assert!(
        syntax <= MAX_SYNTAX_ERRORS + 1,
        "{syntax} syntax diagnostics"
    );
}

fn parse_checked(text: &str) -> ParserReturn {
    let r = parse_str("t.gen", text);
    check_invariants(text, &r);
    r
}

fn has_nesting_error(r: &ParserReturn) -> bool {
    r.diagnostics
        .iter()
        .any(|d| d.code == Code::Syntax && d.message.contains("nesting"))
}

// ---------------------------------------------------------------- property tests

/// Tokens of the grammar, glued at random.
const TOKENS: &[&str] = &[
    "{",
    "}",
    ";",
    ":",
    "::",
    ":=",
    "(",
    ")",
    ",",
    "<",
    ">",
    "[",
    "]",
    ".",
    "-",
    "*",
    "service",
    "component",
    "codel",
    "exec",
    "start",
    "inter",
    "control",
    "init",
    "auto",
    "thread",
    "ids",
    "export",
    "import",
    "include",
    "#include",
    "typedef",
    "struct",
    "enum",
    "const",
    "module",
    "sequence",
    "string",
    "long",
    "unsigned",
    "double",
    "x",
    "y",
    "1",
    "0.5",
    "1s",
    "10ms",
    "64k",
    "\"a\"",
    "\"",
    "/*",
    "*/",
    "//",
    "\n",
    "next",
    "period",
    "max-time",
    "on-inter",
    "doc",
    "credentials",
    "input",
    "output",
    "update",
    "stack",
    "priority",
    "TRUE",
    "\\",
];

fn token_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            prop::sample::select(TOKENS),
            prop::sample::select(&[" ", "", "\n"][..]),
        ),
        0..120,
    )
    .prop_map(|parts| parts.into_iter().flat_map(|(t, sep)| [t, sep]).collect())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn arbitrary_strings_never_panic(text in "(?s).{0,400}") {
        parse_checked(&text);
    }

    #[test]
    fn arbitrary_ascii_never_panics(text in "[ -~\n\t]{0,400}") {
        parse_checked(&text);
    }

    #[test]
    fn token_sequences_never_panic(text in token_soup()) {
        parse_checked(&text);
    }

    /// Garbage placed after a valid component does not change the component
    /// (a leading `;` of the garbage is the component's optional `;`).
    #[test]
    fn valid_prefix_survives_trailing_garbage(garbage in token_soup()) {
        let text = format!("component c {{ lang: C; }}\n{garbage}");
        let r = parse_checked(&text);
        let Some(Item::Component(c)) = r.ast.items().next() else {
            return Err(TestCaseError::fail(format!("no component first: {:#?}", r.ast)));
        };
        prop_assert_eq!(&c.name.name, "c");
        prop_assert_eq!(c.attributes.len(), 1);
        let head = "component c { lang: C; }";
        prop_assert!(r.sources.slice(c.span).starts_with(head));
        prop_assert!(r.diagnostics.iter().all(|d| d.span().start >= c.span.end));
    }
}

// ---------------------------------------------------------------- the canonical example

fn parse_pilot(text: &str) -> ParserReturn {
    let loader = MemoryLoader::new().with("specs/demoStruct.idl", DEMO_STRUCT);
    parse_source(Path::new("specs/pilot.gen"), text.to_owned(), &loader)
}

#[test]
fn every_truncation_of_the_pilot_parses_without_panic() {
    let full = parse_pilot(PILOT);
    assert!(full.diagnostics.is_empty(), "{:#?}", full.diagnostics);
    let service_start = PILOT.find("service moveDistance").expect("the service");
    let service_end = PILOT.rfind('}').expect("a closing brace") + 1;
    let item_ends: Vec<usize> = full.ast.units[0]
        .items
        .iter()
        .map(|i| i.span().end as usize)
        .collect();
    assert!(item_ends.contains(&service_end));

    for cut in (0..=PILOT.len()).filter(|&c| PILOT.is_char_boundary(c)) {
        let prefix = &PILOT[..cut];
        let r = parse_pilot(prefix);
        // Only the main file's diagnostics are checked against `prefix`.
        let main_only = ParserReturn {
            diagnostics: r
                .diagnostics
                .iter()
                .filter(|d| r.sources.locate(d.span()).is_some_and(|l| l.file.0 == 0))
                .cloned()
                .collect(),
            ..r.clone()
        };
        check_invariants(
            prefix,
            &ParserReturn {
                ast: Default::default(),
                ..main_only
            },
        );
        let syntax = r
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::Syntax)
            .count();
        if cut > service_start && cut < service_end {
            assert!(
                syntax > 0,
                "no syntax error for the prefix cut at {cut}: {prefix:?}"
            );
        }
        if item_ends.contains(&cut) {
            assert_eq!(
                syntax, 0,
                "syntax error for the prefix ending an item at {cut}: {:#?}",
                r.diagnostics
            );
        }
    }
}

// ---------------------------------------------------------------- size

/// A deterministic pseudo-random generator (no dependency needed).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
}

#[test]
fn a_megabyte_of_garbage_finishes_with_bounded_diagnostics() {
    let mut rng = Lcg(42);
    let mut text = String::with_capacity(1 << 20);
    while text.len() < 1 << 20 {
        // Many lines look like the start of an item, so recovery restarts often.
        let opened = match rng.next() % 8 {
            0 => {
                text.push_str("service x {\n");
                true
            }
            1 => {
                text.push_str("thread t { period: 1s }\n");
                false
            }
            _ => false,
        };
        let line_len = rng.next() % 100;
        for _ in 0..line_len {
            let c = char::from(b' ' + u8::try_from(rng.next() % 95).expect("printable"));
            // Brackets left open would add up past the nesting bound and
            // end the file in one error: keep the recovery busy instead
            // (the service opened above is closed below).
            if !"{}()[]<>".contains(c) {
                text.push(c);
            }
        }
        text.push('\n');
        if opened {
            text.push_str("}\n");
        }
    }
    let r = parse_checked(&text);
    assert!(
        r.diagnostics.len() <= MAX_SYNTAX_ERRORS + 1,
        "{}",
        r.diagnostics.len()
    );
    let last = r.diagnostics.last().expect("garbage has errors");
    assert!(
        last.message.starts_with("too many syntax errors"),
        "{}",
        last.message
    );

    // Garbage with no line that starts an item: one error, then give up.
    let flat: String = (0..1 << 20)
        .map(|i| if i % 80 == 79 { '\n' } else { '@' })
        .collect();
    let r = parse_checked(&flat);
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
}

#[test]
fn a_very_long_line() {
    let members: String = (0..50_000).map(|i| format!("long m{i}; ")).collect();
    let text = format!(
        "ids big {{ {members}}} component c {{ lang: C; doc: \"{}\"; }}",
        "x".repeat(100_000)
    );
    let r = parse_checked(&text);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    let Some(Item::Data(ids)) = r.ast.items().next() else {
        panic!()
    };
    assert_eq!(ids.members.len(), 50_000);
    assert_eq!(ids.members[49_999].decl.name.name, "m49999");

    let long_name = "n".repeat(200_000);
    let r = parse_checked(&format!("thread {long_name} {{ period: 1s; }}"));
    assert!(r.diagnostics.is_empty());
}

#[test]
fn only_comments_and_empty_files() {
    for text in [
        "",
        " \n\t\r\n",
        "// just a comment",
        "/* block */",
        "/* a */ // b\n/*\n*/\n",
        "\u{FEFF}",
    ] {
        let r = parse_checked(text);
        assert!(r.diagnostics.is_empty(), "{text:?}: {:#?}", r.diagnostics);
        assert_eq!(r.ast.items().count(), 0, "{text:?}");
        assert_eq!(r.ast.units.len(), 1);
    }
}

// ---------------------------------------------------------------- nesting

#[test]
fn deep_brace_nesting_is_a_syntax_error_not_a_stack_overflow() {
    let r = parse_checked(&"{".repeat(10_000));
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
    // It points at the first bracket past the limit.
    assert_eq!(r.diagnostics.len(), 1);
    assert_eq!(r.diagnostics[0].span(), Span::new(64, 65));
    assert_eq!(MAX_NESTING, 64);
    let r = parse_checked(&format!(
        "ids i {{ T x := {}1{}; }}",
        "{".repeat(10_000),
        "}".repeat(10_000)
    ));
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
    let r = parse_checked(&format!(
        "{}{}",
        "module m { ".repeat(10_000),
        "};".repeat(10_000)
    ));
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
}

#[test]
fn deep_sequence_nesting_is_a_syntax_error_not_a_stack_overflow() {
    let text = format!(
        "typedef {}double{} T;",
        "sequence<".repeat(10_000),
        ">".repeat(10_000)
    );
    let r = parse_checked(&text);
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
    let text = format!(
        "const long N = {}1{};",
        "(".repeat(10_000),
        ")".repeat(10_000)
    );
    let r = parse_checked(&text);
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
}

/// Nesting without brackets (a comment between `sequence` and `<`, a chain
/// of unary minus) is reported as nesting too, in debug and release builds
/// alike (in release, pest's own stack guard does not stop these before the
/// AST builder overflows).
#[test]
fn nesting_without_brackets_is_reported_as_nesting() {
    let text = format!(
        "typedef {}double{} T;",
        "sequence/**/<".repeat(10_000),
        ">".repeat(10_000)
    );
    let r = parse_checked(&text);
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
    let text = format!("const long N = {}1;", "- ".repeat(10_000));
    let r = parse_checked(&text);
    assert!(has_nesting_error(&r), "{:#?}", r.diagnostics);
    let first_minus = "const long N = ".len();
    let expected = u32::try_from(first_minus + 2 * MAX_NESTING).unwrap();
    assert_eq!(r.diagnostics[0].span().start, expected);
    assert!(
        r.diagnostics
            .iter()
            .all(|d| !d.message.contains("something else"))
    );
}

/// A very long operator chain builds a tree as deep as the chain is long;
/// it is refused instead of overflowing the stack when the tree is dropped.
#[test]
fn a_very_long_constant_expression_is_refused_not_a_stack_overflow() {
    let text = format!(
        "const long N = 1{};\nconst long M = 2;\n",
        " + 1".repeat(100_000)
    );
    let r = parse_checked(&text);
    assert_eq!(r.diagnostics.len(), 1, "{:#?}", r.diagnostics);
    let d = &r.diagnostics[0];
    assert_eq!(d.code, Code::Syntax);
    assert!(d.message.contains("operators"), "{}", d.message);
    assert!(r.sources.slice(d.span()).starts_with("1 + 1"));
    // Both constants are still there.
    assert_eq!(r.ast.items().count(), 2);

    // A long but reasonable sum, in an array bound, is fine.
    let text = format!("typedef double a[1{}];", " + 1".repeat(500));
    let r = parse_checked(&text);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
}

/// Nesting up to the limit is fine, even on a 2 MiB debug-mode test stack.
#[test]
fn nesting_at_the_limit_parses() {
    let depth = MAX_NESTING - 4;
    let text = format!(
        "ids i {{ T x := {}1{}; }}",
        "{".repeat(depth),
        "}".repeat(depth)
    );
    let r = parse_checked(&text);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    let text = format!(
        "typedef {}double{} T;",
        "sequence<".repeat(depth),
        ">".repeat(depth)
    );
    let r = parse_checked(&text);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    let text = format!(
        "const long N = {}1{};",
        "(".repeat(depth),
        ")".repeat(depth)
    );
    let r = parse_checked(&text);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    let text = format!(
        "{}typedef double T;{}",
        "module m { ".repeat(depth),
        "};".repeat(depth)
    );
    let r = parse_checked(&text);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
}
