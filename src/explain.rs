//! `genom-check explain CODE`: the long explanation of every diagnostic code
//! (what it finds, why it matters, an example), as `rustc --explain` does.
//! Each text lives next to the code that produces the diagnostic: in the
//! front-end (syntax and resolution, [`genom_model::frontend::Frontend`])
//! or in the checker's registry (`genom_checker::checks`).

use genom_model::Code;

use crate::pipeline::FRONTENDS;

/// The explanation of a code, in Markdown.
pub fn explanation(code: Code) -> String {
    explanation_with(code, body(code))
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
    fn syntax_explanation_has_an_example() {
        assert!(explanation(Code::Syntax).contains("```"));
    }
}
