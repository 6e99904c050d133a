//! Fuzz target `parse`: the parser on arbitrary UTF-8 text, with a few
//! files available to `include`. It must never panic, every diagnostic
//! label must point inside a loaded file, and rendering must not panic.

#![no_main]

use std::path::Path;

use genom_check_fuzz::{PATH, assert_spans, loader, render};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let out = gen_frontend::parse_source(Path::new(PATH), text.to_owned(), &loader());
    assert_spans(&out.sources, &out.diagnostics);
    let _ = render(&out.sources, &out.diagnostics, None);
});
