//! The reader of a Substrate material's nodes as Unreal's material editor
//! copies them (T3D: `Begin Object Class=… Name="…"` declarations, then
//! `Begin Object Name="…"` blocks of `Property=Value` lines in UE's struct
//! text). Names, from UE 5.8's MaterialExpressionSubstrate.h: the Slab
//! (`MaterialExpressionSubstrateSlabBSDF`) has the inputs `DiffuseAlbedo`,
//! `Roughness`, `SSSMFP`, `SSSMFPScale` (each `(Expression="…'Node'")`), a
//! `SubsurfaceProfile` and a `SubSurfaceType` (MSS_Diffusion when left
//! out: the constructor's value in MaterialExpressionSubstrate.cpp); a
//! `MaterialExpressionConstant3Vector` holds `Constant=(R=…,G=…,B=…,A=…)`
//! and a `MaterialExpressionConstant` `R=…`. Substrate.ush
//! (`InternalGetSubstrateSlabBSDF`): a plugged profile wins over the MFP,
//! an unplugged MFP scatters nothing, SSSMFPScale is saturated, and the
//! unplugged Diffuse Albedo is 0.18 (the Slab's `Compile`). The SSS MFP (cm)
//! becomes Burley's d by the SubsurfaceProfile's conversion, the inverse
//! of [`super::substrate_mfp_cm`]: d = 10·MFP/(0.6·s(A)) mm.

use super::read::{clip, parse_value, Fields, Value};
use crate::export::import::{ImportError, ImportedLook};
use crate::model::burley::ScalingFit;
use crate::model::units::UNREAL_DMFP_TO_MFP;
use crate::model::Rgb;
use crate::settings::rendering::RenderingSpec;
use std::path::Path;

/// The Slab's `Compile` default for an unplugged Diffuse Albedo.
const DEFAULT_DIFFUSE_ALBEDO: f64 = 0.18;

/// One object of the text: its class (from its declaration) and fields.
struct Object {
    class: String,
    fields: Fields,
}

/// `Name="X"` or `Name=X` on a `Begin Object` line.
fn attribute(line: &str, key: &str) -> Option<String> {
    let at = line.find(&format!("{key}="))? + key.len() + 1;
    let rest = &line[at..];
    Some(match rest.strip_prefix('"') {
        Some(r) => r.split('"').next().unwrap_or("").to_owned(),
        None => rest.split_whitespace().next().unwrap_or("").to_owned(),
    })
}

/// Every object of the text by name.
fn objects(text: &str, path: &Path) -> Result<Vec<(String, Object)>, ImportError> {
    let mut out: Vec<(String, Object)> = Vec::new();
    // The objects whose property block is open, innermost last.
    let mut stack: Vec<Option<String>> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if let Some(rest) = line.strip_prefix("Begin Object") {
            let name = attribute(rest, "Name");
            match (attribute(rest, "Class"), name) {
                (Some(class), Some(name)) => {
                    if let Some(o) = out.iter_mut().find(|(k, _)| *k == name) {
                        o.1.class = class;
                    } else {
                        out.push((
                            name.clone(),
                            Object {
                                class,
                                fields: Fields::default(),
                            },
                        ));
                    }
                    stack.push(Some(name));
                }
                (None, Some(name)) => stack.push(Some(name)),
                _ => stack.push(None),
            }
            continue;
        }
        if line == "End Object" {
            if stack.pop().is_none() {
                return Err(ImportError::file(
                    path,
                    format!("line {}: End Object without Begin Object", n + 1),
                ));
            }
            continue;
        }
        let Some(Some(current)) = stack.last() else {
            continue;
        };
        let Some(eq) = line.find('=') else {
            continue;
        };
        let key = line[..eq].trim();
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        let (value, _) = parse_value(&line[eq + 1..], path, 0).map_err(|_| {
            ImportError::field(
                path,
                format!("{current}.{key}"),
                format!(
                    "line {}: \"{}\" is not UE struct text",
                    n + 1,
                    clip(&line[eq + 1..])
                ),
            )
        })?;
        let current = current.clone();
        match out.iter_mut().find(|(k, _)| *k == current) {
            Some(o) => o.1.fields.0.push((key.to_owned(), value)),
            None => out.push((
                current,
                Object {
                    class: String::new(),
                    fields: Fields(vec![(key.to_owned(), value)]),
                },
            )),
        }
    }
    if !stack.is_empty() {
        return Err(ImportError::file(path, "a Begin Object has no End Object"));
    }
    Ok(out)
}

