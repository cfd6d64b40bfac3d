//! Unity HDRP's `DiffusionProfileSettings` assets, both ways: the writer
//! (m_Version 2) and the reader of every version HDRP has written, the
//! lists that hold several profiles (a Diffusion Profile List or override
//! in a volume profile, the HDRP Global Settings' list) resolved through
//! the `.meta` files beside them. HDRP's own code is the reference for
//! every rule here, cited by file:
//! - `DiffusionProfileSettings.cs` (HDRP 17, Runtime/Material/
//!   DiffusionProfile): the serialized `DiffusionProfile` fields
//!   (scatteringDistance, scatteringDistanceMultiplier, transmissionTint,
//!   texturingMode, smoothnessMultipliers, lobeMix, diffuseShadingPower,
//!   transmissionMode, thicknessRemap, worldScale, ior, hash), the enums
//!   (`TexturingMode`: PreAndPostScatter = 0, PostScatter = 1;
//!   `TransmissionMode`: Regular = 0, shown as "Thick Object", ThinObject =
//!   1), `ResetToDefault`, `Validate` (the clamps a loaded profile goes
//!   through, and dual-lobe defaults where `diffuseShadingPower` reads 0,
//!   as a field missing from an older file does), `UpdateKernel` (the
//!   distance is `scatteringDistanceMultiplier × scatteringDistance`, with
//!   S = min(2²⁴, 1/d)) and the `scatteringDistance` property;
//! - `DiffusionProfileSettings.Migration.cs`: `Version` Initial = 0 (a
//!   `profiles` array of up to 16 per asset), DiffusionProfileRework = 1
//!   (one `profile` per asset, `scatteringDistance` an HDR colour in mm),
//!   SplitScatteringDistance = 2 (the HDR colour split into an LDR colour
//!   and `scatteringDistanceMultiplier` by `HDUtils.ConvertHDRColorToLDR`:
//!   the product is the same distance);
//! - `DiffusionProfileList.cs` / `DiffusionProfileOverride.cs` (a volume
//!   component's `diffusionProfiles.m_Value`) and the HDRP assets'
//!   `diffusionProfileSettingsList`: references by GUID.

use super::import::{ImportError, ImportedLook};
use super::{burley_of, fit_note, Provenance};
use crate::model::units::UnityProfile;
use crate::model::{ModelError, Rgb};
use crate::settings::profile::{BurleyShape, BurleySpec};
use crate::settings::rendering::{DualLobeSpec, RenderingSpec, TexturingId, TransmissionId};
use crate::settings::{Preset, ProfileSpec};
use std::path::{Path, PathBuf};
use yaml_rust2::Yaml;

/// HDRP's dual-lobe fields for our dual-lobe specular. HDRP multiplies the
/// *perceptual smoothness* 1 − ρ of each lobe (Lit.hlsl `EvaluateBSDF`:
/// `saturate(lobeA − ρ·lobeA)`), where Unreal and our viewport multiply the
/// roughness ρ. At the preset's base roughness the two agree when a lobe of
/// roughness ρ·m gets the smoothness multiplier (1 − ρ·m)/(1 − ρ). HDRP's
/// `.x` (0–1) is the rougher lobe, weighted 1 − `lobeMix`; its `.y` (1–2)
/// is the smoother lobe, weighted `lobeMix` (DiffusionProfileSettings.cs
/// lines 296–309 name them secondary and primary; UpdateCache line 389
/// packs them for the shader). Our `lobe_mix` weighs the rougher lobe 1,
/// so HDRP's `lobeMix` is 1 − `lobe_mix`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnityDualLobe {
    /// `smoothnessMultipliers.x`: the rougher lobe (our lobe 1).
    pub secondary: f64,
    /// `smoothnessMultipliers.y`: the smoother lobe (our lobe 0).
    pub primary: f64,
    /// `lobeMix`: the weight of the smoother lobe.
    pub lobe_mix: f64,
}

pub fn unity_dual_lobe(preset: &Preset) -> UnityDualLobe {
    let s = &preset.rendering.specular;
    let base = (1.0 - s.roughness).max(1e-3);
    let mult = |m: f64| (1.0 - (s.roughness * m).min(1.0)) / base;
    UnityDualLobe {
        secondary: mult(s.lobe1_roughness_multiplier).clamp(0.0, 1.0),
        primary: mult(s.lobe0_roughness_multiplier).clamp(1.0, 2.0),
        lobe_mix: 1.0 - s.lobe_mix,
    }
}

