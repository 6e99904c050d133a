//! House rules of the workspace's source (issue 29, docs/architecture.md):
//! no import cycle between files, and no source file much over 800 lines.
//!
//! The cycle check reads every crate's module tree from its roots
//! (`src/lib.rs`, `src/main.rs`, `src/bin/*`), following `mod x;` and
//! inline `mod x { … }` (leaving out whatever `#[cfg(test)]` marks). It
//! resolves the `crate::…`, `super::…`, `self::…` paths of `use` items and
//! of code (not of comments or string literals) to the file of the longest
//! module prefix. A name that a module only imports (`pub use
//! child::Item`) is followed to the file that defines it: a re-export is
//! no dependency on the file that re-exports. Each resolved path is an
//! edge between two files; every strongly connected set of files is a
//! failure. A path from a child module's bare name (`child::f()` in its
//! parent) is no edge: it serves only to follow re-exports.
//!
//! The detector is in `support`, the checks of the workspace in
//! `workspace`, and the detector's own tests in `detector`.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

mod detector;
mod support;
mod workspace;
