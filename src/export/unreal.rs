//! Unreal Engine's SubsurfaceProfile, both ways: the details panel's
//! copy-paste text and a Python snippet for the editor (writers), and the
//! reader of that text and of our snippet. UE's own code is the reference:
//! `SubsurfaceProfile.h` (the `FSubsurfaceProfileStruct` fields, their
//! defaults and clamps, UE 5.1.1) and `SubsurfaceProfile.cpp`
//! (`UpgradeSubsurfaceProfileParameters`: a profile saved before mean free
//! paths, `bEnableMeanFreePath=False`, is upgraded from a diffuse mean free
//! path on load, `UpgradeDiffuseMeanFreePathToMeanFreePath`; one saved
//! before Burley, `bEnableBurley=False`, is converted from the separable
//! model by a fit of the falloff colour that differs between UE versions).
//! The conversions themselves are `model::units::UnrealProfile`.

use super::{asset_name, burley_of, fit_note, Provenance};
use crate::model::units::{UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE};
use crate::model::{ModelError, Rgb};
use crate::settings::Preset;

/// Unreal's parameters of the look (world unit scale 0.1: physical), with
/// distances under 0.1 cm folded into the colour as UE does.
pub fn unreal_profile(preset: &Preset) -> Result<(UnrealProfile, f64), ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    Ok((
        UnrealProfile::from_burley(&burley, UNREAL_DEFAULT_WORLD_UNIT_SCALE)?,
        fit_error,
    ))
}

/// The struct's dual-lobe and material fields, kept inside the ranges
/// SubsurfaceProfile.h (UE 5.1.1) clamps them to, with a note for each
/// value that had to move.
#[derive(Debug, Clone, PartialEq)]
pub struct UnrealMaterialFields {
    pub roughness0: f64,
    pub roughness1: f64,
    pub lobe_mix: f64,
    pub ior: f64,
    pub transmission_tint: Rgb,
    pub notes: Vec<String>,
}

pub fn unreal_material_fields(preset: &Preset) -> UnrealMaterialFields {
    let r = &preset.rendering;
    let s = &r.specular;
    let mut notes = Vec::new();
    let mut clamp = |field: &str, v: f64, lo: f64, hi: f64| {
        let c = v.clamp(lo, hi);
        if c != v {
            notes.push(format!(
                "{field} {v} is outside UE's {lo}-{hi} and is written as {c}"
            ));
        }
        c
    };
    // Roughness0/1 ClampMin 0.5, ClampMax 2.0 (lines 95–99); LobeMix 0.1–0.9
    // (lines 101–102); IOR 1.0–3.0 (lines 92–93); TransmissionTintColor
    // 0.001–1 (lines 107–108).
    let roughness0 = clamp("Roughness0", s.lobe0_roughness_multiplier, 0.5, 2.0);
    let roughness1 = clamp("Roughness1", s.lobe1_roughness_multiplier, 0.5, 2.0);
    let lobe_mix = clamp("LobeMix", s.lobe_mix, 0.1, 0.9);
    let ior = clamp("IOR", r.ior, 1.0, 3.0);
    let tint = r.transmission_tint;
    let transmission_tint = [
        clamp("TransmissionTintColor.R", tint[0], 0.001, 1.0),
        clamp("TransmissionTintColor.G", tint[1], 0.001, 1.0),
        clamp("TransmissionTintColor.B", tint[2], 0.001, 1.0),
    ];
    UnrealMaterialFields {
        roughness0,
        roughness1,
        lobe_mix,
        ior,
        transmission_tint,
        notes,
    }
}

/// What the Unreal export cannot hold exactly, one line each.
pub fn unreal_notes(preset: &Preset) -> Result<Vec<String>, ModelError> {
    let (u, fit_error) = unreal_profile(preset)?;
    Ok(unreal_notes_of(preset, &u, fit_error))
}

/// `unreal_notes` for a profile already converted (fits take a while).
fn unreal_notes_of(preset: &Preset, u: &UnrealProfile, fit_error: f64) -> Vec<String> {
    let mut notes = vec![fit_note(fit_error)];
    for ch in u.clamped_channels() {
        notes.push(format!(
            "MeanFreePathColor {ch} is under UE's minimum of 0.001 after folding the distance into 0.1 cm; UE raises it, which widens that channel"
        ));
    }
    notes.extend(unreal_material_fields(preset).notes);
    notes
}

