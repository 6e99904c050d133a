//! Differential test of the GenoM3 front-end against the real GenoM3
//! parser: `genom3 -n` (parse and check only) and
//! `genom-check --dialect genom3 --static-only` must accept and reject the
//! same files, the GenoM3 corpus (`../shared/corpus/genom3`) and mutants
//! of it (a token deleted, duplicated or swapped with the next, a missing
//! `;`, a keyword or a parameter direction replaced by another, a name
//! misspelt, a bracket deleted).
//!
//! The comparison needs the `genom3` executable, so it is ignored by a plain
//! `cargo test`; docs/testing/genom3.md says how to build `genom3` and run
//! it:
//!
//! ```sh
//! GENOM3=/path/to/bin/genom3 cargo test --test genom3 genom3_diff:: -- --ignored --nocapture
//! ```
//!
//! Both tools read each file with `-I <the corpus folder of the file>` and
//! `-I tests/fixtures/genom3/include` (the interface stubs). `genom3` runs
//! with `PKG_CONFIG=true`, so that its `#pragma require` lines succeed
//! without the packages installed (the stubs stand in for them).
//!
//! Accept is exit status 0 for both tools. A `genom3` crash or timeout
//! leaves the file out of the comparison (listed); a `genom-check` crash,
//! timeout or exit status other than 0, 1 or 2 is a failure. A corpus file
//! whose `require "genom3 >= V"` is newer than the `genom3` under test is
//! left out (listed), with its mutants.
//!
//! Other variables:
//!
//! - `GENOM3_CORPUS`: the corpus folder (default `../shared/corpus/genom3`
//!   from the workspace root);
//! - `GENOM3_MUTANTS_PER_KIND`: mutants of each kind per corpus file
//!   (default 2: 8 kinds, 19 files, 304 mutants);
//! - `GENOM3_SEED`: changes every mutant (default 0);
//! - `GENOM3_SHOW`: disagreements printed with their whole mutated file
//!   (default 3; the others print the lines around the mutation);
//! - `GENOM3_KEEP`: a folder that keeps every mutant (by default they are
//!   written to a temporary folder, kept when the tools disagree).
//!
//! The mutator itself (deterministic, distinct mutants that never touch
//! comments or preprocessor lines) is checked by the ordinary tests in
//! `mutator`. The mutator, the runs of both tools and the corpus helpers
//! are in `support`; the comparison is in `agreement`.

#![allow(clippy::expect_used, clippy::print_stdout, clippy::print_stderr)] // test harness

mod agreement;
mod mutator;
mod support;
