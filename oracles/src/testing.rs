//! Test support: lower snippets with the front-ends (dev-dependencies)
//! into the component model the oracles read.

use std::path::Path;

use gen_frontend::MemoryLoader;
use genom_model::component::Component;

/// A valid LANGUAGE.md component header and thread for snippets.
pub const HEADER: &str = "component t { lang: C; }\nthread main { period: 10ms; }\n";

/// The component of LANGUAGE.md text `src` (as `test.gen`, no includes),
/// when it parses and resolves.
pub fn check(src: &str) -> Option<Component> {
    let lowered = gen_frontend::lower(Path::new("test.gen"), src.to_owned(), &MemoryLoader::new());
    lowered.model.filter(|_| lowered.has_component)
}

/// Loads GenoM3 text as `t.gen`; panics on any error, as a test fixture
/// must be valid.
pub fn load_genom3(text: &str) -> Component {
    load(text, None)
}

/// [`load_genom3`] with a WCET side file (`t.wcet`); panics on any error.
pub fn load_genom3_wcet(text: &str, wcet: &str) -> Component {
    load(text, Some(wcet))
}

fn load(text: &str, wcet: Option<&str>) -> Component {
    genom3_frontend::load_clean(text, wcet).unwrap_or_else(|e| panic!("{e}"))
}
