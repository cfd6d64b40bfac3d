//! The scatterlab preset (RON) as an export target: written exactly, read
//! back exactly.

use super::{
    import::strip_path, no_notes, write, ExportError, ImportError, ImportOptions, ImportedLook,
    Provenance, Reader, Target,
};
use crate::settings::{Preset, PRESET_EXTENSION};
use std::path::Path;

pub(super) const RON: Target = Target {
    id: PRESET_EXTENSION,
    name: "scatterlab preset",
    description: "the look as a .ron preset, exactly",
    extension: PRESET_EXTENSION,
    companion: None,
    slow: false,
    write: write_ron,
    notes: no_notes,
    fidelity: |_| Some(0.0),
    params: None,
    reader: Some(Reader {
        extensions: &[PRESET_EXTENSION],
        claims: |ext, _| ext == PRESET_EXTENSION,
        read: read_ron,
    }),
};

fn write_ron(
    preset: &Preset,
    prov: &Provenance,
    out: &Path,
    _: &Path,
    _: &super::ExportOptions,
) -> Result<(), ExportError> {
    let text = format!("// Exported: {}.\n{}", prov.line(), preset.to_ron());
    write(out, text.as_bytes())
}

fn read_ron(text: &str, path: &Path, _: &ImportOptions) -> Result<Vec<ImportedLook>, ImportError> {
    let preset = Preset::from_ron(text, path)
        .map_err(|e| ImportError::file(path, strip_path(&e.to_string(), path)))?;
    Ok(vec![ImportedLook {
        fields: Vec::new(),
        kind: "scatterlab preset",
        notes: Vec::new(),
        preset,
    }])
}
