//! Exports of a look to the engines and tools artists ship on. One file
//! per target family; every file is written atomically (temporary file,
//! then rename) and, where the format has comments or metadata, records the
//! scatterlab version and the source preset.

mod blender;
pub mod frames;
mod gltf;
mod godot;
mod images;
pub mod import;
mod materialx;
mod preset;
mod shaders;
mod unity;
mod unreal;

use crate::model::burley::Burley;
use crate::model::fit::fit_burley;
use crate::model::ModelError;
use crate::settings::{Preset, ProfileSpec};
use std::path::{Path, PathBuf};

pub use blender::blender_python;
pub use gltf::{
    gltf_document, gltf_document_on, gltf_has_volume, gltf_notes, gltf_readings, gltf_volume,
    GltfMesh, GltfOnMesh, GltfVolume, Reading,
};
pub use godot::{
    godot_material, godot_notes, godot_subsurface, GodotSubsurface, GodotTransmittance,
};
pub use images::{rgba_exr_bytes, LUT_LAYOUT, PROFILE_TEXELS, SHADOW_LAYOUT, TRANSMITTANCE_TEXELS};
pub use import::{import_file, import_text, ImportError, ImportOptions, ImportedLook};
pub use materialx::{materialx_document, open_pbr_subsurface, OpenPbrSubsurface};
pub use shaders::{kernel_source, samples_json, ShaderLanguage};
pub use unity::budget as unity_budget;
#[cfg(feature = "gpu")]
pub use unity::budget_run as unity_budget_run;
pub use unity::project as unity_project;
pub use unity::{unity_asset, unity_dual_lobe, UnityDualLobe};
pub use unreal::{
    substrate_mfp_cm, unreal_material_fields, unreal_notes, unreal_python, unreal_struct,
    UnrealMaterialFields,
};

/// Every export target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// The scatterlab preset (RON).
    Ron,
    /// Unity HDRP DiffusionProfileSettings `.asset` (YAML).
    Unity,
    /// Unreal SubsurfaceProfile struct text, plus a `.py` snippet beside it.
    Unreal,
    /// Separable kernel and Burley sample pattern as HLSL arrays.
    Hlsl,
    /// The same as GLSL arrays.
    Glsl,
    /// The same as WGSL arrays.
    Wgsl,
    /// Burley sample pattern: radius (mm), angle, per-channel weight.
    SamplesJson,
    /// Pre-integrated table (PNG) and the shadow table beside it.
    LutPng,
    /// The same tables as float OpenEXR.
    LutExr,
    /// r·R(r) as a 1D float texture, and the transmittance strip beside it.
    ProfileExr,
    /// The same as 16-bit PNG, normalised (scale in a text chunk).
    ProfilePng,
    /// Blender Principled BSDF: subsurface radius and scale as a Python snippet.
    Blender,
    /// MaterialX document with an OpenPBR Surface (`open_pbr_surface`).
    Materialx,
    /// Godot 4 StandardMaterial3D `.tres` (width and transmittance fitted).
    Godot,
    /// glTF 2.0 `.gltf` on the head or a sphere: KHR_materials_volume and
    /// KHR_materials_diffuse_transmission (plus the draft
    /// KHR_materials_volume_scatter with `--gltf-volume-scatter`).
    Gltf,
}

/// One export target, declared once, in its engine's module: everything
/// the Export menu, the command line, [`planned_paths`], [`export`],
/// [`export_notes`], `convert` and the importer know of it.
pub struct Target {
    /// The command-line name (`--format`); `targets_match_the_command_line`
    /// checks it against clap's.
    pub id: &'static str,
    /// The name an artist knows the target by (the Export menu, dialogs).
    pub name: &'static str,
    /// What the export writes, in one line (the Export menu's second line).
    pub description: &'static str,
    /// The extension an exported file gets by default.
    pub extension: &'static str,
    /// The second file written beside `out`, if the target has one.
    pub companion: Option<fn(&Path) -> PathBuf>,
    /// Whether the export needs the slow table bakes (off the UI thread).
    pub slow: bool,
    /// Writes the look to `out` and to the companion path (the second
    /// argument; `out` again for a target without one), with the options
    /// that only some targets take.
    pub write: fn(&Preset, &Provenance, &Path, &Path, &ExportOptions) -> Result<(), ExportError>,
    /// What the target will not hold exactly, one sentence each.
    pub notes: fn(&Preset) -> Result<Vec<String>, ModelError>,
    /// How far what the engine draws is from the look: the relative L2
    /// error of r·R(r) (a Burley fit, Godot's kernel), where known.
    pub fidelity: fn(&Preset) -> Option<f64>,
    /// The engine's parameters for a Burley profile as JSON, units in the
    /// keys (`convert --to` without files), given the world scale.
    pub params: Option<EngineParams>,
    /// Reads a file of this target back, if scatterlab can.
    pub reader: Option<Reader>,
}

