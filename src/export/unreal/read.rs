//! The reader of Unreal's SubsurfaceProfile: the struct text the details
//! panel copies (`(SurfaceAlbedo=(R=…,G=…,B=…,A=…),MeanFreePathDistance=…,…)`,
//! UE's `ImportText` syntax) and the Python snippet scatterlab writes
//! (`settings.set_editor_property("surface_albedo", unreal.LinearColor(…))`).
//! Both become one map of UE field names, read by one function.

use super::super::import::{ImportError, ImportedLook};
use crate::model::units::UnrealProfile;
use crate::model::Rgb;
use crate::settings::profile::{BurleyShape, BurleySpec};
use crate::settings::rendering::{DualLobeSpec, RenderingSpec, TexturingId};
use crate::settings::{Preset, ProfileSpec};
use std::path::Path;

/// A struct's fields in the order written.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct Fields(pub(super) Vec<(String, Value)>);

impl Fields {
    pub(super) fn get(&self, key: &str) -> Option<&Value> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }
    fn insert(&mut self, key: String, value: Value) {
        self.0.retain(|(k, _)| *k != key);
        self.0.push((key, value));
    }
    fn contains_key(&self, key: &str) -> bool {
        self.get(key).is_some()
    }
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    fn iter(&self) -> impl Iterator<Item = &(String, Value)> {
        self.0.iter()
    }
}

/// A value of UE's struct text: a number, a word (True, an enum), a
/// quoted string or a nested struct.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Value {
    Number(f64),
    Word(String),
    Struct(Fields),
}

/// UE's defaults of the fields scatterlab reads, where a copy leaves one
/// out (`FSubsurfaceProfileStruct`'s constructor, SubsurfaceProfile.h, UE
/// 5.1.1 lines 114–134; its `bEnableMeanFreePath` is false, so a default
/// profile reaches UE 5.1+ through the diffuse-mean-free-path upgrade).
const DEFAULT_IOR: f64 = 1.55;
const DEFAULT_ROUGHNESS: [f64; 2] = [0.75, 1.30];
const DEFAULT_LOBE_MIX: f64 = 0.85;

/// Every look in an Unreal struct text or scatterlab Unreal .py (one).
pub fn read(text: &str, path: &Path) -> Result<Vec<ImportedLook>, ImportError> {
    let (fields, name, kind) = if text.contains("import unreal") {
        let name = text
            .lines()
            .next()
            .and_then(|l| l.split('"').nth(1))
            .map(str::to_owned);
        (
            python_fields(text, path)?,
            name,
            "Unreal SubsurfaceProfile (scatterlab .py)",
        )
    } else {
        let body = text.trim();
        let (v, rest) = parse_value(body, path, 0)?;
        if !rest.trim().is_empty() {
            return Err(ImportError::file(
                path,
                format!(
                    "text after the struct's closing ')': \"{}\"",
                    clip(rest.trim())
                ),
            ));
        }
        let Value::Struct(map) = v else {
            return Err(ImportError::file(
                path,
                "not an Unreal struct: it does not start with '('",
            ));
        };
        (map, None, "Unreal SubsurfaceProfile (details-panel text)")
    };
    let name = name.unwrap_or_else(|| {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "Imported Unreal profile".into())
    });
    Ok(vec![look_from_fields(&fields, &name, kind, path)?])
}

pub(super) fn clip(s: &str) -> String {
    s.chars().take(40).collect()
}

