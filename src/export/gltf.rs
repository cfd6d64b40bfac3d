//! glTF 2.0, both ways: a `.gltf` whose material carries the look through
//! Khronos' volume extensions, on the default head, on a sphere or (from
//! the editor) on the mesh on screen with its maps, and the reader of
//! those extensions. The definitions, from the KhronosGroup/glTF
//! repository (`extensions/2.0/Khronos/`, at 77b44be7; the drafts at their
//! pull requests' heads):
//! - `KHR_materials_volume` (ratified), README lines 112–115:
//!   `thicknessFactor` (mesh units; 0 is thin-walled), `attenuationDistance`
//!   (world units, default +∞), `attenuationColor` (default 1); line 150:
//!   the attenuation coefficient σt = −ln(c)/d per channel.
//! - `KHR_materials_diffuse_transmission` (Release Candidate), README lines
//!   77–80: `diffuseTransmissionFactor` and `diffuseTransmissionColorFactor`;
//!   line 386: with a volume, it is the boundary's diffuse BTDF and the
//!   light inside is the volume's to carry.
//! - `KHR_materials_volume_scatter` (draft, PR #2453 at 134d0766), README
//!   lines 72–74: `multiscatterColorFactor`, "the multi-scatter albedo";
//!   line 85: σt now counts scattering as well; lines 102–115 split it by
//!   the single-scatter albedo, line 126 the Kulla–Conty inversion from the
//!   multi-scatter albedo; lines 175–179 point dense media at a diffusion
//!   approximation (Christensen & Burley 2015). Its schema (line 8) still
//!   names the colour `multiscatterColor`, so both names are written.
//!
//! The mapping: the multi-scatter albedo is Burley's A (the surface's
//! total diffuse reflectance, also `baseColorFactor`), and the mean free
//! path is ℓ = 1/σt = d·s(A), with Christensen & Burley 2015's eq. 5 for
//! s(A), as the MaterialX export maps OpenPBR's mean free path (one rule
//! for every mean-free-path format here). `attenuationDistance` is the
//! widest channel's ℓ, in metres, and each channel's colour is then
//! c = exp(−attenuationDistance/ℓ), so −ln(c)/attenuationDistance = 1/ℓ.
//!
//! Readers do not all read it so. What each known one draws from the file
//! is computed here ([`gltf_readings`]) and stated with its shape error
//! against the look (`model::fit::shape_error`, the measure `convert`
//! reports) in the file's `extras` and in the export notes:
//! - Khronos' glTF-Sample-Renderer (`punctual.glsl`, `getSubsurfaceScattering`
//!   and `burley_setup`): radius = attenuationDistance × multiscatterColor,
//!   d = radius/(4π·s(A)) with Christensen & Burley's eq. 6,
//!   s = 1.9 − A + 3.5(A − 0.8)², A the base colour.
//! - Babylon.js's glTF loader (`@babylonjs/loaders` 9.28,
//!   `KHR_materials_volume_scatter.pure.ts` lines 118–145 and
//!   `openpbrMaterialLoadingAdapter.ts`): with `useOpenPBR`,
//!   `subsurfaceRadius` = max ℓ, `subsurfaceRadiusScale` = ℓ/max ℓ and
//!   `subsurfaceColor` = multiscatter colour, OpenPBR's own meaning. Its
//!   default `PBRMaterial` (`pbrMaterialLoadingAdapter.ts` lines 946–998,
//!   758–781) turns diffuse transmission into translucency with
//!   `diffusionDistance` = attenuationColor × attenuationDistance and
//!   leaves screen-space scattering off: nothing spreads.

use super::import::{ImportError, ImportOptions, ImportedLook};
use super::{burley_of, fit_note, ExportError, Provenance};
use crate::model::burley::{Burley, ScalingFit};
use crate::model::fit::shape_error;
use crate::model::{ModelError, Rgb};
use crate::settings::rendering::RenderingSpec;
use crate::settings::Preset;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::Path;

mod mesh;
mod read;
pub use mesh::GltfOnMesh;
use mesh::{head, mesh_data_on, sphere, Buffer, MeshData};
pub use read::{gltf_has_volume, read};