/// A target's engine parameters of a Burley profile, given the world
/// scale (metres per unit; the engine's default when `None`).
pub type EngineParams = fn(&Burley, Option<f64>) -> Result<serde_json::Value, ModelError>;

/// How the importer finds and reads a target's files.
pub struct Reader {
    /// The extensions its files have (lower case, no dot): what the file
    /// dialogs list, dropped files are told by, and `convert` picks from a
    /// folder (`importable_extensions`).
    pub extensions: &'static [&'static str],
    /// Whether a file with this (lower-case) extension and text is one.
    pub claims: fn(&str, &str) -> bool,
    pub read: fn(&str, &Path, &ImportOptions) -> Result<Vec<ImportedLook>, ImportError>,
}

/// The extensions the importer reads (lower case, no dot, each once), in
/// the targets' order: with `presets`, scatterlab's own `.ron` too; without,
/// the engines' files alone.
pub fn importable_extensions(presets: bool) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for &f in Format::all() {
        if f == Format::Ron && !presets {
            continue;
        }
        for ext in f.target().reader.iter().flat_map(|r| r.extensions) {
            if !out.contains(ext) {
                out.push(ext);
            }
        }
    }
    out
}

/// The engines whose files the importer reads, with their extensions, for
/// titles and messages: "Unity HDRP diffusion profile .asset, …".
pub fn importable_kinds() -> String {
    Format::all()
        .iter()
        .filter(|f| **f != Format::Ron)
        .filter_map(|f| {
            let t = f.target();
            t.reader
                .as_ref()
                .map(|r| format!("{} .{}", t.name, r.extensions.join("/.")))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

impl Format {
    /// Every target, in the Export menu's order (clap's list of the enum).
    pub fn all() -> &'static [Format] {
        <Format as clap::ValueEnum>::value_variants()
    }

    /// The target's declaration.
    pub fn target(self) -> &'static Target {
        match self {
            Format::Ron => &preset::RON,
            Format::Unity => &unity::TARGET,
            Format::Unreal => &unreal::TARGET,
            Format::Hlsl => &shaders::HLSL,
            Format::Glsl => &shaders::GLSL,
            Format::Wgsl => &shaders::WGSL,
            Format::SamplesJson => &shaders::SAMPLES_JSON,
            Format::LutPng => &images::LUT_PNG,
            Format::LutExr => &images::LUT_EXR,
            Format::ProfileExr => &images::PROFILE_EXR,
            Format::ProfilePng => &images::PROFILE_PNG,
            Format::Blender => &blender::TARGET,
            Format::Materialx => &materialx::TARGET,
            Format::Godot => &godot::TARGET,
            Format::Gltf => &gltf::TARGET,
        }
    }

    /// The command-line name (`--format`).
    pub fn id(self) -> &'static str {
        self.target().id
    }

    /// The name an artist knows the target by.
    pub fn name(self) -> &'static str {
        self.target().name
    }

    /// What the export writes, in one line.
    pub fn description(self) -> &'static str {
        self.target().description
    }

    /// The file extension an exported file gets by default.
    pub fn extension(self) -> &'static str {
        self.target().extension
    }

    /// Whether the export needs the slow table bakes (run off the UI thread).
    pub fn is_slow(self) -> bool {
        self.target().slow
    }
}

/// The export-dialog note on a look that reaches an engine through a
/// Burley fit (or exactly).
pub(crate) fn burley_note(preset: &Preset) -> Result<String, ModelError> {
    let (_, e) = burley_of(&preset.profile)?;
    Ok(if e > 0.0 {
        format!(
            "The look reaches the engine through a Burley fit: relative L2 error of r·R(r) {e:.4}."
        )
    } else {
        "The Burley profile goes across exactly.".into()
    })
}

/// `fidelity` of a target that holds the look's Burley fit.
pub(crate) fn burley_fidelity(preset: &Preset) -> Option<f64> {
    burley_of(&preset.profile).ok().map(|(_, e)| e)
}

/// `notes` of a target that holds the look exactly.
pub(crate) fn no_notes(_: &Preset) -> Result<Vec<String>, ModelError> {
    Ok(Vec::new())
}

/// `fidelity` of a target that is no engine's material (tables, code).
pub(crate) fn no_fidelity(_: &Preset) -> Option<f64> {
    None
}

#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("{path}: cannot write: {error}")]
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{path}: {message}")]
    Encode { path: PathBuf, message: String },
    #[error("{0}")]
    Model(#[from] ModelError),
}