/// `(Key=Value,…)`, recursively; returns the value and the rest.
pub(super) fn parse_value<'a>(
    s: &'a str,
    path: &Path,
    depth: usize,
) -> Result<(Value, &'a str), ImportError> {
    if depth > 8 {
        return Err(ImportError::file(
            path,
            "structs nested deeper than any UE subsurface field",
        ));
    }
    let s = s.trim_start();
    if let Some(mut rest) = s.strip_prefix('(') {
        let mut map = Fields::default();
        loop {
            rest = rest.trim_start();
            if let Some(r) = rest.strip_prefix(')') {
                return Ok((Value::Struct(map), r));
            }
            let eq = rest.find('=').ok_or_else(|| {
                ImportError::file(
                    path,
                    format!("malformed struct text: no '=' after \"{}\"", clip(rest)),
                )
            })?;
            let key = rest[..eq].trim();
            if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(ImportError::file(
                    path,
                    format!(
                        "malformed struct text: \"{}\" is not a field name",
                        clip(key)
                    ),
                ));
            }
            let (v, r) = parse_value(&rest[eq + 1..], path, depth + 1)?;
            map.insert(key.to_owned(), v);
            rest = r.trim_start();
            if let Some(r) = rest.strip_prefix(',') {
                rest = r;
            } else if !rest.starts_with(')') {
                return Err(ImportError::file(
                    path,
                    format!(
                        "malformed struct text: expected ',' or ')' at \"{}\"",
                        clip(rest)
                    ),
                ));
            }
        }
    }
    if let Some(rest) = s.strip_prefix('"') {
        let end = rest
            .find('"')
            .ok_or_else(|| ImportError::file(path, "malformed struct text: an unclosed string"))?;
        return Ok((Value::Word(rest[..end].to_owned()), &rest[end + 1..]));
    }
    let end = s.find([',', ')']).unwrap_or(s.len());
    let token = s[..end].trim();
    if token.is_empty() {
        return Err(ImportError::file(
            path,
            "malformed struct text: a field without a value",
        ));
    }
    let v = match token.parse::<f64>() {
        Ok(x) => Value::Number(x),
        Err(_) => Value::Word(token.to_owned()),
    };
    Ok((v, &s[end..]))
}

/// The fields a scatterlab Unreal .py sets, under UE's names.
fn python_fields(text: &str, path: &Path) -> Result<Fields, ImportError> {
    let mut map = Fields::default();
    for (i, line) in text.lines().enumerate() {
        let Some(rest) = line.trim().strip_prefix("settings.set_editor_property(\"") else {
            continue;
        };
        let (py_name, rest) = rest.split_once('"').unwrap_or(("", ""));
        let value = rest
            .trim_start_matches([',', ' '])
            .strip_suffix(')')
            .unwrap_or("")
            .trim();
        let ue = match py_name {
            "surface_albedo" => "SurfaceAlbedo",
            "mean_free_path_color" => "MeanFreePathColor",
            "mean_free_path_distance" => "MeanFreePathDistance",
            "world_unit_scale" => "WorldUnitScale",
            "transmission_tint_color" => "TransmissionTintColor",
            "ior" => "IOR",
            "roughness0" => "Roughness0",
            "roughness1" => "Roughness1",
            "lobe_mix" => "LobeMix",
            "enable_burley" => "bEnableBurley",
            "enable_mean_free_path" => "bEnableMeanFreePath",
            other => {
                return Err(ImportError::field(
                    path,
                    format!("line {}: {other}", i + 1),
                    "not a SubsurfaceProfileStruct property scatterlab writes",
                ))
            }
        };
        let v = if let Some(args) = value
            .strip_prefix("unreal.LinearColor(")
            .and_then(|a| a.strip_suffix(')'))
        {
            let parts: Vec<&str> = args.split(',').map(str::trim).collect();
            if parts.len() != 4 {
                return Err(ImportError::field(
                    path,
                    ue,
                    format!("line {}: a LinearColor needs four values", i + 1),
                ));
            }
            let mut m = Fields::default();
            for (k, p) in ["R", "G", "B", "A"].into_iter().zip(parts) {
                let x: f64 = p.parse().map_err(|_| {
                    ImportError::field(
                        path,
                        format!("{ue}.{k}"),
                        format!("line {}: \"{p}\" is not a number", i + 1),
                    )
                })?;
                m.insert(k.to_owned(), Value::Number(x));
            }
            Value::Struct(m)
        } else if let Ok(x) = value.parse::<f64>() {
            Value::Number(x)
        } else {
            Value::Word(value.to_owned())
        };
        map.insert(ue.to_owned(), v);
    }
    if map.is_empty() {
        return Err(ImportError::file(
            path,
            "a Python file that sets no SubsurfaceProfileStruct property: not a scatterlab Unreal snippet",
        ));
    }
    Ok(map)
}

