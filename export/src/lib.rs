//! Exports of verified models: UPPAAL, Fiacre, TChecker, PNML/TINA, the
//! runtime configuration and diagrams. The formats are added with the
//! exports issue; this crate is part of the workspace layout from the start.
