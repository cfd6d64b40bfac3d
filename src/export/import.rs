//! Reading engine files back into looks (issue 24): each engine's reader
//! lives beside its writer (`unity.rs`, …); this file finds which one a
//! file is for and holds what they share. A reader returns the look the
//! engine renders from the file (its conventions applied: clamps, defaults
//! of missing fields, version upgrades), the file's own fields as it wrote
//! them (for the editor's Engines readout) and notes on what scatterlab
//! had to assume.

use crate::settings::Preset;
use std::path::{Path, PathBuf};

/// What an importer could not be told by the file.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ImportOptions {
    /// Metres per unit of the file's distances where the file does not
    /// say (`--metres-per-unit`).
    pub metres_per_unit: Option<f64>,
}

/// One look read from an engine file.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedLook {
    /// The look as scatterlab holds it: what the engine renders.
    pub preset: Preset,
    /// The engine's name for what was read ("Unity HDRP diffusion profile").
    pub kind: &'static str,
    /// The file's own fields, as written there (name, value).
    pub fields: Vec<(String, String)>,
    /// What scatterlab assumed or could not hold, one sentence each.
    pub notes: Vec<String>,
}

#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{path}: cannot read: {error}")]
    Read {
        path: PathBuf,
        error: std::io::Error,
    },
    /// A field is missing, malformed or out of range.
    #[error("{path}: {field}: {message}")]
    Field {
        path: PathBuf,
        field: String,
        message: String,
    },
    /// The file as a whole is not what it should be.
    #[error("{path}: {message}")]
    File { path: PathBuf, message: String },
    /// The file is not an engine's profile at all (a README, binary data,
    /// a Unity asset of another kind): a folder's scan skips it, where a
    /// file named on its own is refused.
    #[error("{path}: {message}")]
    NotEngine { path: PathBuf, message: String },
}

impl ImportError {
    pub fn field(path: &Path, field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Field {
            path: path.to_owned(),
            field: one_line(field.into()),
            message: one_line(message.into()),
        }
    }

    pub fn file(path: &Path, message: impl Into<String>) -> Self {
        Self::File {
            path: path.to_owned(),
            message: one_line(message.into()),
        }
    }

    pub fn not_engine(path: &Path, message: impl Into<String>) -> Self {
        Self::NotEngine {
            path: path.to_owned(),
            message: one_line(message.into()),
        }
    }

    /// Whether the file is no engine profile at all (what a folder's scan
    /// skips), rather than a profile that is broken.
    pub fn is_not_engine(&self) -> bool {
        matches!(self, Self::NotEngine { .. })
    }
}

/// A message on one line, whatever text from the file it quotes (the
/// fuzzer found a struct text's newline splitting an error in two).
fn one_line(s: String) -> String {
    if s.chars().any(char::is_control) {
        s.chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect()
    } else {
        s
    }
}

/// The look of a file that holds a Burley profile: albedo A and
/// scattering distance d (mm), the file as its source (not yet
/// validated: each reader names its own field on an error).
pub(crate) fn burley_preset(
    path: &Path,
    name: String,
    description: &str,
    albedo: crate::model::Rgb,
    d_mm: crate::model::Rgb,
    rendering: crate::settings::rendering::RenderingSpec,
) -> Preset {
    use crate::settings::profile::{BurleyShape, BurleySpec};
    Preset {
        name,
        description: description.to_owned(),
        source: path.display().to_string(),
        profile: crate::settings::ProfileSpec::Burley(BurleySpec {
            albedo,
            shape: BurleyShape::ScatteringDistance {
                mm: d_mm,
                multiplier: 1.0,
            },
        }),
        rendering,
        ..Preset::default()
    }
}

/// Engine files are small: anything larger is refused before parsing.
const MAX_BYTES: u64 = 16 << 20;

/// Reads `path` as text: a clear error for a missing, empty, oversized or
/// binary file.
pub(crate) fn read_text(path: &Path) -> Result<String, ImportError> {
    let read = |error| ImportError::Read {
        path: path.to_owned(),
        error,
    };
    let meta = std::fs::metadata(path).map_err(read)?;
    if meta.is_dir() {
        return Err(ImportError::file(path, "is a folder, not a file"));
    }
    if meta.len() == 0 {
        return Err(ImportError::file(path, "0 bytes: the file is empty"));
    }
    if meta.len() > MAX_BYTES {
        return Err(ImportError::file(
            path,
            format!(
                "{} bytes: larger than any engine profile ({} MB at most)",
                meta.len(),
                MAX_BYTES >> 20
            ),
        ));
    }
    let bytes = std::fs::read(path).map_err(read)?;
    String::from_utf8(bytes)
        .map_err(|e| {
            ImportError::not_engine(
                path,
                format!(
                    "not text (invalid UTF-8 at byte {}): not a file scatterlab imports",
                    e.utf8_error().valid_up_to()
                ),
            )
        })
        .map(|t| t.strip_prefix('\u{feff}').map(str::to_owned).unwrap_or(t))
}

/// The kinds of file `import` reads, for messages.
pub const KINDS: &str = "Unity HDRP .asset (diffusion profiles, profile lists, volume profiles), Unreal SubsurfaceProfile text or scatterlab's Unreal .py, MaterialX .mtlx (OpenPBR or Standard Surface), Godot .tres, scatterlab's Blender .py, or a scatterlab preset .ron";

/// Every look in the engine file at `path`.
pub fn import_file(path: &Path, options: &ImportOptions) -> Result<Vec<ImportedLook>, ImportError> {
    let text = read_text(path)?;
    import_text(&text, path, options)
}

/// Every look in `text`, read as the file `path` (its extension and
/// content say which engine wrote it; a Unity list's references are
/// looked for beside it).
pub fn import_text(
    text: &str,
    path: &Path,
    options: &ImportOptions,
) -> Result<Vec<ImportedLook>, ImportError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    // The first target that claims the file reads it (`Target::reader`).
    for format in super::Format::all() {
        if let Some(reader) = &format.target().reader {
            if (reader.claims)(&ext, text) {
                return (reader.read)(text, path, options);
            }
        }
    }
    Err(ImportError::not_engine(
        path,
        format!("not a file scatterlab imports; it reads {KINDS}"),
    ))
}

/// An error message without its leading "path: " (the caller adds it).
pub(super) fn strip_path(message: &str, path: &Path) -> String {
    let prefix = format!("{}: ", path.display());
    message.strip_prefix(&prefix).unwrap_or(message).to_owned()
}

/// sRGB's transfer function, decoding (IEC 61966-2-1): how MaterialX's
/// `srgb_texture` and Godot's material colours become linear.
pub(crate) fn srgb_decode(v: f64) -> f64 {
    crate::model::colour::srgb_to_linear_f64(v)
}

/// A name made safe as a file stem.
pub fn file_stem_of(name: &str) -> String {
    let s: String = name
        .trim()
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    let s = s.trim_matches('_').to_owned();
    let mut out = String::new();
    for c in s.chars() {
        if !(c == '_' && out.ends_with('_')) {
            out.push(c);
        }
    }
    if out.is_empty() {
        "look".into()
    } else {
        out
    }
}
