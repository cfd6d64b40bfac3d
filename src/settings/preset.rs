//! Presets: a look written as commented RON. Loading validates every
//! number and names the field and the file in errors; saving is atomic.

use super::profile::ProfileSpec;
use super::rendering::RenderingSpec;
use crate::model::{ModelError, RadialProfile};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The preset format this build writes. Older versions still load.
/// 1: profile only. 2: adds `rendering`.
pub const FORMAT_VERSION: u32 = 2;

/// The embedded default look (also `presets/skin_default.ron`).
pub const DEFAULT_PRESET_RON: &str = include_str!("../../presets/skin_default.ron");

/// A preset file's extension: the one place the format is named (the
/// editor's dialogs and drops, the browser, the autosave, the library,
/// the export registry).
pub const PRESET_EXTENSION: &str = "ron";

/// Whether `path` names a preset file (by its extension, in any case).
pub fn is_preset_file(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(PRESET_EXTENSION))
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Preset {
    pub format_version: u32,
    pub name: String,
    /// What the look is for.
    pub description: String,
    /// Where the numbers come from (paper, table, engine default).
    pub source: String,
    pub profile: ProfileSpec,
    /// Method, quality and engine-side material settings (format 2; files
    /// without it take the defaults).
    pub rendering: RenderingSpec,
}

impl Default for Preset {
    fn default() -> Self {
        Self {
            format_version: FORMAT_VERSION,
            name: "Untitled".into(),
            description: String::new(),
            source: String::new(),
            profile: ProfileSpec::default(),
            rendering: RenderingSpec::default(),
        }
    }
}

/// Why a preset could not be loaded or saved. Each names the file.
#[derive(Debug, thiserror::Error)]
pub enum PresetError {
    #[error("{path}: cannot read: {error}")]
    Read {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{path}: cannot write: {error}")]
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{path}: not a valid preset: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: {error}")]
    Invalid { path: PathBuf, error: ModelError },
    #[error("{path}: format_version {found} is newer than this scatterlab understands ({FORMAT_VERSION})")]
    TooNew { path: PathBuf, found: u32 },
}

impl Preset {
    /// The embedded default skin look.
    pub fn default_skin() -> Self {
        // The embedded file is tested to parse and validate.
        Self::from_ron(DEFAULT_PRESET_RON, Path::new("<embedded default preset>"))
            .unwrap_or_default()
    }

    /// Parses and validates RON; `origin` names the source in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, PresetError> {
        let preset: Preset = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .from_str(text)
            .map_err(|e| PresetError::Parse {
                path: origin.to_owned(),
                message: e.to_string(),
            })?;
        if preset.format_version > FORMAT_VERSION {
            return Err(PresetError::TooNew {
                path: origin.to_owned(),
                found: preset.format_version,
            });
        }
        preset.validate().map_err(|error| PresetError::Invalid {
            path: origin.to_owned(),
            error,
        })?;
        // Older files are upgraded on load (missing sections took their
        // defaults), so saving writes the current format.
        let mut preset = preset;
        preset.format_version = FORMAT_VERSION;
        Ok(preset)
    }

    pub fn load(path: &Path) -> Result<Self, PresetError> {
        let text = std::fs::read_to_string(path).map_err(|error| PresetError::Read {
            path: path.to_owned(),
            error,
        })?;
        if text.trim().is_empty() {
            let message = crate::fsutil::too_short(text.len() as u64, u64::MAX, "a preset")
                .unwrap_or_default();
            return Err(PresetError::Parse {
                path: path.to_owned(),
                message: format!("{message}: no preset in it (a RON file starting with '(')"),
            });
        }
        Self::from_ron(&text, path)
    }

    /// Checks every parameter by building the model.
    pub fn validate(&self) -> Result<(), ModelError> {
        self.rendering.validate()?;
        self.profile.build().map(|_| ())
    }