/// The extensions' names.
pub const VOLUME: &str = "KHR_materials_volume";
pub const DIFFUSE_TRANSMISSION: &str = "KHR_materials_diffuse_transmission";
pub const VOLUME_SCATTER: &str = "KHR_materials_volume_scatter";
pub const IOR: &str = "KHR_materials_ior";

/// The mesh the exported material is put on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum GltfMesh {
    /// The default head (its eyes and teeth get plain materials).
    #[default]
    Head,
    /// A sphere 10 cm across.
    Sphere,
}

/// The sphere's radius (m): a head-sized shape, wide against any look's
/// scattering.
const SPHERE_RADIUS_M: f64 = 0.05;

/// The volume extensions' values for a look.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GltfVolume {
    /// `baseColorFactor` and the multi-scatter colour: Burley's A.
    pub albedo: Rgb,
    /// The mean free path ℓ = d·s(A) per channel (mm).
    pub mean_free_path_mm: Rgb,
    /// `attenuationDistance` (m): the widest channel's ℓ.
    pub attenuation_distance_m: f64,
    /// `attenuationColor`: exp(−attenuationDistance/ℓ) per channel.
    pub attenuation_color: Rgb,
}

/// The look's volume (KHR_materials_volume with the volume_scatter draft)
/// and the Burley fit's error when the look is not a Burley profile.
pub fn gltf_volume(preset: &Preset) -> Result<(GltfVolume, f64), ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    Ok((volume_of(&burley), fit_error))
}

fn volume_of(burley: &Burley) -> GltfVolume {
    let albedo = burley.albedo();
    // ℓ = d·s(A), Christensen & Burley 2015 eq. 5.
    let mfp = burley.mean_free_path_mm(ScalingFit::Perpendicular);
    let widest = mfp.into_iter().fold(0.0, f64::max);
    // KHR_materials_volume README line 150: σt = −ln(c)/D; with
    // c = exp(−D/ℓ), σt = 1/ℓ exactly.
    let attenuation_color = mfp.map(|l| (-widest / l).exp());
    GltfVolume {
        albedo,
        mean_free_path_mm: mfp,
        attenuation_distance_m: widest * 1e-3,
        attenuation_color,
    }
}

