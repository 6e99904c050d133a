//! `genom-check explain CODE`: the long explanation of every diagnostic code
//! (what it finds, why it matters, an example), as `rustc --explain` does.
//! Each text lives next to the code that produces the diagnostic: in the
//! front-end (syntax and resolution) or in the checker.

use genom_model::Code;

/// The explanation of a code, in Markdown.
pub fn explanation(code: Code) -> String {
    explanation_with(code, body(code))
}

/// The explanation of a code whose text lives in another front-end (the
/// GenoM3 codes: `genom_genom3::explain`), in the same format.
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

/// The explanation text of each code, from the file that produces it.
fn body(code: Code) -> &'static str {
    use genom_checker::checks::*;
    use genom_parser::checks::*;
    use genom_parser::diagnostics::explain as parser;
    match code {
        Code::Syntax => parser::SYNTAX,
        Code::IncludeNotFound => parser::INCLUDE_NOT_FOUND,
        Code::IncludeCycle => parser::INCLUDE_CYCLE,
        Code::MissingComponent => missing_component::EXPLANATION,
        Code::DuplicateDefinition => duplicate_definition::EXPLANATION,
        Code::UnknownType
        | Code::UnknownData
        | Code::UnknownThread
        | Code::UnknownService
        | Code::UnknownCodel
        | Code::UnknownReport
        | Code::UnknownCredential => unknown_name::EXPLANATION,
        Code::InvalidAttribute => invalid_attribute::EXPLANATION,
        Code::MissingStart => service_structure::EXPLANATION_MISSING_START,
        Code::MissingThread => service_structure::EXPLANATION_MISSING_THREAD,
        Code::MultipleInit => service_structure::EXPLANATION_MULTIPLE_INIT,
        Code::DuplicateCodelKind => service_structure::EXPLANATION_DUPLICATE_CODEL_KIND,
        Code::BadNext => codel_transitions::EXPLANATION_BAD_NEXT,
        Code::BadOnInter => codel_transitions::EXPLANATION_BAD_ON_INTER,
        Code::AmbiguousName => codel_transitions::EXPLANATION_AMBIGUOUS_NAME,
        Code::TypeMismatch => type_mismatch::EXPLANATION,
        Code::PrototypeMismatch => prototype_mismatch::EXPLANATION,
        Code::UpdateNotArgument => update_rules::EXPLANATION_NOT_ARGUMENT,
        Code::ConstUpdate => update_rules::EXPLANATION_CONST,
        Code::UnreachableCodel => unreachable_codel::EXPLANATION,
        Code::NoTermination => no_termination::EXPLANATION,
        Code::AutoTerminates => auto_terminates::EXPLANATION,
        Code::UnusedReport => unused_report::EXPLANATION,
        Code::MissingOnInter => missing_on_inter::EXPLANATION,
        Code::PrivilegeEscalation => privilege_escalation::EXPLANATION,
        Code::RecursiveType => recursive_type::EXPLANATION,
        Code::Deadlock => deadlock::EXPLANATION,
        Code::Starvation => starvation::EXPLANATION,
        Code::DeadService => dead_service::EXPLANATION,
        Code::UnboundedInterrupt => unbounded_interrupt::EXPLANATION,
        Code::Incomplete => incomplete::EXPLANATION,
        Code::CodelOverrun => codel_overrun::EXPLANATION,
        Code::ThreadOverrun => thread_overrun::EXPLANATION,
        Code::MaxTimeInfeasible => max_time::EXPLANATION_INFEASIBLE,
        Code::MaxTimeExceeded => max_time::EXPLANATION_EXCEEDED,
        Code::MaxTimeWatchdog => max_time::EXPLANATION_WATCHDOG,
        Code::DeadlineMiss => response_time::EXPLANATION,
        Code::MissingWcet => missing_wcet::EXPLANATION,
        Code::Livelock => livelock::EXPLANATION_LIVELOCK,
        Code::UnpausedLoop => livelock::EXPLANATION_UNPAUSED_LOOP,
        // The GenoM3 front-end's codes: their texts are in
        // `genom_genom3::explain` (the CLI asks it first).
        Code::IgnoredDirective
        | Code::UnknownState
        | Code::UnreachableState
        | Code::StopNoEther
        | Code::AsyncSharedData
        | Code::MissingSource
        | Code::UnknownInterface
        | Code::BadWcet => "",
    }
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

    #[test]
    fn syntax_explanation_has_an_example() {
        assert!(explanation(Code::Syntax).contains("```"));
    }
}
