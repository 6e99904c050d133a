//! The `promela` export (being written).

use crate::{ExportError, ExportInput, Exported};

/// Exports the component as `promela`.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let _ = input;
    Err(ExportError::Unsupported {
        format: "promela",
        reason: "not available yet".to_owned(),
    })
}