/// What one known reader draws from the exported file.
#[derive(Debug, Clone, PartialEq)]
pub struct Reading {
    /// The reader, as its users know it.
    pub reader: &'static str,
    /// Its fields as it sets them from the file (name, value).
    pub fields: Vec<(&'static str, Value)>,
    /// Shape error of the profile it draws against the look (the largest
    /// channel's; 1 where nothing spreads).
    pub error: f64,
    /// One sentence: how it reads the file.
    pub how: String,
}

/// What each known reader draws from the exported file, the extensions'
/// own reading first. `thickness_m` is the file's `thicknessFactor`.
pub fn gltf_readings(
    preset: &Preset,
    thickness_m: f64,
    with_scatter: bool,
) -> Result<Vec<Reading>, ModelError> {
    let look = preset.profile.build()?;
    let (burley, fit_error) = burley_of(&preset.profile)?;
    let v = volume_of(&burley);
    let worst = |e: Rgb| e.into_iter().fold(0.0, f64::max);
    let mut out = Vec::new();
    // The extensions' definition, as this module and its reader hold it.
    let spec =
        Burley::from_mean_free_path(v.albedo, v.mean_free_path_mm, ScalingFit::Perpendicular)?;
    out.push(Reading {
        reader: "the extensions' definition (scatterlab's reader)",
        fields: vec![
            ("mean_free_path_mm", json!(v.mean_free_path_mm)),
            ("albedo", json!(v.albedo)),
        ],
        error: worst(shape_error(look.as_ref(), &spec)),
        how: format!(
            "σt = −ln(attenuationColor)/attenuationDistance = 1/ℓ, A = the multi-scatter colour, d = ℓ/s(A) (Christensen & Burley 2015 eq. 5): the look's Burley profile ({})",
            fit_note(fit_error)
        ),
    });
    // Khronos glTF-Sample-Renderer: radius = D·A, d = radius/(4π s₆(A)).
    if with_scatter {
        let d_mm: Rgb = std::array::from_fn(|c| {
            let a = v.albedo[c];
            v.attenuation_distance_m * a / (4.0 * PI * ScalingFit::DiffuseSurface.scale(a)) * 1e3
        });
        let (lo, hi) = crate::model::burley::DISTANCE_RANGE_MM;
        let drawn = Burley::from_scattering_distance(v.albedo, d_mm.map(|d| d.clamp(lo, hi)))?;
        out.push(Reading {
            reader: "Khronos glTF-Sample-Renderer",
            fields: vec![("scattering_distance_mm", json!(d_mm))],
            error: worst(shape_error(look.as_ref(), &drawn)),
            how: format!(
                "Burley's d = attenuationDistance × multiscatterColor / (4π·s(A)), s = 1.9 − A + 3.5(A − 0.8)² (punctual.glsl, burley_setup): the widest channel's d is {:.3} of the look's",
                d_mm[burley.widest_channel()] / burley.scattering_distance_mm()[burley.widest_channel()]
            ),
        });
    }
    out.push(babylon_pbr_reading(preset, &v, thickness_m, with_scatter));
    // Blender 5.0's glTF importer (io_import_scene_gltf2, checked by
    // tests/clients/blender_gltf_volume.py): the volume as a Volume
    // Absorption node (Color = attenuationColor, Density =
    // 1/attenuationDistance) under a Principled BSDF without subsurface;
    // neither diffuse transmission nor the draft becomes scattering.
    out.push(Reading {
        reader: "Blender 5.0 glTF importer",
        fields: vec![
            ("Volume Absorption.Color", json!(v.attenuation_color)),
            (
                "Volume Absorption.Density",
                json!(1.0 / v.attenuation_distance_m),
            ),
            ("Principled BSDF.Subsurface Weight", json!(0.0)),
        ],
        // Light is absorbed in the volume, not spread at the surface.
        error: 1.0,
        how: "the volume becomes absorption only (Volume Absorption, density 1/attenuationDistance) and the Principled BSDF gets no subsurface, so reflected light does not spread".into(),
    });
    if with_scatter {
        let widest = v.mean_free_path_mm.into_iter().fold(0.0, f64::max);
        let drawn = spec;
        out.push(Reading {
            reader: "Babylon.js OpenPBRMaterial (glTF loader with useOpenPBR)",
            fields: vec![
                ("subsurfaceRadius", json!(widest * 1e-3)),
                (
                    "subsurfaceRadiusScale",
                    json!(v.mean_free_path_mm.map(|l| l / widest)),
                ),
                ("subsurfaceColor", json!(v.albedo)),
            ],
            error: worst(shape_error(look.as_ref(), &drawn)),
            how: "subsurfaceRadius × subsurfaceRadiusScale = 1/σt, subsurfaceColor = the multi-scatter colour: OpenPBR's mean free path and albedo, the extensions' own reading".into(),
        });
    }
    Ok(out)
}

/// What Babylon.js's default `PBRMaterial` draws from the file: its
/// glTF loader turns diffuse transmission into translucency.
fn babylon_pbr_reading(
    preset: &Preset,
    v: &GltfVolume,
    thickness_m: f64,
    with_scatter: bool,
) -> Reading {
    let tint = preset
        .rendering
        .transmission_tint
        .map(|t| t.clamp(0.0, 1.0));
    // KHR_materials_volume's loader multiplies diffusionDistance (white)
    // by attenuationColor and attenuationDistance when only diffuse
    // transmission is on (pbrMaterialLoadingAdapter.ts, the
    // transmissionColor and transmissionDepth setters). With the draft,
    // its subsurfaceColor setter then takes that product as a colour at a
    // depth of 0.001: σ = −ln(c·D)/0.001, and diffusionDistance =
    // exp(−σ/max σ).
    let product = v.attenuation_color.map(|c| c * v.attenuation_distance_m);
    let diffusion_distance = if with_scatter {
        let sigma = product.map(|p| -p.ln() / 0.001);
        let max = sigma.into_iter().fold(0.0, f64::max);
        if max > 0.0 {
            sigma.map(|s| (-s / max).exp())
        } else {
            [1.0; 3]
        }
    } else {
        product
    };
    Reading {
        reader: "Babylon.js PBRMaterial (glTF loader's default)",
        fields: vec![
            ("subSurface.isTranslucencyEnabled", json!(true)),
            ("subSurface.translucencyIntensity", json!(1.0)),
            ("subSurface.tintColor", json!(tint)),
            (
                "subSurface.diffusionDistance",
                json!(diffusion_distance),
            ),
            ("subSurface.maximumThickness", json!(thickness_m)),
            ("subSurface.volumeIndexOfRefraction", json!(preset.rendering.ior)),
            ("subSurface.isScatteringEnabled", json!(false)),
        ],
        // A profile that does not spread: r·R(r) is 0 for r > 0, a
        // relative L2 error of exactly 1.
        error: 1.0,
        how: "diffuse transmission becomes translucency (light through thin parts); screen-space scattering stays off unless the application turns on its pre-pass, so reflected light does not spread".into(),
    }
}

/// One sentence per reading, for the export notes.
fn reading_line(r: &Reading) -> String {
    format!("{}: shape error {:.4}; {}.", r.reader, r.error, r.how)
}

/// What the glTF export cannot hold exactly, one sentence each: the fit,
/// and what each known reader draws (with the draft extension, as
/// `--gltf-volume-scatter` writes it).
pub fn gltf_notes(preset: &Preset) -> Result<Vec<String>, ModelError> {
    let (_, fit_error) = burley_of(&preset.profile)?;
    let readings = gltf_readings(preset, SPHERE_RADIUS_M * 2.0, true)?;
    let mut notes = vec![who_draws_it(&readings), fit_note(fit_error)];
    notes.push(format!(
        "{VOLUME_SCATTER} is a draft (KhronosGroup/glTF PR #2453): written only with --gltf-volume-scatter; without it readers get no albedo for the volume"
    ));
    for r in &readings {
        notes.push(reading_line(r));
    }
    Ok(notes)
}

/// The notes' first line: which readers draw the scattering the file
/// holds and which draw none (a shape error of 1: nothing spreads), so
/// that "error 1.0" reads as what those readers do, not as a broken file.
fn who_draws_it(readings: &[Reading]) -> String {
    let names = |draws: bool| {
        readings
            .iter()
            .filter(|r| (r.error < 0.999) == draws)
            .map(|r| r.reader)
            .collect::<Vec<_>>()
            .join("; ")
    };
    let (some, none) = (names(true), names(false));
    match (some.is_empty(), none.is_empty()) {
        (false, false) => format!(
            "Who draws the scattering: {some}. Who draws none, whatever the file holds (their glTF materials do not spread light under the surface): {none}. The file is the same for all."
        ),
        (false, true) => format!("Who draws the scattering: {some}."),
        _ => format!("No known reader draws this file's scattering: {none}."),
    }
}

/// The `.gltf` document of a look on `mesh`, with the buffer inline.
pub fn gltf_document(
    preset: &Preset,
    prov: &Provenance,
    mesh: GltfMesh,
    with_scatter: bool,
) -> Result<String, ExportError> {
    let data = match mesh {
        GltfMesh::Head => head()?,
        GltfMesh::Sphere => sphere(),
    };
    document(preset, prov, data, with_scatter)
}

/// The `.gltf` document of a look on the artist's mesh `on`, with its UVs,
/// its colour map as the base colour's texture (as the editor draws it)
/// and its normal map, all inline.
pub fn gltf_document_on(
    preset: &Preset,
    prov: &Provenance,
    on: &GltfOnMesh,
    with_scatter: bool,
) -> Result<String, ExportError> {
    // The colour the viewport tints a map to: the look's albedo as it is
    // drawn (a kernel model's surface albedo, not a Burley fit's A).
    let albedo = crate::settings::albedo::look_albedo(preset);
    document(preset, prov, mesh_data_on(on, albedo)?, with_scatter)
}

fn document(
    preset: &Preset,
    prov: &Provenance,
    data: MeshData,
    with_scatter: bool,
) -> Result<String, ExportError> {
    use base64::Engine as _;
    let (v, fit_error) = gltf_volume(preset)?;
    let readings = gltf_readings(preset, data.thickness_m, with_scatter)?;
    let skin = SkinMaterial {
        volume: &v,
        fit_error,
        readings: &readings,
        thickness_m: data.thickness_m,
        with_scatter,
    };
    let mut materials = vec![skin.material(preset, prov)];
    let mut buffer = Buffer::default();
    let primitives = buffer.primitives(&data, &mut materials);
    let maps = buffer.maps(&data, &mut materials[0]);
    let mut used = vec![VOLUME, DIFFUSE_TRANSMISSION, IOR];
    if with_scatter {
        used.push(VOLUME_SCATTER);
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&buffer.bytes)
    );
    let mut doc = json!({
        "asset": {
            "version": "2.0",
            "generator": format!("scatterlab {}", env!("CARGO_PKG_VERSION")),
            "extras": {"source": prov.line()},
        },
        "extensionsUsed": used,
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": data.name, "mesh": 0}],
        "meshes": [{"name": data.name, "primitives": primitives}],
        "materials": materials,
        "accessors": buffer.accessors,
        "bufferViews": buffer.views,
        "buffers": [{"byteLength": buffer.bytes.len(), "uri": uri}],
    });
    if let Some((images, textures)) = maps {
        // 9729 LINEAR, 9987 LINEAR_MIPMAP_LINEAR, 10497 REPEAT (§5.26).
        doc["samplers"] =
            json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}]);
        doc["images"] = json!(images);
        doc["textures"] = json!(textures);
    }
    serde_json::to_string_pretty(&doc).map_err(|e| ExportError::Encode {
        path: "glTF".into(),
        message: e.to_string(),
    })
}

