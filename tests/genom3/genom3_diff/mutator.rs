//! The mutator's own tests (ordinary `cargo test`): the tokenizer, distinct
//! deterministic mutants at the source's positions, and version comparison.

use std::collections::BTreeSet;

use super::support::*;

// ---------------------------------------------------------------------------
// The mutator's own tests (ordinary `cargo test`)

/// A small component with everything the tokenizer must step over.
const SAMPLE: &str = r#"/* a comment; with { brackets } */
#pragma require "openrobots2-idl >= 2.0"
#include "or/pose/pose_estimator.gen"
#define TWO \
  2

component sample {
  version "1.0";  // a line comment; too
  codels-require "eigen3";
  uses or_pose_estimator;
  port in or_pose_estimator::state state;
  const double gain = 1e-2;
  ids { double x[TWO]; struct s_s { long a; } s; };
  task main {
    period 10 ms;
    codel<start> start(out ::ids) yield ether;
  };
  activity go(in double v = 0.5 : "speed; in m/s") {
    task main;
    codel<start> go_start(in v, ids inout x, port in state) yield pause::start, ether;
  };
};
"#;

fn words(src: &str) -> Vec<&str> {
    tokenize(src).iter().map(|t| &src[t.start..t.end]).collect()
}

#[test]
fn tokenizer_skips_comments_and_preprocessor_lines() {
    let w = words(SAMPLE);
    assert_eq!(&w[..3], ["component", "sample", "{"]);
    assert!(w.contains(&"codels-require"));
    assert!(w.contains(&"1e-2"));
    assert!(w.contains(&"::"));
    assert!(w.contains(&"\"speed; in m/s\""));
    assert!(!w.contains(&"#pragma") && !w.contains(&"comment") && !w.contains(&"2"));
    assert_eq!(w.last(), Some(&";"));
    assert_eq!(
        words("a::b 0x1e-2 'c'"),
        ["a", "::", "b", "0x1e", "-", "2", "'c'"]
    );
}

#[test]
fn mutants_are_deterministic_and_distinct() {
    let per_kind = 3;
    let first = mutants(SAMPLE, "sample/sample.gen", per_kind, 0);
    assert_eq!(first, mutants(SAMPLE, "sample/sample.gen", per_kind, 0));
    assert_eq!(first.len(), Kind::ALL.len() * per_kind);
    let texts: BTreeSet<&str> = first.iter().map(|m| m.text.as_str()).collect();
    assert_eq!(texts.len(), first.len(), "mutants are pairwise distinct");
    assert!(
        !texts.contains(SAMPLE),
        "every mutant differs from the source"
    );
    for kind in Kind::ALL {
        assert_eq!(first.iter().filter(|m| m.kind == kind).count(), per_kind);
    }
    // Another name or seed gives other mutants.
    assert_ne!(first, mutants(SAMPLE, "other.gen", per_kind, 0));
    assert_ne!(first, mutants(SAMPLE, "sample/sample.gen", per_kind, 1));

    let semicolons = words(SAMPLE).iter().filter(|w| **w == ";").count();
    for m in &first {
        // Comments and preprocessor lines are never mutated.
        for kept in [
            "/* a comment; with { brackets } */\n#pragma require",
            "#include \"or/pose/pose_estimator.gen\"\n#define TWO \\\n  2\n",
            "// a line comment; too\n",
        ] {
            assert!(m.text.contains(kept), "{}: {}", m.what, m.text);
        }
        let w = words(&m.text);
        match m.kind {
            Kind::MissingSemicolon => {
                assert_eq!(w.iter().filter(|w| **w == ";").count(), semicolons - 1);
            }
            Kind::DeleteToken | Kind::DeleteBracket => {
                assert_eq!(w.len(), words(SAMPLE).len() - 1, "{}", m.what);
            }
            Kind::DuplicateToken => assert_eq!(w.len(), words(SAMPLE).len() + 1),
            Kind::SwapDirection => assert!(
                m.what.contains("`in`") || m.what.contains("`out`") || m.what.contains("`inout`")
            ),
            Kind::MisspellName => assert!(m.what.contains("_x`")),
            Kind::SwapAdjacent | Kind::SwapKeyword => {
                assert_eq!(w.len(), words(SAMPLE).len(), "{}", m.what);
            }
        }
    }
}

#[test]
fn mutant_positions_are_those_of_the_source() {
    let src = "component c {\n  version \"1\";\n  lang \"c\";\n};\n";
    let m = mutants(src, "c.gen", 2, 0);
    let semicolon = m
        .iter()
        .find(|m| m.kind == Kind::MissingSemicolon)
        .expect("a missing-semicolon mutant");
    assert!(
        [
            "line 2:14: deleted `;`",
            "line 3:11: deleted `;`",
            "line 4:2: deleted `;`"
        ]
        .contains(&semicolon.what.as_str()),
        "{}",
        semicolon.what
    );
    let line = semicolon.line;
    assert_eq!(
        semicolon.text.lines().nth(line - 1),
        src.lines()
            .nth(line - 1)
            .map(|l| l.replacen(';', "", 1))
            .as_deref()
    );
}

#[test]
fn genom3_versions_compare_numerically() {
    assert!(version("2.99.41") > version("2.99.39"));
    assert!(version("2.99.100") > version("2.99.41"));
    assert_eq!(
        required_genom3("  require \"genom3 >= 2.99.41\";"),
        Some(vec![2, 99, 41])
    );
    assert_eq!(required_genom3("require \"eigen3\";"), None);
}
