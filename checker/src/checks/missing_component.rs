//! `missing-component`: a file with no `component` item.
//!
//! Every description describes exactly one component; without the item there
//! is nothing to verify. (A second `component` item is
//! `duplicate-definition`.)

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain missing-component`.
pub const EXPLANATION: &str = r#"The file has no `component` item. A description file describes exactly one
component: its name, the engine category and the codel language.

Why it matters: services, threads and data belong to a component; without
it the file cannot be verified or exported.

Example:

```
thread motionTask { period: 1s; }      // missing-component: add
component pilot { category: default; lang: C; }
```"#;

/// The file has no `component` item; `start` is the start of the file.
pub fn missing_component(start: Span) -> Diagnostic {
    Diagnostic::new(
        Code::MissingComponent,
        "no `component` item in this file",
        start,
        "the file starts here",
    )
    .with_help("declare the component, e.g. `component pilot { category: default; lang: C; }`")
}

#[cfg(test)]
mod tests {
    use genom_model::{Code, Span};

    use crate::CheckResult;
    use crate::testing;

    /// Every diagnostic of `code` in `src`, as
    /// ``line:col `primary text` + line:col `label text`...: message``.
    fn found(src: &str, code: Code) -> Vec<String> {
        let r = testing::check(src);
        r.diagnostics
            .iter()
            .filter(|d| d.code == code)
            .map(|d| {
                let spans: Vec<String> = d.labels.iter().map(|l| at(&r, l.span)).collect();
                format!("{}: {}", spans.join(" + "), d.message)
            })
            .collect()
    }

    fn at(r: &CheckResult, span: Span) -> String {
        let (line, col) = r
            .sources
            .locate(span)
            .and_then(|l| Some(r.sources.file(l.file)?.line_col(l.offset)))
            .unwrap_or_default();
        format!("{line}:{col} `{}`", r.sources.slice(span))
    }

    const NO_COMPONENT: &str =
        "thread motionTask { period: 1s; }\nids demoIds { double distRef; }\n";

    #[test]
    fn a_file_without_component_is_reported_once_at_its_start() {
        assert_eq!(
            found(NO_COMPONENT, Code::MissingComponent),
            ["1:1 ``: no `component` item in this file"]
        );
    }

    #[test]
    fn an_empty_or_comment_only_file_has_no_component() {
        assert_eq!(testing::count("", Code::MissingComponent), 1);
        assert_eq!(
            testing::count(
                "// nothing yet\n/* still nothing */\n",
                Code::MissingComponent
            ),
            1
        );
    }

    #[test]
    fn a_component_anywhere_in_the_file_is_enough() {
        let src = format!("{NO_COMPONENT}component pilot {{ lang: C; }}\n");
        assert_eq!(testing::count(&src, Code::MissingComponent), 0);
        assert!(
            testing::codes(&src).is_empty(),
            "{:?}",
            testing::codes(&src)
        );
    }

    #[test]
    fn a_file_with_syntax_errors_is_not_checked_for_its_component() {
        let src = "thread motionTask { period 1s; }\n";
        assert_eq!(testing::codes(src), [Code::Syntax]);
    }

    #[test]
    fn snapshot() {
        insta::assert_snapshot!(testing::render(NO_COMPONENT));
    }
}
