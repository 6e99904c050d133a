//! The exit statuses of the process, shared by the subcommands and the
//! Language Server.

/// No error.
pub const EXIT_OK: u8 = 0;
/// Errors found (or warnings with `--deny warnings`).
pub const EXIT_ERRORS: u8 = 1;
/// Usage or I/O problem.
pub const EXIT_USAGE: u8 = 2;