/// What the header comment of an export says about where it came from.
#[derive(Debug, Clone)]
pub struct Provenance {
    /// The preset's file (or "unsaved").
    pub source: String,
    pub preset_name: String,
}

impl Provenance {
    pub fn new(preset: &Preset, source: Option<&Path>) -> Self {
        Self {
            source: source
                .map(|p| p.display().to_string())
                .unwrap_or_else(|| "unsaved preset".into()),
            preset_name: preset.name.clone(),
        }
    }

    /// One line for a comment: version and source.
    pub fn line(&self) -> String {
        format!(
            "written by scatterlab {} from \"{}\" ({})",
            env!("CARGO_PKG_VERSION"),
            self.preset_name,
            self.source
        )
    }
}

pub(crate) fn fit_note(fit_error: f64) -> String {
    if fit_error > 0.0 {
        format!("converted through a Burley fit (relative L2 error of r*R(r): {fit_error:.4})")
    } else {
        "exact Burley parameters".into()
    }
}

/// An asset name: letters, digits and '_' only.
pub(crate) fn asset_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let s = s.trim_matches('_');
    if s.is_empty() {
        "SSS_Profile".into()
    } else {
        format!("SSS_{s}")
    }
}

/// The look's Burley parameters: exact for a Burley profile, otherwise a
/// least-squares fit, with the fit's relative L2 error of r·R(r).
pub fn burley_of(profile: &ProfileSpec) -> Result<(Burley, f64), ModelError> {
    match profile {
        ProfileSpec::Burley(b) => Ok((b.build()?, 0.0)),
        other => {
            let p = other.build()?;
            let f = fit_burley(p.as_ref())?;
            let e = f.max_error();
            Ok((f.model, e))
        }
    }
}

/// What the target will not hold exactly, one sentence each, for the export
/// dialog (the files' comments say the same): the relative L2 error of
/// r·R(r) when the look reaches the engine through a Burley fit, values an
/// engine clamps, and fields a target cannot express. Fits run here, so
/// call it off the UI thread.
pub fn export_notes(preset: &Preset, format: Format) -> Result<Vec<String>, ModelError> {
    (format.target().notes)(preset)
}

/// Path of a companion file: `out` with `suffix` added to its stem and `ext`.
pub fn companion(out: &Path, suffix: &str, ext: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "export".into());
    out.with_file_name(format!("{stem}{suffix}.{ext}"))
}

pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    crate::fsutil::write_atomic(path, bytes).map_err(|error| ExportError::Write {
        path: path.to_owned(),
        error,
    })
}

/// Every file [`export`] writes for `format` at `out`: `out`, then its
/// companion if the format has one (Unreal's Python, the shadow table, the
/// transmittance strip). The editor asks before replacing any of them.
pub fn planned_paths(format: Format, out: &Path) -> Vec<PathBuf> {
    std::iter::once(out.to_owned())
        .chain(format.target().companion.map(|c| c(out)))
        .collect()
}

/// Choices that only some targets take; each target reads its own and
/// ignores the rest.
#[derive(Debug, Clone, Default)]
pub struct ExportOptions {
    /// glTF: the mesh the material is put on.
    pub gltf_mesh: GltfMesh,
    /// glTF: the mesh on the editor's screen instead, with its maps (its
    /// colour map as the base colour's texture, as the look draws it, and
    /// its normal map).
    pub gltf_on_mesh: Option<GltfOnMesh>,
    /// glTF: also write the draft `KHR_materials_volume_scatter`.
    pub gltf_volume_scatter: bool,
    /// Unreal: the Substrate Slab of type Diffusion with its own mean free
    /// path (`SSS MFP`, cm) instead of the SubsurfaceProfile.
    pub unreal_substrate_diffusion: bool,
}

/// The file name an export of the look named `stem` proposes: `stem.ext`,
/// or `stem_<format id>.ext` where another format writes a file of the
/// same extension (Unreal's `.py` beside Blender's, the two PNG and the
/// two EXR targets), so no two formats' files of one look collide.
pub fn export_file_name(stem: &str, format: Format) -> String {
    let exts = |f: Format| -> Vec<String> {
        planned_paths(f, Path::new(&format!("x.{}", f.extension())))
            .iter()
            .filter_map(|p| p.extension().map(|e| e.to_string_lossy().into_owned()))
            .collect()
    };
    let mine = exts(format);
    let shared = Format::all()
        .iter()
        .filter(|&&f| f != format)
        .any(|&f| exts(f).iter().any(|e| mine.contains(e)));
    if shared {
        format!("{stem}_{}.{}", format.id(), format.extension())
    } else {
        format!("{stem}.{}", format.extension())
    }
}

