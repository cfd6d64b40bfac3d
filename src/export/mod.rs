//! Exports of a look to the engines and tools artists ship on. One file
//! per target family; every file is written atomically (temporary file,
//! then rename) and, where the format has comments or metadata, records the
//! scatterlab version and the source preset.

mod blender;
mod godot;
mod images;
pub mod import;
mod materialx;
mod shaders;
mod unity;
mod unreal;

use crate::model::burley::Burley;
use crate::model::fit::fit_burley;
use crate::model::ModelError;
use crate::settings::{Preset, ProfileSpec};
use std::path::{Path, PathBuf};

pub use blender::blender_python;
pub use godot::{
    godot_material, godot_notes, godot_subsurface, GodotSubsurface, GodotTransmittance,
};
pub use images::{LUT_LAYOUT, PROFILE_TEXELS, SHADOW_LAYOUT, TRANSMITTANCE_TEXELS};
pub use import::{import_file, import_text, ImportError, ImportOptions, ImportedLook};
pub use materialx::{materialx_document, open_pbr_subsurface, OpenPbrSubsurface};
pub use shaders::{kernel_source, samples_json, ShaderLanguage};
pub use unity::{unity_asset, unity_dual_lobe, UnityDualLobe};
pub use unreal::{
    unreal_material_fields, unreal_notes, unreal_python, unreal_struct, UnrealMaterialFields,
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
}

impl Format {
    pub const ALL: [Format; 14] = [
        Format::Ron,
        Format::Unity,
        Format::Unreal,
        Format::Hlsl,
        Format::Glsl,
        Format::Wgsl,
        Format::SamplesJson,
        Format::LutPng,
        Format::LutExr,
        Format::ProfileExr,
        Format::ProfilePng,
        Format::Blender,
        Format::Materialx,
        Format::Godot,
    ];

    /// The command-line name (`--format`).
    pub fn id(self) -> &'static str {
        match self {
            Format::Ron => "ron",
            Format::Unity => "unity",
            Format::Unreal => "unreal",
            Format::Hlsl => "hlsl",
            Format::Glsl => "glsl",
            Format::Wgsl => "wgsl",
            Format::SamplesJson => "samples-json",
            Format::LutPng => "lut-png",
            Format::LutExr => "lut-exr",
            Format::ProfileExr => "profile-exr",
            Format::ProfilePng => "profile-png",
            Format::Blender => "blender",
            Format::Materialx => "materialx",
            Format::Godot => "godot",
        }
    }

    /// The name an artist knows the target by (the editor's Export menu
    /// and dialog; the command line takes [`Format::id`]).
    pub fn name(self) -> &'static str {
        match self {
            Format::Ron => "scatterlab preset",
            Format::Unity => "Unity HDRP diffusion profile",
            Format::Unreal => "Unreal subsurface profile",
            Format::Hlsl => "HLSL kernel and samples",
            Format::Glsl => "GLSL kernel and samples",
            Format::Wgsl => "WGSL kernel and samples",
            Format::SamplesJson => "Burley samples (JSON)",
            Format::LutPng => "Pre-integrated tables (PNG)",
            Format::LutExr => "Pre-integrated tables (OpenEXR)",
            Format::ProfileExr => "Profile texture (OpenEXR)",
            Format::ProfilePng => "Profile texture (PNG)",
            Format::Blender => "Blender Principled BSDF",
            Format::Materialx => "MaterialX OpenPBR",
            Format::Godot => "Godot 4 material",
        }
    }

    /// What the export writes, in one line (the Export menu's second line).
    pub fn description(self) -> &'static str {
        match self {
            Format::Ron => "the look as a .ron preset, exactly",
            Format::Unity => {
                "DiffusionProfileSettings .asset (a Burley fit where the look is not Burley)"
            }
            Format::Unreal => "SubsurfaceProfile struct text, and a .py that sets it",
            Format::Hlsl | Format::Glsl | Format::Wgsl => {
                "separable kernel and Burley sample pattern as arrays"
            }
            Format::SamplesJson => "Burley sample pattern: radius (mm), angle, weights",
            Format::LutPng => "pre-integrated and shadow tables, 8-bit (takes a few seconds)",
            Format::LutExr => "pre-integrated and shadow tables, float (takes a few seconds)",
            Format::ProfileExr => "r·R(r) as a 1D float texture, and the transmittance strip",
            Format::ProfilePng => "r·R(r) as a 16-bit texture, and the transmittance strip",
            Format::Blender => "a .py snippet setting subsurface radius, scale and weight",
            Format::Materialx => "an .mtlx document with an open_pbr_surface",
            Format::Godot => "a StandardMaterial3D .tres; its fixed kernel's error is stated",
        }
    }

    /// The file extension an exported file gets by default.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Ron => "ron",
            Format::Unity => "asset",
            Format::Unreal => "txt",
            Format::Hlsl => "hlsl",
            Format::Glsl => "glsl",
            Format::Wgsl => "wgsl",
            Format::SamplesJson => "json",
            Format::LutPng | Format::ProfilePng => "png",
            Format::LutExr | Format::ProfileExr => "exr",
            Format::Blender => "py",
            Format::Materialx => "mtlx",
            Format::Godot => "tres",
        }
    }

    /// Whether the export needs the slow table bakes (run off the UI thread).
    pub fn is_slow(self) -> bool {
        matches!(self, Format::LutPng | Format::LutExr)
    }
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
    let burley_note = || -> Result<String, ModelError> {
        let (_, e) = burley_of(&preset.profile)?;
        Ok(if e > 0.0 {
            format!("The look reaches the engine through a Burley fit: relative L2 error of r·R(r) {e:.4}.")
        } else {
            "The Burley profile goes across exactly.".into()
        })
    };
    let mut notes = Vec::new();
    match format {
        Format::Unity => {
            notes.push(burley_note()?);
            let s = &preset.rendering.specular;
            let l = unity_dual_lobe(preset);
            notes.push(format!(
                "HDRP scales smoothness, not roughness: its two lobes match ours at base roughness {} (smoothness multipliers {:.4} and {:.4}, lobeMix {:.4} on the smoother lobe).",
                s.roughness, l.secondary, l.primary, l.lobe_mix
            ));
            notes.push("Add the asset to HDRP's Diffusion Profile List (at most 15); dual lobe needs HDRP 15+.".into());
        }
        Format::Unreal => {
            notes.extend(unreal_notes(preset)?.into_iter().map(|n| {
                let mut n = n;
                if let Some(f) = n.get_mut(0..1) {
                    f.make_ascii_uppercase();
                }
                format!("{n}.")
            }));
            notes.push("Needs Unreal Engine 5.1 or later.".into());
        }
        Format::Blender => {
            notes.push(burley_note()?);
            notes.push("Cycles renders it exactly (Christensen–Burley); EEVEE approximates it. Blender 4.0+ (checked with 4.5 and 5.0).".into());
        }
        Format::Materialx => {
            notes.push(burley_note()?);
            notes.push("The dual-lobe specular is not representable in OpenPBR: the base roughness is written.".into());
        }
        Format::Godot => notes.extend(godot_notes(preset)?),
        _ => {}
    }
    Ok(notes)
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
    let companion_path = match format {
        Format::Unreal => {
            let py = companion(out, "", "py");
            Some(if py == out {
                companion(out, "_unreal", "py")
            } else {
                py
            })
        }
        Format::LutPng | Format::LutExr => Some(companion(out, "_shadow", format.extension())),
        Format::ProfileExr | Format::ProfilePng => {
            Some(companion(out, "_transmittance", format.extension()))
        }
        _ => None,
    };
    std::iter::once(out.to_owned())
        .chain(companion_path)
        .collect()
}