/// The FSubsurfaceProfileStruct as details-panel copy-paste text (Unreal's
/// struct export syntax has no comments, so the provenance is in the .py).
pub fn unreal_struct(preset: &Preset) -> Result<String, ModelError> {
    let (u, _) = unreal_profile(preset)?;
    let m = unreal_material_fields(preset);
    let base = u.to_struct_text();
    // to_struct_text ends with ')'; append the rendering fields.
    let head = base.strip_suffix(')').unwrap_or(&base);
    Ok(format!(
        "{head},TransmissionTintColor=(R={:.6},G={:.6},B={:.6},A=1.000000),IOR={:.6},Roughness0={:.6},Roughness1={:.6},LobeMix={:.6})\n",
        m.transmission_tint[0],
        m.transmission_tint[1],
        m.transmission_tint[2],
        m.ior,
        m.roughness0,
        m.roughness1,
        m.lobe_mix,
    ))
}

/// The Substrate Slab's `SSS MFP` (world centimetres: its tooltip in
/// MaterialExpressionSubstrate.h says "unit = centimeters") for a look:
/// the value UE's own SubsurfaceProfile holds for it at WorldUnitScale
/// 0.1, 0.6·ℓ with ℓ = d·s(A) (Christensen & Burley 2015 eq. 5), since UE
/// turns a mean free path into Burley's shape through
/// `GetDiffuseMeanFreePathFromMeanFreePath`, whose `Dmfp2MfpMagicNumber`
/// is 0.6 (SubsurfaceProfile.cpp `CreateTexture`,
/// SubsurfaceScatteringMath.h). From the Slab to the SSS pass, UE 5.8's
/// Substrate.ush (`InternalGetSubstrateSlabBSDF`, `SLAB_SSSMFP` = SSSMFP ×
/// SSSMFPScale) and SubstrateExport.ush (`PackSubstrateOut`) pass the value
/// on unscaled; the per-pixel `GetBurleyParameters` was not readable, so
/// that it applies the same conversion is an assumption the export notes
/// state.
pub fn substrate_mfp_cm(burley: &crate::model::burley::Burley) -> Rgb {
    burley
        .mean_free_path_mm(crate::model::burley::ScalingFit::Perpendicular)
        .map(|l| crate::model::units::UNREAL_DMFP_TO_MFP * l / 10.0)
}

/// A Python snippet for Unreal's editor scripting that sets the struct on
/// the selected (or a new) SubsurfaceProfile asset, and builds (or
/// rebuilds, if scatterlab made it) a Substrate material whose Slab uses
/// it, or with `substrate_diffusion` the Slab's own mean free path. Property names are those
/// of `unreal.SubsurfaceProfileStruct` in UE 5.1+ (its Python API pages);
/// UE 5.0 has no `enable_mean_free_path` and reads the two mean-free-path
/// fields as a diffuse mean free path, so there the script stops with a
/// message instead of setting a different look.
pub fn unreal_python(
    preset: &Preset,
    prov: &Provenance,
    substrate_diffusion: bool,
) -> Result<String, ModelError> {
    let (u, fit_error) = unreal_profile(preset)?;
    let (burley, _) = burley_of(&preset.profile)?;
    let m = unreal_material_fields(preset);
    let notes: String = unreal_notes_of(preset, &u, fit_error)
        .iter()
        .map(|n| format!("# - {n}.\n"))
        .collect();
    let col = |c: Rgb| format!("unreal.LinearColor({}, {}, {}, 1.0)", c[0], c[1], c[2]);
    Ok(format!(
        r#"# Unreal SubsurfaceProfile for "{name}": {line}.
# Needs Unreal Engine 5.1 or later (checked against the 5.1 to 5.7 Python API).
# MeanFreePathDistance is in cm (UE keeps it at 0.1 cm or more, so shorter
# paths are folded into the colour as UE's own upgrade does); WorldUnitScale
# 0.1 keeps it physical. How close this is to the scatterlab look:
{notes}# Run in the editor's Python console with a SubsurfaceProfile selected in the
# Content Browser, or it creates /Game/{asset}.
import unreal

settings = unreal.SubsurfaceProfileStruct()
try:
    settings.set_editor_property("enable_mean_free_path", True)
except Exception as error:
    raise RuntimeError(
        "This profile needs Unreal Engine 5.1 or later: this engine has no "
        "enable_mean_free_path and would read MeanFreePathColor/Distance as a "
        "diffuse mean free path, a different look."
    ) from error
settings.set_editor_property("enable_burley", True)
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

{substrate}"#,
        name = preset.name.replace(['\n', '\r'], " "),
        line = prov.line(),
        asset = asset_name(&preset.name),
        albedo = col(u.surface_albedo),
        mfp = col(u.mean_free_path_color),
        dist = u.mean_free_path_distance_cm,
        wus = u.world_unit_scale,
        tint = col(m.transmission_tint),
        ior = m.ior,
        r0 = m.roughness0,
        r1 = m.roughness1,
        mix = m.lobe_mix,
        substrate = substrate_python(preset, &burley, m.ior, substrate_diffusion),
    ))
}