fn number(
    fields: &Fields,
    key: &str,
    default: Option<f64>,
    path: &Path,
) -> Result<f64, ImportError> {
    match fields.get(key) {
        Some(Value::Number(x)) if x.is_finite() => Ok(*x),
        Some(Value::Number(x)) => Err(ImportError::field(
            path,
            key,
            format!("{x} is not a finite number"),
        )),
        Some(Value::Word(w)) => Err(ImportError::field(
            path,
            key,
            format!("\"{w}\" is not a number"),
        )),
        Some(Value::Struct(_)) => Err(ImportError::field(
            path,
            key,
            "a struct where a number belongs",
        )),
        None => default.ok_or_else(|| ImportError::field(path, key, "missing")),
    }
}

fn colour(
    fields: &Fields,
    key: &str,
    default: Option<Rgb>,
    path: &Path,
) -> Result<Rgb, ImportError> {
    match fields.get(key) {
        Some(Value::Struct(m)) => {
            let mut c = [0.0; 3];
            for (i, k) in ["R", "G", "B"].into_iter().enumerate() {
                c[i] = number(m, k, None, path).map_err(|_| {
                    ImportError::field(path, format!("{key}.{k}"), "missing or not a finite number")
                })?;
            }
            Ok(c)
        }
        Some(_) => Err(ImportError::field(
            path,
            key,
            "not a colour (R=…,G=…,B=…,A=…)",
        )),
        None => default.ok_or_else(|| ImportError::field(path, key, "missing")),
    }
}

fn boolean(fields: &Fields, key: &str, default: bool, path: &Path) -> Result<bool, ImportError> {
    match fields.get(key) {
        Some(Value::Word(w)) if w.eq_ignore_ascii_case("true") => Ok(true),
        Some(Value::Word(w)) if w.eq_ignore_ascii_case("false") => Ok(false),
        Some(_) => Err(ImportError::field(path, key, "not True or False")),
        None => Ok(default),
    }
}

fn show(v: &Value) -> String {
    match v {
        Value::Number(x) => x.to_string(),
        Value::Word(w) => w.clone(),
        Value::Struct(m) => {
            let parts: Vec<String> = m.iter().map(|(k, v)| format!("{k}={}", show(v))).collect();
            format!("({})", parts.join(","))
        }
    }
}

/// The profile's own fields (albedo, mean free path colour and distance,
/// world unit scale), range-checked as UE clamps them; a diffuse mean free
/// path is upgraded as UE 5.1+ does on load.
fn profile_fields(
    fields: &Fields,
    path: &Path,
    notes: &mut Vec<String>,
) -> Result<UnrealProfile, ImportError> {
    if !boolean(fields, "bEnableBurley", true, path)? {
        return Err(ImportError::field(
            path,
            "bEnableBurley",
            "False: a separable (pre-Burley) profile. UE 5 converts it on load by a fit of FalloffColor that differs between UE versions; open it in UE 5.1 or later and copy the profile again",
        ));
    }
    let albedo = colour(fields, "SurfaceAlbedo", None, path)?;
    let mfp_colour = colour(fields, "MeanFreePathColor", None, path)?;
    let distance = number(fields, "MeanFreePathDistance", None, path)?;
    let world_unit_scale = number(fields, "WorldUnitScale", Some(0.1), path)?;
    for (k, c) in [("SurfaceAlbedo", albedo), ("MeanFreePathColor", mfp_colour)] {
        if let Some(i) = (0..3).find(|&i| !(0.0..=1.0).contains(&c[i])) {
            return Err(ImportError::field(
                path,
                format!("{k}.{}", ["R", "G", "B"][i]),
                format!("{} is outside 0–1 (UE's ClampMin/ClampMax)", c[i]),
            ));
        }
    }
    if !(distance > 0.0 && distance <= 50.0) {
        return Err(ImportError::field(
            path,
            "MeanFreePathDistance",
            format!("{distance} cm is outside UE's range (0.1–50 cm)"),
        ));
    }
    if !(world_unit_scale > 0.0 && world_unit_scale <= 50.0) {
        return Err(ImportError::field(
            path,
            "WorldUnitScale",
            format!("{world_unit_scale} is outside UE's range (up to 50)"),
        ));
    }
    let mean_free_path = boolean(fields, "bEnableMeanFreePath", false, path)?;
    Ok(if mean_free_path {
        UnrealProfile {
            surface_albedo: albedo,
            mean_free_path_color: mfp_colour,
            mean_free_path_distance_cm: distance,
            world_unit_scale,
        }
    } else {
        notes.push("bEnableMeanFreePath is False: the colour and distance are a diffuse mean free path, which UE 5.1+ upgrades on load (UpgradeDiffuseMeanFreePathToMeanFreePath), as here".into());
        UnrealProfile::upgrade_from_diffuse_mean_free_path(
            albedo,
            mfp_colour,
            distance,
            world_unit_scale,
        )
    })
}

