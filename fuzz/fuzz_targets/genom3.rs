//! Fuzz target `genom3`: the GenoM3 front-end (preprocessor, parser,
//! lowering into the model) and the static checks on arbitrary UTF-8 text,
//! with interface files available to `#include` (`interface.gen`, two
//! files `left.gen` and `right.gen` that both include it, a diamond, a
//! self-including `self.gen`, a broken `bad.idl`). Seeded with the real
//! components of the GenoM3 corpus and the front-end's fixtures, which
//! libFuzzer mutates. It must never panic, every label must point inside a
//! loaded file, and both renderers must not panic.

#![no_main]

use std::path::Path;
use std::time::Instant;

use genom_check::CheckOptions;
use genom_check_fuzz::{PATH, assert_spans, render};
use genom3_frontend::MemoryLoader;
use libfuzzer_sys::fuzz_target;

fn loader() -> MemoryLoader {
    MemoryLoader::new()
        .with(
            "interface.gen",
            "#ifndef IF\n#define IF\ninterface i {\n  ids { double x; };\n  \
             function f(in double v) { doc \"set\"; };\n};\n#endif\n",
        )
        .with(
            "left.gen",
            "#include \"interface.gen\"\nconst long L = 1;\n",
        )
        .with(
            "right.gen",
            "#include \"interface.gen\"\nconst long R = 2;\n",
        )
        .with("self.gen", "#include \"self.gen\"\n")
        .with("bad.idl", "struct s { double x; \n")
}

fuzz_target!(|text: &str| {
    let out = genom3_frontend::load_with(Path::new(PATH), text.to_owned(), &[], &loader());
    assert_spans(&out.sources, &out.diagnostics);
    let complete = out.is_complete();
    let has_component = out.component.is_some();
    let model = out.component.filter(|_| complete);
    let options = CheckOptions::new().behaviour(false);
    let verdicts = genom_checker::verify(
        model,
        has_component,
        out.diagnostics,
        &options,
        Instant::now(),
    );
    assert_spans(&out.sources, &verdicts.diagnostics);
    let _ = render(&out.sources, &verdicts.diagnostics, None);
});