/// A stable non-zero 32-bit id for the profile (FNV-1a of the name). HDRP
/// re-hashes a profile whose hash collides with another in the project.
fn profile_hash(name: &str) -> u32 {
    let h = name.bytes().fold(0x811c_9dc5u32, |h, b| {
        (h ^ b as u32).wrapping_mul(0x0100_0193)
    });
    // Keep it a normal, finite float bit pattern as HDRP's own hashes are
    // (they are read in shaders as asfloat).
    (h & 0x007f_ffff) | 0x3f80_0000
}

fn yaml_color(c: Rgb) -> String {
    format!("{{r: {}, g: {}, b: {}, a: 1}}", c[0], c[1], c[2])
}

/// HDRP `DiffusionProfileSettings` (m_Version 2) as Unity writes it:
/// the scattering distance (mm at world scale 1) split into an LDR colour
/// and `scatteringDistanceMultiplier` the way HDRP splits HDR input. Field
/// order, enum values and the script GUID follow DiffusionProfileSettings.cs
/// (HDRP 15–17, lines 33–77) and its .meta; `m_Name` is the asset's file
/// name, as Unity expects.
pub fn unity_asset(
    preset: &Preset,
    prov: &Provenance,
    file_stem: &str,
) -> Result<String, ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    let r = &preset.rendering;
    let u = UnityProfile::from_burley(&burley, r.world_scale_m_per_unit)?;
    let lobes = unity_dual_lobe(preset);
    let header = mono_behaviour(
        11400000,
        0,
        project::PROFILE_SCRIPT_GUID,
        &yaml_name(file_stem),
    );
    Ok(format!(
        "%YAML 1.1
%TAG !u! tag:unity3d.com,2011:
# HDRP Diffusion Profile {}.
# Scattering distance in mm at world scale 1; {}.
# The profile's albedo {:?} belongs in the material's base colour.
# HDRP renders a profile only once it is in the Diffusion Profile List
# (HDRP 17: the Diffusion Profile List volume override; HDRP 12-16: the HDRP
# Global Settings asset), which holds at most 15 profiles.
# The dual lobe (smoothnessMultipliers, lobeMix, diffuseShadingPower) needs
# HDRP 15 or later; this layout (m_Version 2, SplitScatteringDistance: the
# colour/multiplier split) was checked against HDRP 15-17, not older ones. The smoothness multipliers reproduce scatterlab's roughness
# multipliers exactly at a base roughness of {} (HDRP scales smoothness,
# scatterlab and Unreal scale roughness); lobeMix weights the smoother lobe.
{header}  profile:
    scatteringDistance: {}
    scatteringDistanceMultiplier: {}
    transmissionTint: {}
    texturingMode: {}
    smoothnessMultipliers: {{x: {}, y: {}}}
    lobeMix: {}
    diffuseShadingPower: 1
    transmissionMode: {}
    thicknessRemap: {{x: {}, y: {}}}
    worldScale: {}
    ior: {}
    hash: {}
  m_Version: 2
",
        prov.line(),
        fit_note(fit_error),
        burley.albedo(),
        r.specular.roughness,
        yaml_color(u.scattering_distance_color),
        u.scattering_distance_multiplier,
        yaml_color(r.transmission_tint),
        match r.texturing {
            TexturingId::PreAndPostScatter => 0,
            TexturingId::PostScatter => 1,
        },
        lobes.secondary,
        lobes.primary,
        lobes.lobe_mix,
        // HDRP: 0 = Regular ("Thick Object"), 1 = ThinObject. HDRP has no
        // "off": transmission is a material keyword there.
        match r.transmission {
            TransmissionId::ThickObject => 0,
            TransmissionId::ThinObject | TransmissionId::Off => 1,
        },
        r.thickness_remap_mm.0,
        r.thickness_remap_mm.1,
        u.world_scale_m_per_unit,
        r.ior,
        profile_hash(file_stem),
    ))
}