/// The look UE 5.1+ renders from a SubsurfaceProfileStruct.
fn look_from_fields(
    fields: &Fields,
    name: &str,
    kind: &'static str,
    path: &Path,
) -> Result<ImportedLook, ImportError> {
    let mut notes = Vec::new();
    let profile = profile_fields(fields, path, &mut notes)?;
    let burley = profile
        .to_burley()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    let tint = colour(fields, "TransmissionTintColor", Some([1.0; 3]), path)?;
    let ior = number(fields, "IOR", Some(DEFAULT_IOR), path)?;
    let r0 = number(fields, "Roughness0", Some(DEFAULT_ROUGHNESS[0]), path)?;
    let r1 = number(fields, "Roughness1", Some(DEFAULT_ROUGHNESS[1]), path)?;
    let mix = number(fields, "LobeMix", Some(DEFAULT_LOBE_MIX), path)?;
    if !(1.0..=3.0).contains(&ior) {
        return Err(ImportError::field(
            path,
            "IOR",
            format!("{ior} is outside UE's 1–3"),
        ));
    }
    let ior = if ior > 2.0 {
        notes.push(format!(
            "IOR {ior} is held as 2, the highest scatterlab's specular takes"
        ));
        2.0
    } else {
        ior
    };
    for (k, v, lo, hi) in [
        ("Roughness0", r0, 0.0, 2.0),
        ("Roughness1", r1, 0.0, 2.0),
        ("LobeMix", mix, 0.0, 1.0),
    ] {
        if !(lo..=hi).contains(&v) {
            return Err(ImportError::field(
                path,
                k,
                format!("{v} is outside {lo}–{hi}"),
            ));
        }
    }
    for k in [
        "Tint",
        "BoundaryColorBleed",
        "ExtinctionScale",
        "NormalScale",
        "ScatteringDistribution",
    ] {
        if fields.contains_key(k) {
            notes.push(format!("{k} has no counterpart in scatterlab: not used"));
        }
    }
    notes
        .push("UE applies the base colour after scattering: read as Post-Scatter texturing".into());
    let preset = Preset {
        name: name.to_owned(),
        description: "Read from an Unreal SubsurfaceProfile.".into(),
        source: path.display().to_string(),
        profile: ProfileSpec::Burley(BurleySpec {
            albedo: burley.albedo(),
            shape: BurleyShape::ScatteringDistance {
                mm: burley.scattering_distance_mm(),
                multiplier: 1.0,
            },
        }),
        rendering: RenderingSpec {
            texturing: TexturingId::PostScatter,
            transmission_tint: tint,
            ior,
            specular: DualLobeSpec {
                lobe0_roughness_multiplier: r0,
                lobe1_roughness_multiplier: r1,
                lobe_mix: mix,
                ..DualLobeSpec::default()
            },
            ..RenderingSpec::default()
        },
        ..Preset::default()
    };
    preset
        .validate()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    Ok(ImportedLook {
        preset,
        kind,
        fields: fields.iter().map(|(k, v)| (k.clone(), show(v))).collect(),
        notes,
    })
}
