//! `genom-check explain CODE`: the long explanation of every diagnostic code
//! (what it finds, why it matters, an example), as `rustc --explain` does.
//! Each text lives next to the code that produces the diagnostic: in the
//! front-end (syntax and resolution, [`genom_model::frontend::Frontend`])
//! or in the checker's registry (`genom_checker::checks`).

use genom_model::Code;
use genom_model::dialect::Dialect;

use crate::pipeline::FRONTENDS;

/// The explanation of a code, in Markdown.
pub fn explanation(code: Code) -> String {
    explanation_with(code, body(code))
}

/// The explanation of a code for a user of `dialect`: for GenoM3, the
/// section about GenoM3 components (the paragraphs from the first that
/// begins `GenoM3 `) comes first, in GenoM3's words (tasks, activities,
/// `yield`, WCET files), and the LANGUAGE.md text after it under its own
/// heading; a code without such a section, and LANGUAGE.md, read as
/// [`explanation`].
pub fn explanation_for(code: Code, dialect: Dialect) -> String {
    let body = body(code);
    match (dialect, split_genom3(body)) {
        (Dialect::Genom3, Some((language, genom3))) => explanation_with(
            code,
            &format!(
                "{}\n\n## In the LANGUAGE.md dialect\n\n{}",
                genom3.trim_end(),
                language.trim_end()
            ),
        ),
        _ => explanation_with(code, body),
    }
}

/// `body` split before its first paragraph that begins `GenoM3 `, when it
/// has one after some text of its own.
fn split_genom3(body: &str) -> Option<(&str, &str)> {
    let at = body.match_indices("\n\nGenoM3 ").next()?.0;
    let (language, genom3) = body.split_at(at);
    Some((language, genom3.trim_start())).filter(|(g, _)| !g.trim().is_empty())
}

/// The explanation of a code with the text `body`, in the format of
/// [`explanation`].
pub fn explanation_with(code: Code, body: &str) -> String {
    let header = format!(
        "# `{}` ({})\n\n{}.\n",
        code.as_str(),
        code.severity().as_str(),
        capitalise(code.meaning())
    );
    if body.is_empty() {
        header
    } else {
        format!("{header}\n{}", body.trim_end()) + "\n"
    }
}

/// The explanation text of a code, from whichever owns it: a front-end
/// (syntax, resolution, GenoM3's own codes) or the checker's registry.
fn body(code: Code) -> &'static str {
    owners(code).next().unwrap_or_default()
}

/// The explanations of `code` by every owner: the front-ends', then the
/// checker's (one, for every code: see the tests).
fn owners(code: Code) -> impl Iterator<Item = &'static str> {
    FRONTENDS
        .iter()
        .filter_map(move |f| f.explanation(code))
        .chain(genom_checker::checks::explanation(code))
        .chain(genom_system::explanation(code))
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or_else(String::new, |f| {
        f.to_uppercase().collect::<String>() + c.as_str()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_a_header_with_its_severity() {
        for &code in Code::ALL {
            let text = explanation(code);
            assert!(
                text.starts_with(&format!(
                    "# `{}` ({})",
                    code.as_str(),
                    code.severity().as_str()
                )),
                "{text}"
            );
        }
    }

    /// A code without an owner, or with two, would print no text or an
    /// arbitrary one: a new check's code must be registered with its
    /// explanation (`STATIC_CHECKS`, `VERDICTS`, or a front-end's).
    #[test]
    fn every_code_has_one_owner_and_an_explanation() {
        for &code in Code::ALL {
            let texts: Vec<&str> = owners(code).collect();
            assert_eq!(texts.len(), 1, "`{code}` has {} owners", texts.len());
            assert!(!texts[0].trim().is_empty(), "`{code}` has no explanation");
        }
    }

    #[test]
    fn for_genom3_the_genom3_section_comes_first_and_nothing_is_lost() {
        for code in [Code::CodelOverrun, Code::ThreadOverrun, Code::Incomplete] {
            let text = explanation_for(code, Dialect::Genom3);
            let after_header = text.split_once(".\n\n").map_or("", |(_, b)| b);
            assert!(after_header.starts_with("GenoM3 "), "{code:?}: {text}");
            assert!(text.contains("\n## In the LANGUAGE.md dialect\n"), "{text}");
            // The same paragraphs, reordered.
            let plain = explanation(code);
            let mut a: Vec<&str> = plain.split("\n\n").map(str::trim).collect();
            let mut b: Vec<&str> = text
                .split("\n\n")
                .map(str::trim)
                .filter(|p| !p.starts_with("## In the LANGUAGE.md"))
                .collect();
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b, "{code:?}");
            assert_eq!(explanation_for(code, Dialect::Gen), explanation(code));
        }
        // A code without a GenoM3 section reads the same either way.
        assert_eq!(
            explanation_for(Code::Deadlock, Dialect::Genom3),
            explanation(Code::Deadlock)
        );
    }

    #[test]
    fn syntax_explanation_has_an_example() {
        assert!(explanation(Code::Syntax).contains("```"));
    }
}