/// Writes `preset` in `format` to `out` (and any companion files) with the
/// default options; returns every path written. `source` is the preset's
/// file, for the header.
pub fn export(
    preset: &Preset,
    source: Option<&Path>,
    format: Format,
    out: &Path,
) -> Result<Vec<PathBuf>, ExportError> {
    export_with(preset, source, format, out, &ExportOptions::default())
}

/// [`export`] with the targets' options.
pub fn export_with(
    preset: &Preset,
    source: Option<&Path>,
    format: Format,
    out: &Path,
    options: &ExportOptions,
) -> Result<Vec<PathBuf>, ExportError> {
    preset.validate()?;
    let prov = Provenance::new(preset, source);
    let written = planned_paths(format, out);
    // The companion file, where the format has one.
    let second = written.get(1).cloned().unwrap_or_else(|| out.to_owned());
    (format.target().write)(preset, &prov, out, &second, options)?;
    Ok(written)
}

#[cfg(test)]
mod target_tests {
    use super::*;

    /// Each target's id is clap's name for its `Format` variant (the
    /// command line and the descriptor cannot drift apart), ids and names
    /// are unique, the first planned path is the one asked for and a
    /// companion never is it (Unreal's text given a .py name keeps its
    /// script apart).
    /// A reader lists the extension its target exports with (what we
    /// write, we read back from the same dialog), and the importable
    /// extensions are the readers' (the engines' without the preset's own
    /// `.ron`), each once: what the Import and Compare dialogs, dropped
    /// files and `convert` on a folder take.
    #[test]
    fn importable_extensions_come_from_the_readers() {
        for &f in Format::all() {
            if let Some(r) = &f.target().reader {
                assert!(r.extensions.contains(&f.extension()), "{}", f.id());
                assert!(r.extensions.iter().all(|e| *e == e.to_ascii_lowercase()));
            }
        }
        let all = importable_extensions(true);
        let engines = importable_extensions(false);
        assert!(all.contains(&"ron") && !engines.contains(&"ron"));
        assert_eq!(all.len(), engines.len() + 1);
        let mut unique = all.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), all.len(), "{all:?}");
        // Today's readers (typed here): Unity, Unreal text and script,
        // MaterialX, Godot, Blender's script.
        for ext in ["asset", "txt", "py", "mtlx", "tres"] {
            assert!(engines.contains(&ext), "{ext} in {engines:?}");
        }
        let kinds = importable_kinds();
        assert!(
            kinds.contains("Unreal subsurface profile .txt/.py"),
            "{kinds}"
        );
    }

    /// Every format's proposed files for one look are distinct from every
    /// other format's (issue 41: the Blender export proposed the `.py` the
    /// Unreal export had just written): Unreal's `look_unreal.txt` and
    /// `look_unreal.py`, Blender's `look_blender.py`.
    #[test]
    fn export_names_never_collide_across_formats() {
        let mut seen: Vec<(PathBuf, Format)> = Vec::new();
        for &f in Format::all() {
            let out = PathBuf::from(export_file_name("look", f));
            for p in planned_paths(f, &out) {
                if let Some((_, g)) = seen.iter().find(|(q, _)| *q == p) {
                    panic!("{} and {} both write {}", f.id(), g.id(), p.display());
                }
                seen.push((p, f));
            }
        }
        assert_eq!(export_file_name("look", Format::Blender), "look_blender.py");
        assert_eq!(export_file_name("look", Format::Unreal), "look_unreal.txt");
        assert_eq!(export_file_name("look", Format::Unity), "look.asset");
    }

    #[test]
    fn targets_match_the_command_line() {
        use clap::ValueEnum;
        let mut ids = std::collections::HashSet::new();
        let mut names = std::collections::HashSet::new();
        for &f in Format::all() {
            let clap_name = f.to_possible_value().map(|v| v.get_name().to_owned());
            assert_eq!(clap_name.as_deref(), Some(f.id()));
            assert!(ids.insert(f.id()), "{} twice", f.id());
            assert!(names.insert(f.name()), "{} twice", f.name());
            let out = Path::new("exports").join(format!("look.{}", f.extension()));
            let planned = planned_paths(f, &out);
            assert_eq!(planned[0], out);
            assert!(planned[1..].iter().all(|p| *p != out), "{planned:?}");
        }
        assert_eq!(
            planned_paths(Format::Unreal, Path::new("a/look.py")),
            vec![
                PathBuf::from("a/look.py"),
                PathBuf::from("a/look_unreal.py")
            ]
        );
        assert_eq!(
            planned_paths(Format::LutExr, Path::new("a/t.exr"))[1],
            PathBuf::from("a/t_shadow.exr")
        );
    }
}
