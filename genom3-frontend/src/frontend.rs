//! The GenoM3 front-end behind the one front-end interface
//! ([`genom_model::frontend::Frontend`]): [`crate::load_watched`] on the
//! checked text with the include folders asked for, then the WCET side
//! file; the explanations of the codes this crate adds.

use genom_model::frontend::{Frontend, Input, Loaded, Refused};
use genom_model::loader::display;
use genom_model::{Assumption, Code, Dialect};

use crate::Genom3Options;

/// The front-end of GenoM3, as LAAS-CNRS's `genom3` reads it.
#[derive(Debug, Clone, Copy, Default)]
pub struct Genom3Frontend;

impl Frontend for Genom3Frontend {
    fn dialect(&self) -> Dialect {
        Dialect::Genom3
    }

    fn recognises(&self, text: &str) -> bool {
        crate::looks_like_genom3(text)
    }

    /// A partial component (a file missing or unparsed) is no model: its
    /// findings would be the cascade of what is missing.
    fn load(&self, input: Input<'_>, text: String) -> Result<Loaded, Refused> {
        let options = Genom3Options {
            include_dirs: input.include_dirs.to_vec(),
            use_env_include_path: input.env_include_path,
            wcet_file: None,
            watch: input.watch,
        };
        let search = options.search_path();
        let mut out = crate::load_watched(input.path, text, &search, input.loader, input.watch);
        let mut assumptions = Vec::new();
        if let Some(path) = input.wcet_file {
            let text = input
                .loader
                .load(path)
                .map_err(|error| Refused::Unreadable {
                    path: path.to_owned(),
                    error,
                })?;
            crate::add_wcet_file(&mut out, path, text);
            assumptions.push(Assumption::wcet(&display(path)));
        }
        let has_component = out.component.is_some();
        let complete = out.is_complete();
        Ok(Loaded {
            dialect: Dialect::Genom3,
            sources: out.sources,
            model: out.component.filter(|_| complete),
            has_component,
            diagnostics: out.diagnostics,
            pragmas: out.pragmas,
            assumptions,
        })
    }

    fn explanation(&self, code: Code) -> Option<&'static str> {
        crate::explain::explanation(code)
    }
}
