//! Clock zones for the timed engine: difference-bound matrices with the
//! operations of zone-based model checking (see [`dbm`]).

pub mod dbm;

#[cfg(test)]
mod tests;
