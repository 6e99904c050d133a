//! Fuzz target `check`: the whole pipeline (parse, resolve, static checks,
//! behavioural and timed engines, rendering) on arbitrary UTF-8 text, with
//! small limits so that every input runs fast. It must never panic, and
//! every diagnostic label must point inside a loaded file.

#![no_main]

use std::path::Path;
use std::time::Duration;

use genom_check::CheckOptions;
use genom_check_fuzz::{PATH, assert_spans, loader, render};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let options = CheckOptions::new()
        .max_states(20_000)
        .timeout(Some(Duration::from_millis(200)))
        .max_memory(64 << 20);
    let result = genom_check::check_source(Path::new(PATH), text.to_owned(), &loader(), &options);
    assert_spans(&result.sources, &result.diagnostics);
    let _ = render(
        &result.sources,
        &result.diagnostics,
        result.statistics.as_ref(),
    );
});