/// Writes `preset` in `format` to `out` (and any companion files); returns
/// every path written. `source` is the preset's file, for the header.
pub fn export(
    preset: &Preset,
    source: Option<&Path>,
    format: Format,
    out: &Path,
) -> Result<Vec<PathBuf>, ExportError> {
    preset.validate()?;
    let prov = Provenance::new(preset, source);
    let written = planned_paths(format, out);
    // The companion file, where the format has one.
    let second = || written.get(1).cloned().unwrap_or_else(|| out.to_owned());
    match format {
        Format::Ron => {
            let text = format!("// Exported: {}.\n{}", prov.line(), preset.to_ron());
            write(out, text.as_bytes())?;
        }
        Format::Unity => {
            let stem = out
                .file_stem()
                .map(|s| s.to_string_lossy())
                .unwrap_or_default();
            write(out, unity_asset(preset, &prov, &stem)?.as_bytes())?
        }
        Format::Unreal => {
            let (text, py) = (unreal_struct(preset)?, unreal_python(preset, &prov)?);
            write(out, text.as_bytes())?;
            write(&second(), py.as_bytes())?;
        }
        Format::Hlsl | Format::Glsl | Format::Wgsl => {
            let lang = match format {
                Format::Hlsl => ShaderLanguage::Hlsl,
                Format::Glsl => ShaderLanguage::Glsl,
                _ => ShaderLanguage::Wgsl,
            };
            write(out, kernel_source(preset, lang, &prov)?.as_bytes())?;
        }
        Format::SamplesJson => write(out, samples_json(preset, &prov)?.as_bytes())?,
        Format::LutPng | Format::LutExr => {
            images::write_luts(preset, &prov, format == Format::LutExr, out, &second())?;
        }
        Format::ProfileExr | Format::ProfilePng => {
            images::write_profile(preset, &prov, format == Format::ProfileExr, out, &second())?;
        }
        Format::Blender => write(out, blender_python(preset, &prov)?.as_bytes())?,
        Format::Materialx => write(out, materialx_document(preset, &prov)?.as_bytes())?,
        Format::Godot => write(out, godot_material(preset, &prov)?.as_bytes())?,
    }
    Ok(written)
}