/// What the skin's material is made of: the look's volume and fit, each
/// reader's reading, the mesh's thickness and whether the draft
/// `KHR_materials_volume_scatter` is written.
struct SkinMaterial<'a> {
    volume: &'a GltfVolume,
    fit_error: f64,
    readings: &'a [Reading],
    thickness_m: f64,
    with_scatter: bool,
}

impl SkinMaterial<'_> {
    /// The skin's glTF material: its extensions, and the mapping and the
    /// readers' readings in its `extras`.
    fn material(&self, preset: &Preset, prov: &Provenance) -> Value {
        let (v, fit_error, readings) = (self.volume, self.fit_error, self.readings);
        let with_scatter = self.with_scatter;
        let name = if preset.name.trim().is_empty() {
            "look".to_owned()
        } else {
            preset.name.clone()
        };
        let a = v.albedo;
        let rendering = &preset.rendering;
        let tint = rendering.transmission_tint.map(|t| t.clamp(0.0, 1.0));
        let mut extensions = serde_json::Map::new();
        extensions.insert(
            VOLUME.into(),
            json!({
                "thicknessFactor": self.thickness_m,
                "attenuationDistance": v.attenuation_distance_m,
                "attenuationColor": v.attenuation_color,
            }),
        );
        extensions.insert(
            DIFFUSE_TRANSMISSION.into(),
            json!({"diffuseTransmissionFactor": 1.0, "diffuseTransmissionColorFactor": tint}),
        );
        extensions.insert(IOR.into(), json!({"ior": rendering.ior}));
        if with_scatter {
            // README line 72 names it multiscatterColorFactor, the schema
            // (line 8) and older readers multiscatterColor: both, the same.
            extensions.insert(
                VOLUME_SCATTER.into(),
                json!({"multiscatterColorFactor": a, "multiscatterColor": a, "scatterAnisotropy": 0.0}),
            );
        }
        let extras = json!({
            "scatterlab": {
                "written_by": prov.line(),
                "look": name,
                "burley": {
                    "albedo": a,
                    "mean_free_path_mm": v.mean_free_path_mm,
                    "fit": fit_note(fit_error),
                },
                "mapping": "multi-scatter colour = Burley's A; 1/σt = ℓ = d·s(A), Christensen & Burley 2015 eq. 5; attenuationDistance = max ℓ (m); attenuationColor = exp(−attenuationDistance/ℓ)",
                "readings": readings.iter().map(|r| json!({
                    "reader": r.reader,
                    "fields": r.fields.iter().map(|(k, v)| (k.to_string(), v.clone())).collect::<serde_json::Map<_, _>>(),
                    "shape_error": r.error,
                    "how": r.how,
                })).collect::<Vec<_>>(),
            }
        });
        json!({
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [a[0], a[1], a[2], 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": rendering.specular.roughness,
            },
            "extensions": extensions,
            "extras": extras,
        })
    }
}

