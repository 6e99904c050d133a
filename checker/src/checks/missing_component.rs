//! Tests of the `missing_component` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::missing_component`), through the whole check.

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
