//! The `svg` export (being written).

use crate::{ExportError, ExportInput, Exported};

/// Exports the component as `svg`.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let _ = input;
    Err(ExportError::Unsupported {
        format: "svg",
        reason: "not available yet".to_owned(),
    })
}