/// Whether `text` is a material editor's copied nodes.
pub fn claims(text: &str) -> bool {
    text.trim_start().starts_with("Begin Object")
}

/// The object an input `(Expression="/Script/Engine.Class'Outer.Name'")`
/// points at.
fn linked<'a>(objects: &'a [(String, Object)], input: &Value) -> Option<&'a Object> {
    let Value::Struct(f) = input else {
        return None;
    };
    let Some(Value::Word(reference)) = f.get("Expression") else {
        return None;
    };
    let inner = reference.split('\'').nth(1).unwrap_or(reference);
    let name = inner.rsplit('.').next().unwrap_or(inner);
    objects.iter().find(|(k, _)| k == name).map(|(_, o)| o)
}

fn num(v: Option<&Value>) -> Option<f64> {
    match v {
        Some(Value::Number(x)) if x.is_finite() => Some(*x),
        _ => None,
    }
}

/// The constant an input of the Slab is plugged into: `None` when the
/// input is not plugged; an error naming it when something other than a
/// constant drives it.
fn constant(
    objects: &[(String, Object)],
    slab: &str,
    fields: &Fields,
    input: &str,
    path: &Path,
) -> Result<Option<Rgb>, ImportError> {
    let Some(v) = fields.get(input) else {
        return Ok(None);
    };
    let field = format!("{slab}.{input}");
    let o = linked(objects, v).ok_or_else(|| {
        ImportError::field(
            path,
            &field,
            "its node is not in the copied text: copy the Slab with the constants that feed it",
        )
    })?;
    let bad = |what: &str| ImportError::field(path, &field, what.to_owned());
    if o.class.ends_with("MaterialExpressionConstant3Vector") {
        let Some(Value::Struct(c)) = o.fields.get("Constant") else {
            // An unset Constant is UE's default, black.
            return Ok(Some([0.0; 3]));
        };
        let ch = |k: &str| num(c.get(k)).unwrap_or(0.0);
        Ok(Some([ch("R"), ch("G"), ch("B")]))
    } else if o.class.ends_with("MaterialExpressionConstant") {
        let r = num(o.fields.get("R")).unwrap_or(0.0);
        Ok(Some([r; 3]))
    } else {
        Err(bad(&format!(
            "driven by a {} node: scatterlab reads constants (Constant, Constant3Vector) only",
            o.class.rsplit('.').next().unwrap_or(&o.class)
        )))
    }
}

/// Every Substrate Slab in a material editor's copied text, as a look.
pub fn read(text: &str, path: &Path) -> Result<Vec<ImportedLook>, ImportError> {
    let objects = objects(text, path)?;
    let slabs: Vec<&(String, Object)> = objects
        .iter()
        .filter(|(_, o)| o.class.ends_with("MaterialExpressionSubstrateSlabBSDF"))
        .collect();
    if slabs.is_empty() {
        return Err(ImportError::not_engine(
            path,
            "copied material nodes without a Substrate Slab (MaterialExpressionSubstrateSlabBSDF)",
        ));
    }
    slabs
        .into_iter()
        .map(|(name, slab)| read_slab(&objects, name, slab, path))
        .collect()
}