/// The Python script's second half: the Substrate material
/// `/Game/M_{asset}` with one Slab BSDF, of type Diffusion with the
/// profile plugged, or with SSS MFP in world centimetres
/// (`substrate_diffusion`).
fn substrate_python(
    preset: &Preset,
    burley: &crate::model::burley::Burley,
    ior: f64,
    substrate_diffusion: bool,
) -> String {
    let mfp_cm = substrate_mfp_cm(burley);
    let col = |c: Rgb| format!("unreal.LinearColor({}, {}, {}, 1.0)", c[0], c[1], c[2]);
    format!(
        r#"# Substrate (UE 5.7 Python API; Project Settings > Rendering > Substrate on):
# the material /Game/M_{asset} with one Slab BSDF on the Front Material.
# {substrate_mode}
# The Python enum has no DiffusionProfile member (it is hidden): a Slab of
# type Diffusion with a profile plugged is drawn as DiffusionProfile
# (Substrate.ush, InternalGetSubstrateSlabBSDF); the profile is set on the
# Slab and on the material, as the Slab's subsurface_profile docs ask.
# A material of that name that scatterlab did not make is left alone.
SUBSTRATE_DIFFUSION = {substrate_diffusion}
SSS_MFP_CM = unreal.LinearColor({mfp_cm_r}, {mfp_cm_g}, {mfp_cm_b}, 1.0)
if not hasattr(unreal, "MaterialExpressionSubstrateSlabBSDF"):
    unreal.log_warning("No Substrate in this engine: only the SubsurfaceProfile was set.")
else:
    lib = unreal.MaterialEditingLibrary
    assets = unreal.EditorAssetLibrary
    path = "/Game/M_{asset}"
    material = None
    if assets.does_asset_exist(path):
        material = assets.load_asset(path)
        if assets.get_metadata_tag(material, "scatterlab") != "substrate":
            raise RuntimeError(path + " exists and scatterlab did not make it: rename it, or move it, and run again.")
        lib.delete_all_material_expressions(material)
    else:
        tools = unreal.AssetToolsHelpers.get_asset_tools()
        material = tools.create_asset("M_{asset}", "/Game", unreal.Material, unreal.MaterialFactoryNew())
    assets.set_metadata_tag(material, "scatterlab", "substrate")
    slab = lib.create_material_expression(material, unreal.MaterialExpressionSubstrateSlabBSDF, -400, 0)
    slab.set_editor_property("sub_surface_type", unreal.MaterialSubSurfaceType.MSS_DIFFUSION)

    def constant3(value, x, y):
        node = lib.create_material_expression(material, unreal.MaterialExpressionConstant3Vector, x, y)
        node.set_editor_property("constant", value)
        return node

    def constant(value, x, y):
        node = lib.create_material_expression(material, unreal.MaterialExpressionConstant, x, y)
        node.set_editor_property("r", value)
        return node

    def connect(node, pin):
        if not lib.connect_material_expressions(node, "", slab, pin):
            raise RuntimeError("could not connect the Slab's " + pin + " input")

    connect(constant3({slab_albedo}, -800, -200), "Diffuse Albedo")
    connect(constant({roughness}, -800, -50), "Roughness")
    connect(constant({f0}, -800, 50), "F0")
    if SUBSTRATE_DIFFUSION:
        connect(constant3(SSS_MFP_CM, -800, 150), "SSS MFP")
        connect(constant(1.0, -800, 250), "SSS MFP Scale")
        material.set_editor_property("subsurface_profile", None)
    else:
        slab.set_editor_property("subsurface_profile", profile)
        material.set_editor_property("subsurface_profile", profile)
    if not lib.connect_material_property(slab, "", unreal.MaterialProperty.MP_FRONT_MATERIAL):
        raise RuntimeError("could not connect the Slab to the Front Material")
    lib.recompile_material(material)
    assets.save_loaded_asset(material)
"#,
        asset = asset_name(&preset.name),
        substrate_mode = if substrate_diffusion {
            "Type Diffusion with SSS MFP in world centimetres (--substrate-diffusion): the profile asset is not used."
        } else {
            "Type Diffusion with the SubsurfaceProfile above plugged: Substrate draws it as DiffusionProfile."
        },
        substrate_diffusion = if substrate_diffusion { "True" } else { "False" },
        mfp_cm_r = mfp_cm[0],
        mfp_cm_g = mfp_cm[1],
        mfp_cm_b = mfp_cm[2],
        slab_albedo = col(burley.albedo()),
        roughness = preset.rendering.specular.roughness,
        f0 = ((ior - 1.0) / (ior + 1.0)).powi(2),
    )
}

