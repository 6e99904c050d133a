//! The `uppaal` export (being written).

use crate::{ExportError, ExportInput, Exported};

/// Exports the component as `uppaal`.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let _ = input;
    Err(ExportError::Unsupported {
        format: "uppaal",
        reason: "not available yet".to_owned(),
    })
}