/// One Substrate Slab `name` of the copied nodes as a look.
fn read_slab(
    objects: &[(String, Object)],
    name: &str,
    slab: &Object,
    path: &Path,
) -> Result<ImportedLook, ImportError> {
    let f = &slab.fields;
    let mut fields = Vec::new();
    let mut notes = Vec::new();
    subsurface_type(name, f, path, (&mut fields, &mut notes))?;
    let albedo = match constant(objects, name, f, "DiffuseAlbedo", path)? {
        Some(a) => a,
        None => {
            notes.push(format!(
                "DiffuseAlbedo is not plugged: the Slab's default, {DEFAULT_DIFFUSE_ALBEDO}"
            ));
            [DEFAULT_DIFFUSE_ALBEDO; 3]
        }
    };
    if let Some(c) = (0..3).find(|&c| !(0.0..=1.0).contains(&albedo[c])) {
        return Err(ImportError::field(
            path,
            format!("{name}.DiffuseAlbedo"),
            format!("{} is outside 0–1", albedo[c]),
        ));
    }
    let mfp = constant(objects, name, f, "SSSMFP", path)?.ok_or_else(|| {
        ImportError::field(
            path,
            format!("{name}.SSSMFP"),
            "not plugged and no SubsurfaceProfile: Substrate draws no subsurface scattering",
        )
    })?;
    let scale = constant(objects, name, f, "SSSMFPScale", path)?
        .map(|s| s[0])
        .unwrap_or(1.0);
    let scale_used = scale.clamp(0.0, 1.0);
    if scale_used != scale {
        notes.push(format!(
            "SSSMFPScale {scale} is saturated to {scale_used}, as Substrate does"
        ));
    }
    fields.push(("DiffuseAlbedo".into(), format!("{albedo:?}")));
    fields.push(("SSSMFP (cm)".into(), format!("{mfp:?}")));
    fields.push(("SSSMFPScale".into(), scale.to_string()));
    let mfp_mm: Rgb = std::array::from_fn(|c| mfp[c] * scale_used * 10.0);
    if let Some(c) = (0..3).find(|&c| !(mfp_mm[c] > 0.0)) {
        return Err(ImportError::field(
            path,
            format!("{name}.SSSMFP"),
            format!(
                "{} cm in {} (× scale {scale_used}): not a distance light scatters",
                mfp[c],
                ["red", "green", "blue"][c]
            ),
        ));
    }
    // d = 10·MFP/(0.6·s(A)) mm: UE's mean free path is 0.6 × the
    // physical one (its Dmfp2MfpMagicNumber).
    let d: Rgb = std::array::from_fn(|c| {
        mfp_mm[c] / (UNREAL_DMFP_TO_MFP * ScalingFit::Perpendicular.scale(albedo[c]))
    });
    notes.push("the SSS MFP is read as a SubsurfaceProfile's mean free path is (0.6 × the physical path): that Substrate's per-pixel path converts it the same way is assumed".into());
    let mut rendering = RenderingSpec::default();
    if let Some(r) = constant(objects, name, f, "Roughness", path)? {
        rendering.specular.roughness = r[0].clamp(0.0, 1.0);
    }
    // The material the nodes were copied from, where the Slab says
    // (`Material="…'/Path/M_Skin'"`), names the look.
    let look_name = match f.get("Material") {
        Some(Value::Word(m)) => m
            .split('\'')
            .nth(1)
            .and_then(|p| p.rsplit(['.', '/']).next())
            .filter(|n| !n.is_empty())
            .unwrap_or(name)
            .to_owned(),
        _ => name.to_owned(),
    };
    let preset = crate::export::import::burley_preset(
        path,
        look_name,
        "Read from a Substrate Slab copied from Unreal's material editor.",
        albedo,
        d,
        rendering,
    );
    preset
        .validate()
        .map_err(|e| ImportError::field(path, format!("{name}.SSSMFP"), e.to_string()))?;
    Ok(ImportedLook {
        preset,
        kind: "Unreal Substrate Slab (copied material nodes)",
        fields,
        notes,
    })
}

/// The Slab's subsurface type, which must scatter by a diffusion profile,
/// and no SubsurfaceProfile asset the copied nodes do not hold.
fn subsurface_type(
    name: &str,
    f: &Fields,
    path: &Path,
    (fields, notes): (&mut Vec<(String, String)>, &mut Vec<String>),
) -> Result<(), ImportError> {
    match f.get("SubSurfaceType") {
        None => {
            notes.push("SubSurfaceType is left out: UE's default for a Slab, MSS_Diffusion".into())
        }
        Some(Value::Word(w)) if w == "MSS_Diffusion" || w == "MSS_DiffusionProfile" => {
            fields.push(("SubSurfaceType".into(), w.clone()));
        }
        Some(other) => {
            return Err(ImportError::field(
                path,
                format!("{name}.SubSurfaceType"),
                format!(
                    "{} is not a diffusion profile (only MSS_Diffusion scatters by a profile)",
                    match other {
                        Value::Word(w) => w.clone(),
                        _ => "a struct".into(),
                    }
                ),
            ))
        }
    }
    if let Some(p) = f.get("SubsurfaceProfile") {
        let which = match p {
            Value::Word(w) => w.clone(),
            _ => "a profile".into(),
        };
        if which != "None" {
            return Err(ImportError::field(
                path,
                format!("{name}.SubsurfaceProfile"),
                format!("the Slab draws {which}, which the copied nodes do not hold: import that profile's struct text (its Details panel, Settings, Copy)"),
            ));
        }
    }
    Ok(())
}
