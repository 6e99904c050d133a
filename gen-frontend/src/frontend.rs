//! The LANGUAGE.md front-end behind the one front-end interface
//! ([`genom_model::frontend::Frontend`]): [`crate::lower_until`] on the
//! checked text, and the explanations of the codes this crate raises
//! (syntax, includes, resolution).

use genom_model::Code;
use genom_model::Dialect;
use genom_model::frontend::{Frontend, Input, Loaded, Refused};

use crate::checks::{
    codel_transitions, duplicate_definition, invalid_attribute, missing_component,
    service_structure, type_mismatch, unknown_name,
};
use crate::diagnostics::explain;

/// The front-end of the LANGUAGE.md dialect (the 2004 proposal).
#[derive(Debug, Clone, Copy, Default)]
pub struct GenFrontend;

impl Frontend for GenFrontend {
    fn dialect(&self) -> Dialect {
        Dialect::Gen
    }

    /// The dialect is the default: it recognises nothing of its own.
    fn recognises(&self, _text: &str) -> bool {
        false
    }

    fn load(&self, input: Input<'_>, text: String) -> Result<Loaded, Refused> {
        if input.wcet_file.is_some() {
            return Err(Refused::NoWcetFile);
        }
        let front = crate::lower_until(input.path, text, input.loader, input.watch);
        Ok(Loaded {
            dialect: Dialect::Gen,
            sources: front.sources,
            model: front.model,
            has_component: front.has_component,
            diagnostics: front.diagnostics,
            pragmas: Vec::new(),
            assumptions: Vec::new(),
        })
    }

    fn explanation(&self, code: Code) -> Option<&'static str> {
        explanation(code)
    }
}

/// The explanation of a code this crate raises, from the file that raises
/// it; `None` for the checker's codes and GenoM3's own.
fn explanation(code: Code) -> Option<&'static str> {
    Some(match code {
        Code::Syntax => explain::SYNTAX,
        Code::IncludeNotFound => explain::INCLUDE_NOT_FOUND,
        Code::IncludeCycle => explain::INCLUDE_CYCLE,
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
        _ => return None,
    })
}
