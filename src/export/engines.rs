//! Engine assets: Unity HDRP `.asset`, Unreal SubsurfaceProfile text and
//! Python, Blender Python. The profile goes through its Burley parameters
//! (`model::units`); non-Burley looks are fitted first and the fit error
//! is written into the comment.

use super::{burley_of, Provenance};
use crate::model::units::{
    BlenderSubsurface, UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE,
};
use crate::model::{ModelError, Rgb};
use crate::settings::rendering::{TexturingId, TransmissionId};
use crate::settings::Preset;

fn fit_note(fit_error: f64) -> String {
    if fit_error > 0.0 {
        format!("converted through a Burley fit (relative L2 error of r*R(r): {fit_error:.4})")
    } else {
        "exact Burley parameters".into()
    }
}

/// Unity's smoothness multipliers (secondary x ∈ [0, 1], primary y ∈
/// [1, 2]) for the dual-lobe roughness multipliers on the base roughness ρ:
/// perceptual smoothness is 1 − ρ, so a lobe of roughness ρ·m has the
/// smoothness multiplier (1 − ρ·m)/(1 − ρ).
pub fn unity_smoothness_multipliers(preset: &Preset) -> (f64, f64) {
    let s = &preset.rendering.specular;
    let base = (1.0 - s.roughness).max(1e-3);
    let mult = |m: f64| (1.0 - (s.roughness * m).min(1.0)) / base;
    (
        mult(s.lobe1_roughness_multiplier).clamp(0.0, 1.0),
        mult(s.lobe0_roughness_multiplier).clamp(1.0, 2.0),
    )
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
/// and `scatteringDistanceMultiplier` the way HDRP splits HDR input.
pub fn unity_asset(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    let r = &preset.rendering;
    let u = UnityProfile::from_burley(&burley, r.world_scale_m_per_unit)?;
    let (secondary, primary) = unity_smoothness_multipliers(preset);
    let name = yaml_name(&preset.name);
    Ok(format!(
        "%YAML 1.1
%TAG !u! tag:unity3d.com,2011:
# HDRP Diffusion Profile {}.
# Scattering distance in mm at world scale 1; {}.
# The profile's albedo {:?} belongs in the material's base colour.
--- !u!114 &11400000
MonoBehaviour:
  m_ObjectHideFlags: 0
  m_CorrespondingSourceObject: {{fileID: 0}}
  m_PrefabInstance: {{fileID: 0}}
  m_PrefabAsset: {{fileID: 0}}
  m_GameObject: {{fileID: 0}}
  m_Enabled: 1
  m_EditorHideFlags: 0
  m_Script: {{fileID: 11500000, guid: b2686e09ec7aef44bad2843e4416f057, type: 3}}
  m_Name: {name}
  m_EditorClassIdentifier: 
  profile:
    scatteringDistance: {}
    scatteringDistanceMultiplier: {}
    transmissionTint: {}
    texturingMode: {}
    smoothnessMultipliers: {{x: {secondary}, y: {primary}}}
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
        yaml_color(u.scattering_distance_color),
        u.scattering_distance_multiplier,
        yaml_color(r.transmission_tint),
        match r.texturing {
            TexturingId::PreAndPostScatter => 0,
            TexturingId::PostScatter => 1,
        },
        r.specular.lobe_mix,
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
        profile_hash(&preset.name),
    ))
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

/// Unreal's parameters of the look (world unit scale 0.1: physical).
pub fn unreal_profile(preset: &Preset) -> Result<(UnrealProfile, f64), ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    Ok((
        UnrealProfile::from_burley(&burley, UNREAL_DEFAULT_WORLD_UNIT_SCALE)?,
        fit_error,
    ))
}

/// The FSubsurfaceProfileStruct as details-panel copy-paste text (Unreal's
/// struct export syntax has no comments, so the provenance is in the .py).
pub fn unreal_struct(preset: &Preset) -> Result<String, ModelError> {
    let (u, _) = unreal_profile(preset)?;
    let r = &preset.rendering;
    let s = &r.specular;
    let base = u.to_struct_text();
    // to_struct_text ends with ')'; append the rendering fields.
    let head = base.strip_suffix(')').unwrap_or(&base);
    Ok(format!(
        "{head},TransmissionTintColor=(R={:.6},G={:.6},B={:.6},A=1.000000),IOR={:.6},Roughness0={:.6},Roughness1={:.6},LobeMix={:.6})\n",
        r.transmission_tint[0],
        r.transmission_tint[1],
        r.transmission_tint[2],
        r.ior,
        s.lobe0_roughness_multiplier,
        s.lobe1_roughness_multiplier,
        s.lobe_mix,
    ))
}

/// A Python snippet for Unreal's editor scripting that sets the struct on
/// the selected (or a new) SubsurfaceProfile asset.
pub fn unreal_python(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let (u, fit_error) = unreal_profile(preset)?;
    let r = &preset.rendering;
    let s = &r.specular;
    let col = |c: Rgb| format!("unreal.LinearColor({}, {}, {}, 1.0)", c[0], c[1], c[2]);
    Ok(format!(
        r#"# Unreal SubsurfaceProfile for "{name}": {line}.
# {note}. MeanFreePathDistance is in cm; WorldUnitScale 0.1 keeps it physical.
# Run in the editor's Python console with a SubsurfaceProfile selected in the
# Content Browser, or it creates /Game/{asset}.
import unreal

settings = unreal.SubsurfaceProfileStruct()
settings.set_editor_property("enable_burley", True)
settings.set_editor_property("enable_mean_free_path", True)
settings.set_editor_property("surface_albedo", {albedo})
settings.set_editor_property("mean_free_path_color", {mfp})
settings.set_editor_property("mean_free_path_distance", {dist})
settings.set_editor_property("world_unit_scale", {wus})
settings.set_editor_property("transmission_tint_color", {tint})
settings.set_editor_property("ior", {ior})
settings.set_editor_property("roughness0", {r0})
settings.set_editor_property("roughness1", {r1})
settings.set_editor_property("lobe_mix", {mix})

selected = [a for a in unreal.EditorUtilityLibrary.get_selected_assets()
            if isinstance(a, unreal.SubsurfaceProfile)]
if selected:
    profile = selected[0]
else:
    tools = unreal.AssetToolsHelpers.get_asset_tools()
    profile = tools.create_asset("{asset}", "/Game", unreal.SubsurfaceProfile, None)
profile.set_editor_property("settings", settings)
unreal.EditorAssetLibrary.save_loaded_asset(profile)
"#,
        name = preset.name.replace(['\n', '\r'], " "),
        line = prov.line(),
        note = fit_note(fit_error),
        asset = asset_name(&preset.name),
        albedo = col(u.surface_albedo),
        mfp = col(u.mean_free_path_color),
        dist = u.mean_free_path_distance_cm,
        wus = u.world_unit_scale,
        tint = col(r.transmission_tint),
        ior = r.ior,
        r0 = s.lobe0_roughness_multiplier,
        r1 = s.lobe1_roughness_multiplier,
        mix = s.lobe_mix,
    ))
}

/// An asset name: letters, digits and '_' only.
fn asset_name(name: &str) -> String {
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

/// Blender's Principled BSDF (Christensen–Burley): Subsurface Radius and
/// Scale for a scene in metres (scale 1), as a Python snippet that sets
/// them on the active object's material.
pub fn blender_python(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    let b = BlenderSubsurface::from_burley(&burley, 1.0)?;
    let c = b.subsurface_radius;
    Ok(format!(
        r#"# Blender Principled BSDF subsurface for "{name}": {line}.
# {note}. Scene units in metres (Unit Scale 1).
# subsurface_radius = ({r0}, {r1}, {r2})
# subsurface_scale = {scale}  # m
# base_color = {albedo:?}  (the profile's albedo; textures replace it)
# Run in Blender's Python console with the object selected.
import bpy

SUBSURFACE_RADIUS = ({r0}, {r1}, {r2})
SUBSURFACE_SCALE = {scale}
IOR = {ior}

mat = bpy.context.object.active_material
if mat is None:
    mat = bpy.data.materials.new("{asset}")
    bpy.context.object.data.materials.append(mat)
mat.use_nodes = True
bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
bsdf.subsurface_method = "BURLEY"
bsdf.inputs["Subsurface Weight"].default_value = 1.0
bsdf.inputs["Subsurface Radius"].default_value = SUBSURFACE_RADIUS
bsdf.inputs["Subsurface Scale"].default_value = SUBSURFACE_SCALE
bsdf.inputs["IOR"].default_value = IOR
"#,
        name = preset.name.replace(['\n', '\r'], " "),
        line = prov.line(),
        note = fit_note(fit_error),
        asset = asset_name(&preset.name),
        r0 = c[0],
        r1 = c[1],
        r2 = c[2],
        scale = b.subsurface_scale,
        albedo = burley.albedo(),
        ior = preset.rendering.ior,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Unreal's defaults (roughness 0.55 × 0.75 and × 1.30): perceptual
    /// smoothness 1 − 0.4125 = 0.5875 and 1 − 0.715 = 0.285 over the base
    /// 0.45 give primary 1.30556 and secondary 0.63333 (hand computation).
    #[test]
    fn unity_smoothness_multipliers_from_roughness_multipliers() {
        let p = Preset::default_skin();
        let (secondary, primary) = unity_smoothness_multipliers(&p);
        assert!((primary - 0.5875 / 0.45).abs() < 1e-12, "{primary}");
        assert!((secondary - 0.285 / 0.45).abs() < 1e-12, "{secondary}");
    }

    #[test]
    fn yaml_names_are_quoted_when_needed() {
        assert_eq!(yaml_name("Skin"), "Skin");
        assert_eq!(yaml_name("Skin: it's"), "'Skin: it''s'");
        assert_eq!(yaml_name("  "), "Diffusion Profile");
    }
}
