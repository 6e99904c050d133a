//! The `fiacre` export (being written).

use crate::{ExportError, ExportInput, Exported};

/// Exports the component as `fiacre`.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let _ = input;
    Err(ExportError::Unsupported {
        format: "fiacre",
        reason: "not available yet".to_owned(),
    })
}