/// The glTF parameters of a Burley profile for `convert --to gltf`.
fn params(burley: &Burley, _world_scale: Option<f64>) -> Result<Value, ModelError> {
    let v = volume_of(burley);
    Ok(json!({
        VOLUME: {
            "attenuationDistance_m": v.attenuation_distance_m,
            "attenuationColor": v.attenuation_color,
        },
        VOLUME_SCATTER: {"multiscatterColorFactor": v.albedo},
        "baseColorFactor": v.albedo,
    }))
}

/// glTF as an export target.
pub(super) const TARGET: super::Target = super::Target {
    id: "gltf",
    name: "glTF 2.0 (volume extensions)",
    description: "a .gltf on the mesh on screen (with its maps) or the head or a sphere; KHR_materials_volume and diffuse transmission, each reader's error stated",
    extension: "gltf",
    companion: None,
    slow: false,
    write: |preset, prov, out, _, options| {
        let text = match &options.gltf_on_mesh {
            Some(on) => gltf_document_on(preset, prov, on, options.gltf_volume_scatter)?,
            None => gltf_document(preset, prov, options.gltf_mesh, options.gltf_volume_scatter)?,
        };
        super::write(out, text.as_bytes())
    },
    notes: gltf_notes,
    fidelity: super::burley_fidelity,
    params: Some(params),
    reader: Some(super::Reader {
        extensions: &["gltf"],
        claims: |ext, _| ext == "gltf",
        read,
    }),
};