    pub fn build_profile(&self) -> Result<Box<dyn RadialProfile>, ModelError> {
        self.profile.build()
    }

    /// RON text with a header comment (the writer drops other comments).
    pub fn to_ron(&self) -> String {
        let body = ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::new().depth_limit(6))
            .unwrap_or_default();
        format!(
            "// scatterlab preset (format {FORMAT_VERSION}), written by scatterlab {}.\n// Units: distances in mm, coefficients in 1/mm, variances in mm^2, colours linear RGB.\n{body}\n",
            env!("CARGO_PKG_VERSION")
        )
    }

    /// Validates, then writes atomically.
    pub fn save(&self, path: &Path) -> Result<(), PresetError> {
        self.validate().map_err(|error| PresetError::Invalid {
            path: path.to_owned(),
            error,
        })?;
        crate::fsutil::write_atomic(path, self.to_ron().as_bytes()).map_err(|error| {
            PresetError::Write {
                path: path.to_owned(),
                error,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    /// A preset is named by its extension in any case, and only by it (the
    /// editor's drops and the autosave's leftovers go through this).
    #[test]
    fn a_preset_file_is_known_by_its_extension_alone() {
        use std::path::Path;
        assert!(super::is_preset_file(Path::new("/p/skin.ron")));
        assert!(super::is_preset_file(Path::new("SKIN.RON")));
        assert!(!super::is_preset_file(Path::new("skin.ron.bak")));
        assert!(!super::is_preset_file(Path::new("ron")));
        assert!(!super::is_preset_file(Path::new("skin.gltf")));
    }

    use super::*;

    #[test]
    fn embedded_default_parses_and_round_trips() {
        let p = Preset::from_ron(DEFAULT_PRESET_RON, Path::new("default")).unwrap();
        assert_eq!(p.profile.model_name(), "burley");
        let again = Preset::from_ron(&p.to_ron(), Path::new("again")).unwrap();
        assert_eq!(p, again);
    }

    /// Fields a file leaves out take their defaults (older files still load).
    #[test]
    fn missing_fields_take_defaults() {
        let p = Preset::from_ron("(name: \"old\")", Path::new("old.ron")).unwrap();
        assert_eq!(p.profile, ProfileSpec::default());
        assert_eq!(p.format_version, FORMAT_VERSION);
    }

    /// A format-1 file (no `rendering`) loads with the default rendering
    /// settings and is written back as the current format.
    #[test]
    fn format_1_files_load_and_upgrade() {
        let v1 = "(format_version: 1, name: \"v1\", profile: Jimenez2012((strength: (0.48, 0.41, 0.28), falloff: (1.0, 0.37, 0.3))))";
        let p = Preset::from_ron(v1, Path::new("v1.ron")).unwrap();
        assert_eq!(p.rendering, RenderingSpec::default());
        assert_eq!(p.format_version, FORMAT_VERSION);
        assert!(p
            .to_ron()
            .contains(&format!("format_version: {FORMAT_VERSION}")));
    }

    #[test]
    fn errors_name_field_and_file() {
        let nan = "(profile: Burley((albedo: (0.5, NaN, 0.5))))";
        let e = Preset::from_ron(nan, Path::new("bad.ron"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("bad.ron") && e.contains("profile.albedo.g"),
            "{e}"
        );
        let neg = "(profile: Dipole((sigma_a_per_mm: (-1, 0, 0))))";
        let e = Preset::from_ron(neg, Path::new("neg.ron"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("profile.sigma_a_per_mm.r"), "{e}");
        let typo = "(profil: Burley(()))";
        let e = Preset::from_ron(typo, Path::new("typo.ron"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("typo.ron") && e.contains("profil"), "{e}");
        let e = Preset::from_ron("(format_version: 99)", Path::new("new.ron"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("newer"), "{e}");
        let e = Preset::load(Path::new("/definitely/not/here.ron"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/definitely/not/here.ron"), "{e}");
    }
}
