//! Test support: lower a source text into the component model with the
//! front-end (a dev-dependency), for the engines' unit tests.

use std::path::Path;

use genom_model::component::Component;
use genom_parser::MemoryLoader;

/// What the front-end made of a snippet.
pub struct Lowered {
    /// The resolved component, when the snippet parsed and has one.
    pub component: Option<Component>,
}

/// Lowers `src` as `test.gen` with no includes available.
pub fn check(src: &str) -> Lowered {
    let lowered = genom_parser::lower(Path::new("test.gen"), src.to_owned(), &MemoryLoader::new());
    Lowered {
        component: lowered.model.filter(|_| lowered.has_component),
    }
}

/// A valid component header and thread for snippets.
pub const HEADER: &str = "component t { lang: C; }\nthread main { period: 10ms; }\n";
