//! Blender's Principled BSDF subsurface (Christensen–Burley in Cycles),
//! both ways: the Python snippet that sets it, and the reader of that
//! snippet. The conversion is `model::units::BlenderSubsurface`.

use super::{asset_name, burley_of, fit_note, Provenance};
use crate::model::units::BlenderSubsurface;
use crate::model::ModelError;
use crate::settings::Preset;

/// Blender's Principled BSDF (Christensen–Burley) as a Python snippet that
/// sets it on the active object's material: Subsurface Radius and Scale
/// from `model::units::BlenderSubsurface` (d = Radius × Scale / 4π, as
/// Cycles reads it), the scale divided by the scene's Unit Scale at run time
/// so scenes in centimetres get the same millimetres, and the profile's
/// albedo as Base Color unless a texture already drives it. Checked with
/// Blender 4.5.15 and 5.0.1 (PyPI `bpy`, tests/real_clients.rs renders it in Cycles);
/// the socket names are those of Blender 4.0 and later, and
/// `Material.use_nodes`, deprecated in 5.0, is only set before 5.0.
pub fn blender_python(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    let b = BlenderSubsurface::from_burley(&burley, 1.0)?;
    let c = b.subsurface_radius;
    let a = burley.albedo();
    let d = burley.scattering_distance_mm();
    Ok(format!(
        r#"# Blender Principled BSDF subsurface for "{name}": {line}.
# {note}.
# Cycles (Blender 3.0+, kernel/closure/bssrdf.h bssrdf_setup_radius) uses
# Burley's d = Subsurface Radius x Subsurface Scale / (4 pi) in scene units,
# with Base Color as the albedo. This look: d = ({d0:.6}, {d1:.6}, {d2:.6}) mm,
# albedo ({a0:.6}, {a1:.6}, {a2:.6}).
# Needs Blender 4.0 or later (Principled BSDF v2 socket names); checked with
# Blender 4.5.15 and 5.0.1. EEVEE approximates Burley with its own screen-space blur.
# Select a mesh object and run this in Blender's Python console or Text Editor.
import bpy

NAME = "{asset}"
SUBSURFACE_RADIUS = ({r0}, {r1}, {r2})
SUBSURFACE_SCALE_M = {scale}  # metres; divided by the scene's Unit Scale below
BASE_COLOR = ({a0}, {a1}, {a2}, 1.0)
IOR = {ior}

if bpy.app.version < (4, 0, 0):
    raise RuntimeError("This snippet needs Blender 4.0 or later (Principled BSDF v2).")
obj = bpy.context.object
if obj is None or obj.type != "MESH":
    raise RuntimeError("Select a mesh object first.")
mat = obj.active_material
if mat is None:
    mat = bpy.data.materials.new(NAME)
    if obj.material_slots:
        obj.active_material = mat
    else:
        obj.data.materials.append(mat)
if bpy.app.version < (5, 0, 0):
    mat.use_nodes = True  # Blender 5.0 deprecates it: every material has nodes.
nodes, links = mat.node_tree.nodes, mat.node_tree.links
bsdf = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
if bsdf is None:
    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    out = next((n for n in nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output), None)
    if out is None:
        out = nodes.new("ShaderNodeOutputMaterial")
    links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    print("scatterlab: added a Principled BSDF to", mat.name, "and connected it to the output")
unit_scale = bpy.context.scene.unit_settings.scale_length or 1.0
bsdf.subsurface_method = "BURLEY"
if bsdf.inputs["Base Color"].is_linked:
    print("scatterlab: Base Color is driven by a texture; it stays (the albedo of this look is", BASE_COLOR[:3], ")")
else:
    bsdf.inputs["Base Color"].default_value = BASE_COLOR
bsdf.inputs["Subsurface Weight"].default_value = 1.0
bsdf.inputs["Subsurface Radius"].default_value = SUBSURFACE_RADIUS
bsdf.inputs["Subsurface Scale"].default_value = SUBSURFACE_SCALE_M / unit_scale
bsdf.inputs["IOR"].default_value = IOR
print("scatterlab: set", mat.name, "for a scene of", unit_scale, "m per unit")
"#,
        name = preset.name.replace(['\n', '\r'], " "),
        line = prov.line(),
        note = fit_note(fit_error),
        asset = asset_name(&preset.name),
        r0 = c[0],
        r1 = c[1],
        r2 = c[2],
        scale = b.subsurface_scale,
        d0 = d[0],
        d1 = d[1],
        d2 = d[2],
        a0 = a[0],
        a1 = a[1],
        a2 = a[2],
        ior = preset.rendering.ior,
    ))
}

