//! One test per construct of LANGUAGE.md sections 1 and 2: each parses a
//! small snippet and checks the AST (field values) and the spans of the node
//! and of its names, by the exact text each span covers.
//! One test binary; each file is a module with its own header, and the
//! shared helpers are in `support`.

mod blocks_and_services;
mod codels_and_lexical;
mod declarations;
mod support;
