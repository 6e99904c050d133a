//! The `tchecker` export (being written).

use crate::{ExportError, ExportInput, Exported};

/// Exports the component as `tchecker`.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let _ = input;
    Err(ExportError::Unsupported {
        format: "tchecker",
        reason: "not available yet".to_owned(),
    })
}