/// Reads the Blender snippet scatterlab writes back: its `NAME`,
/// `SUBSURFACE_RADIUS`, `SUBSURFACE_SCALE_M` (metres; the snippet divides
/// it by the scene's unit scale, so the look is in metres whatever the
/// scene), `BASE_COLOR` and `IOR` assignments, through
/// `BlenderSubsurface::to_burley` (Cycles' d = Radius × Scale / 4π). A
/// Blender scene itself is read by the add-on in `tools/blender/`, which
/// writes a scatterlab look.
pub fn read(
    text: &str,
    path: &std::path::Path,
) -> Result<Vec<super::ImportedLook>, super::ImportError> {
    use super::ImportError;
    use crate::settings::profile::{BurleyShape, BurleySpec};
    use crate::settings::ProfileSpec;
    let value = |key: &str| -> Option<(usize, &str)> {
        text.lines().enumerate().find_map(|(i, l)| {
            let (k, v) = l.split_once('=')?;
            (k.trim() == key).then(|| (i + 1, v.split('#').next().unwrap_or("").trim()))
        })
    };
    let numbers = |key: &str, n: usize| -> Result<Vec<f64>, ImportError> {
        let (line, v) = value(key).ok_or_else(|| {
            ImportError::field(path, key, "missing: not a scatterlab Blender snippet")
        })?;
        let inner = v.trim_start_matches('(').trim_end_matches(')');
        let parts: Vec<f64> = inner
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        ImportError::field(
                            path,
                            key,
                            format!("line {line}: \"{s}\" is not a finite number"),
                        )
                    })
            })
            .collect::<Result<_, _>>()?;
        if parts.len() < n {
            return Err(ImportError::field(
                path,
                key,
                format!("line {line}: {} values, {n} needed", parts.len()),
            ));
        }
        Ok(parts)
    };
    let radius = numbers("SUBSURFACE_RADIUS", 3)?;
    let scale = numbers("SUBSURFACE_SCALE_M", 1)?[0];
    let colour = numbers("BASE_COLOR", 3)?;
    let ior = numbers("IOR", 1)?[0];
    let s = BlenderSubsurface {
        base_color: [colour[0], colour[1], colour[2]],
        subsurface_radius: [radius[0], radius[1], radius[2]],
        subsurface_scale: scale,
        metres_per_unit: 1.0,
    };
    let burley = s
        .to_burley()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    // The look's name is quoted on the snippet's first line.
    let name = text
        .lines()
        .next()
        .and_then(|l| l.split('"').nth(1))
        .filter(|n| !n.trim().is_empty())
        .map(str::to_owned)
        .unwrap_or_else(|| "Imported Blender material".into());
    let preset = Preset {
        name,
        description: "Read from scatterlab's Blender Principled BSDF snippet.".into(),
        source: path.display().to_string(),
        profile: ProfileSpec::Burley(BurleySpec {
            albedo: burley.albedo(),
            shape: BurleyShape::ScatteringDistance {
                mm: burley.scattering_distance_mm(),
                multiplier: 1.0,
            },
        }),
        rendering: crate::settings::RenderingSpec {
            ior: ior.clamp(1.0, 2.0),
            ..Default::default()
        },
        ..Preset::default()
    };
    preset
        .validate()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    let fields = [
        "SUBSURFACE_RADIUS",
        "SUBSURFACE_SCALE_M",
        "BASE_COLOR",
        "IOR",
    ]
    .iter()
    .filter_map(|k| value(k).map(|(_, v)| (k.to_string(), v.to_owned())))
    .collect();
    Ok(vec![super::ImportedLook {
        preset,
        kind: "Blender Principled BSDF (scatterlab .py)",
        fields,
        notes: vec![
            "Cycles reads Burley's d = Radius × Scale / (4π) with Base Color as the albedo".into(),
        ],
    }])
}

/// Blender's Principled BSDF snippet as an export target.
pub(super) const TARGET: super::Target = super::Target {
    id: "blender",
    name: "Blender Principled BSDF",
    description: "a .py snippet setting subsurface radius, scale and weight",
    extension: "py",
    companion: None,
    slow: false,
    write: |preset, prov, out, _, _| super::write(out, blender_python(preset, prov)?.as_bytes()),
    notes: |preset| {
        Ok(vec![
            super::burley_note(preset)?,
            "Cycles renders it exactly (Christensen–Burley); EEVEE approximates it. Blender 4.0+ (checked with 4.5 and 5.0).".into(),
        ])
    },
    fidelity: super::burley_fidelity,
    params: Some(|b, world_scale| {
        let u = BlenderSubsurface::from_burley(b, world_scale.unwrap_or(1.0))?;
        Ok(serde_json::json!({
            "base_color": u.base_color,
            "subsurface_radius": u.subsurface_radius,
            "subsurface_scale": u.subsurface_scale,
            "metres_per_unit": u.metres_per_unit,
            "subsurface_method": "Christensen-Burley",
        }))
    }),
    reader: Some(super::Reader {
        extensions: &["py"],
        claims: |ext, text| ext == "py" && text.contains("import bpy"),
        read: |text, path, _| read(text, path),
    }),
};
