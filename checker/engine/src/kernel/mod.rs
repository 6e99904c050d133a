//! The analysis kernel every semantics uses: the explorer over a
//! [`explore::Model`] (breadth-first, limits that end in an incomplete
//! result, the hooks of partial-order reduction and early stop), the
//! store of explored states ([`store`]: packed words, zones kept once,
//! counterexample paths) and the partition of a component into parts
//! explored apart ([`parts`]), and the symbolic method: the same
//! breadth-first reachability with its sets of states as BDDs ([`sets`]). A semantics (the LANGUAGE.md engine in
//! [`crate::dialect`], GenoM3's in [`crate::genom3`]) gives its step rules
//! and its interference links; the kernel knows neither language.

pub mod explore;
pub mod method;
pub mod parts;
pub mod sets;
pub mod store;

pub use explore::{Limits, Stop};