mod read;
mod substrate;
pub use read::read;

/// Unreal's SubsurfaceProfile as an export target: the struct text, and
/// the Python snippet beside it (`_unreal.py` where the text itself was
/// given a .py name).
pub(super) const TARGET: super::Target = super::Target {
    id: "unreal",
    name: "Unreal subsurface profile",
    description: "SubsurfaceProfile struct text, and a .py that sets it",
    extension: "txt",
    companion: Some(|out| {
        let py = super::companion(out, "", "py");
        if py == out {
            super::companion(out, "_unreal", "py")
        } else {
            py
        }
    }),
    slow: false,
    write: |preset, prov, out, py, options| {
        let script = unreal_python(preset, prov, options.unreal_substrate_diffusion)?;
        let text = unreal_struct(preset)?;
        super::write(out, text.as_bytes())?;
        super::write(py, script.as_bytes())
    },
    notes: |preset| {
        let mut notes: Vec<String> = unreal_notes(preset)?
            .into_iter()
            .map(|n| {
                let mut n = n;
                if let Some(f) = n.get_mut(0..1) {
                    f.make_ascii_uppercase();
                }
                format!("{n}.")
            })
            .collect();
        notes.push("Needs Unreal Engine 5.1 or later.".into());
        notes.push("The script also builds a Substrate material (UE 5.7): a Slab of type Diffusion with the profile; with --substrate-diffusion its own SSS MFP, written as the value a SubsurfaceProfile holds (0.6 × the mean free path, in cm), which assumes Substrate's per-pixel path converts it as the profile path does.".into());
        Ok(notes)
    },
    fidelity: super::burley_fidelity,
    params: Some(|b, world_scale| {
        let u =
            UnrealProfile::from_burley(b, world_scale.unwrap_or(UNREAL_DEFAULT_WORLD_UNIT_SCALE))?;
        Ok(serde_json::json!({
            "surface_albedo": u.surface_albedo,
            "mean_free_path_color": u.mean_free_path_color,
            "mean_free_path_distance_cm": u.mean_free_path_distance_cm,
            "world_unit_scale": u.world_unit_scale,
            "struct_text": u.to_struct_text(),
        }))
    }),
    reader: Some(super::Reader {
        extensions: &["txt", "py", "t3d"],
        claims: |ext, text| {
            (ext == "py" && text.contains("import unreal"))
                || text.trim_start().starts_with('(')
                || substrate::claims(text)
        },
        read: |text, path, _| {
            if substrate::claims(text) {
                substrate::read(text, path)
            } else {
                read(text, path)
            }
        },
    }),
};