#[cfg(test)]
mod tests {
    use super::*;

    /// σt = −ln(c)/D gives back 1/ℓ per channel (KHR_materials_volume
    /// README line 150), and the widest channel's colour is e⁻¹.
    #[test]
    fn attenuation_gives_back_the_mean_free_path() {
        let (v, _) = gltf_volume(&Preset::default_skin()).unwrap();
        for c in 0..3 {
            let sigma_t = -v.attenuation_color[c].ln() / (v.attenuation_distance_m * 1e3);
            assert!((sigma_t * v.mean_free_path_mm[c] - 1.0).abs() < 1e-12);
        }
        assert!(v
            .attenuation_color
            .iter()
            .any(|c| (c - (-1.0f64).exp()).abs() < 1e-15));
    }

    /// The draft's Kulla–Conty inversion (PR #2453 README line 126) maps a
    /// multi-scatter albedo of 0 to 0 and 1 to 1 (its published end points
    /// checked numerically, the typo check this module's docs promise): the
    /// multi-scatter colour is an albedo in 0–1, as Burley's A is.
    #[test]
    fn the_drafts_inversion_spans_0_to_1() {
        let ss = |a: f64| {
            let s = 4.09712 + 4.20863 * a - (9.59217 + 41.6808 * a + 17.7126 * a * a).sqrt();
            1.0 - s * s
        };
        assert!(ss(0.0).abs() < 1e-3, "{}", ss(0.0));
        assert!((ss(1.0) - 1.0).abs() < 1e-3, "{}", ss(1.0));
        assert!(ss(0.5) > 0.5 && ss(0.5) < 1.0);
    }

    /// The sphere is closed and its normals are unit length (the
    /// validator's ACCESSOR_VECTOR3_NON_UNIT is an error).
    #[test]
    fn the_sphere_is_sound() {
        let s = sphere();
        for n in &s.normals {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((l - 1.0).abs() < 1e-6);
        }
        let tris = s.parts[0].1.len() / 3;
        assert_eq!(tris, 2 * 64 * 32 - 2 * 64);
    }
}
