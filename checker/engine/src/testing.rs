//! Test support: lower a source text into the component model with the
//! front-end (a dev-dependency), for the engines' unit tests.

use std::path::Path;

use gen_frontend::MemoryLoader;
use genom_model::component::Component;

/// What the front-end made of a snippet.
pub struct Lowered {
    /// The resolved component, when the snippet parsed and has one.
    pub component: Option<Component>,
}

/// Lowers `src` as `test.gen` with no includes available.
pub fn check(src: &str) -> Lowered {
    let lowered = gen_frontend::lower(Path::new("test.gen"), src.to_owned(), &MemoryLoader::new());
    Lowered {
        component: lowered.model.filter(|_| lowered.has_component),
    }
}

/// A generated component (`init` and one auto service): seed, services,
/// codels per service, threads, rules per service and the share of
/// services that stop themselves.
pub fn generated(
    (seed, services, codels, threads, density): (u64, usize, usize, usize, f64),
    self_stops: f64,
) -> Component {
    let text = genom_generate::generate(&genom_generate::GeneratorConfig {
        codels_per_service: codels,
        threads,
        rule_density: density,
        init: true,
        autos: 1,
        self_stops,
        ..genom_generate::GeneratorConfig::new(seed, services)
    });
    check(&text)
        .component
        .unwrap_or_else(|| panic!("generated component {seed} resolves"))
}

/// A valid component header and thread for snippets.
pub const HEADER: &str = "component t { lang: C; }\nthread main { period: 10ms; }\n";

/// Loads GenoM3 text as `t.gen` (no include path from the environment);
/// panics on any error, as a test fixture must be valid.
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