/// The head of a ScriptableObject's YAML document as Unity writes it
/// (`--- !u!114 &ID` and the MonoBehaviour's fixed fields, up to
/// `m_EditorClassIdentifier`): a profile asset, a volume profile and its
/// components all start so.
pub(super) fn mono_behaviour(
    file_id: u64,
    hide_flags: u8,
    script_guid: &str,
    name: &str,
) -> String {
    format!(
        "--- !u!114 &{file_id}
MonoBehaviour:
  m_ObjectHideFlags: {hide_flags}
  m_CorrespondingSourceObject: {{fileID: 0}}
  m_PrefabInstance: {{fileID: 0}}
  m_PrefabAsset: {{fileID: 0}}
  m_GameObject: {{fileID: 0}}
  m_Enabled: 1
  m_EditorHideFlags: 0
  m_Script: {{fileID: 11500000, guid: {script_guid}, type: 3}}
  m_Name: {name}
  m_EditorClassIdentifier: \n"
    )
}

/// A name safe as a plain YAML scalar.
fn yaml_name(name: &str) -> String {
    let cleaned: String = name
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let cleaned = cleaned.trim();
    if cleaned.is_empty() {
        return "Diffusion Profile".into();
    }
    if cleaned.contains([
        ':', '#', '{', '}', '[', ']', ',', '&', '*', '!', '|', '>', '\'', '"', '%', '@', '`',
    ]) {
        format!("'{}'", cleaned.replace('\'', "''"))
    } else {
        cleaned.to_owned()
    }
}

pub mod budget;
/// The budget's use case: the files it writes, the heads it renders.
#[cfg(feature = "gpu")]
mod budget_pictures;
#[cfg(feature = "gpu")]
pub mod budget_run;
pub mod project;
mod read;
pub use read::read;

/// Unity HDRP's diffusion profile as an export target (see the module's
/// sources for every field).
pub(super) const TARGET: super::Target = super::Target {
    id: "unity",
    name: "Unity HDRP diffusion profile",
    description: "DiffusionProfileSettings .asset (a Burley fit where the look is not Burley)",
    extension: "asset",
    companion: None,
    slow: false,
    write: |preset, prov, out, _, _| {
        let stem = out
            .file_stem()
            .map(|s| s.to_string_lossy())
            .unwrap_or_default();
        super::write(out, unity_asset(preset, prov, &stem)?.as_bytes())
    },
    notes: |preset| {
        let s = &preset.rendering.specular;
        let l = unity_dual_lobe(preset);
        Ok(vec![
            super::burley_note(preset)?,
            format!(
                "HDRP scales smoothness, not roughness: its two lobes match ours at base roughness {} (smoothness multipliers {:.4} and {:.4}, lobeMix {:.4} on the smoother lobe).",
                s.roughness, l.secondary, l.primary, l.lobe_mix
            ),
            "Add the asset to HDRP's Diffusion Profile List (at most 15); dual lobe needs HDRP 15+.".into(),
        ])
    },
    fidelity: super::burley_fidelity,
    params: Some(|b, world_scale| {
        let u = crate::model::units::UnityProfile::from_burley(b, world_scale.unwrap_or(1.0))?;
        Ok(serde_json::json!({
            "scattering_distance_color": u.scattering_distance_color,
            "scattering_distance_multiplier": u.scattering_distance_multiplier,
            "world_scale_m_per_unit": u.world_scale_m_per_unit,
            "albedo_for_material": b.albedo(),
        }))
    }),
    reader: Some(super::Reader {
        extensions: &["asset"],
        claims: |ext, text| ext == "asset" || text.trim_start().starts_with("%YAML"),
        read: |text, path, _| read(text, path),
    }),
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Unreal's defaults (roughness 0.55 × 0.75 and × 1.30): perceptual
    /// smoothness 1 − 0.4125 = 0.5875 and 1 − 0.715 = 0.285 over the base
    /// 0.45 give primary 1.30556 and secondary 0.63333 (hand computation);
    /// HDRP's lobeMix weights the smoother (primary) lobe, which takes
    /// 1 − 0.85 = 0.15 of Unreal's default mix.
    #[test]
    fn unity_dual_lobe_from_roughness_multipliers() {
        let p = Preset::default_skin();
        let l = unity_dual_lobe(&p);
        assert!((l.primary - 0.5875 / 0.45).abs() < 1e-12, "{l:?}");
        assert!((l.secondary - 0.285 / 0.45).abs() < 1e-12, "{l:?}");
        assert!((l.lobe_mix - 0.15).abs() < 1e-12, "{l:?}");
    }

    #[test]
    fn yaml_names_are_quoted_when_needed() {
        assert_eq!(yaml_name("Skin"), "Skin");
        assert_eq!(yaml_name("Skin: it's"), "'Skin: it''s'");
        assert_eq!(yaml_name("  "), "Diffusion Profile");
    }
}
