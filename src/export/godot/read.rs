//! The reader of Godot 4 `StandardMaterial3D` text resources (`.tres`):
//! the look is what Godot draws from the material (see the module above),
//! its fixed kernel (the demo's skin kernel, or its red channel for all
//! three) widened to the width the strength gives under the project
//! settings the export asks for, scaled by the material's albedo. Godot's
//! file holds no profile, so that is all it can give back: a look sent to
//! Godot and read back differs from it by the kernel's fit. The import
//! states that error for a file scatterlab wrote, measured against the look
//! the file names (`round_trip_note`); `convert` and the editor's compare
//! show it for any look.

use super::super::import::{srgb_decode, ImportError, ImportedLook};
use super::{width_for_strength, GODOT_DEPTH_SCALE, GODOT_MIN_STRENGTH, GODOT_SCALE};
use crate::model::jimenez::{Jimenez2012, DEFAULT_FALLOFF, DEFAULT_STRENGTH};
use crate::model::Rgb;
use crate::settings::profile::{GaussianTerm, GaussiansSpec};
use crate::settings::rendering::{DualLobeSpec, RenderingSpec, TexturingId, TransmissionId};
use crate::settings::{Preset, ProfileSpec};
use std::path::Path;

/// A value of Godot's text resource syntax that a material's subsurface
/// fields use (`core/variant/variant_parser.cpp`).
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Number(f64),
    Bool(bool),
    Text(String),
    Color(Rgb),
    Other(String),
}

fn parse_value(v: &str, path: &Path, key: &str, line: usize) -> Result<Value, ImportError> {
    let v = v.trim();
    let err = |m: String| ImportError::field(path, format!("[resource].{key} (line {line})"), m);
    if v == "true" || v == "false" {
        return Ok(Value::Bool(v == "true"));
    }
    if let Some(s) = v.strip_prefix('"').and_then(|s| s.strip_suffix('"')) {
        return Ok(Value::Text(s.to_owned()));
    }
    if let Some(args) = v.strip_prefix("Color(").and_then(|s| s.strip_suffix(')')) {
        let parts: Vec<&str> = args.split(',').map(str::trim).collect();
        if parts.len() != 4 && parts.len() != 3 {
            return Err(err(format!("{v} is not a Color(r, g, b, a)")));
        }
        let mut c = [0.0; 3];
        for i in 0..3 {
            c[i] = parts[i]
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| err(format!("\"{}\" in {v} is not a finite number", parts[i])))?;
        }
        return Ok(Value::Color(c));
    }
    if let Ok(x) = v.parse::<f64>() {
        if !x.is_finite() {
            return Err(err(format!("{x} is not a finite number")));
        }
        return Ok(Value::Number(x));
    }
    Ok(Value::Other(v.to_owned()))
}

/// A StandardMaterial3D's `[resource]` fields: parsed (with their line
/// numbers), as written, and the file's comments.
struct Material<'t> {
    fields: Vec<(String, Value, usize)>,
    raw: Vec<(String, String)>,
    comments: Vec<&'t str>,
}

/// Parses a Godot text resource and checks it is a material with
/// subsurface scattering fields.
fn parse_material<'t>(text: &'t str, path: &Path) -> Result<Material<'t>, ImportError> {
    let mut header = None;
    let mut in_resource = false;
    let mut fields: Vec<(String, Value, usize)> = Vec::new();
    let mut raw = Vec::new();
    let mut comments = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let l = line.trim();
        if let Some(c) = l.strip_prefix(';') {
            comments.push(c.trim());
            continue;
        }
        if l.is_empty() {
            continue;
        }
        if l.starts_with('[') {
            if !l.ends_with(']') {
                return Err(ImportError::file(
                    path,
                    format!("malformed section header at line {line_no}: {l}"),
                ));
            }
            if header.is_none() {
                header = Some(l.to_owned());
            }
            in_resource = l == "[resource]";
            continue;
        }
        if !in_resource {
            continue;
        }
        let (k, v) = l.split_once('=').ok_or_else(|| {
            ImportError::file(
                path,
                format!("malformed line {line_no}: \"{l}\" is not key = value"),
            )
        })?;
        let (k, v) = (k.trim(), v.trim());
        raw.push((k.to_owned(), v.to_owned()));
        fields.push((k.to_owned(), parse_value(v, path, k, line_no)?, line_no));
    }
    let header = header.ok_or_else(|| {
        ImportError::file(path, "no [gd_resource …] header: not a Godot text resource")
    })?;
    let is_material = header.starts_with("[gd_resource")
        && (header.contains("type=\"StandardMaterial3D\"")
            || header.contains("type=\"ORMMaterial3D\""));
    if !is_material {
        return Err(ImportError::file(
            path,
            format!("{header}: not a StandardMaterial3D (the only Godot resource with subsurface scattering fields)"),
        ));
    }
    Ok(Material {
        fields,
        raw,
        comments,
    })
}

pub fn read(text: &str, path: &Path) -> Result<Vec<ImportedLook>, ImportError> {
    let Material {
        fields,
        raw,
        comments,
    } = parse_material(text, path)?;
    let get = |k: &str| {
        fields
            .iter()
            .find(|(n, _, _)| n == k)
            .map(|(_, v, l)| (v, *l))
    };
    let (strength, skin, albedo) = sss_fields(&fields, path)?;
    let mut notes = vec![format!(
        "Godot's kernel is fixed (Jimenez's demo skin kernel{}); the strength sets its width, read with the project settings the export asks for (Subsurface Scattering Scale {GODOT_SCALE}, Depth Scale {GODOT_DEPTH_SCALE}, 1 unit = 1 m): with Godot's defaults the blur is a fraction of the screen, not of the object",
        if skin { ", per channel" } else { ", its red channel for all three" }
    )];
    if strength < GODOT_MIN_STRENGTH {
        notes.push(format!("a strength under {GODOT_MIN_STRENGTH} makes Godot draw no blur: the look scatters nothing"));
    }
    let width_mm = width_for_strength(strength.max(GODOT_MIN_STRENGTH));
    let kernel = if skin {
        Jimenez2012::new(DEFAULT_STRENGTH, DEFAULT_FALLOFF)
    } else {
        Jimenez2012::new([DEFAULT_STRENGTH[0]; 3], [DEFAULT_FALLOFF[0]; 3])
    }
    .map_err(|e| ImportError::file(path, e.to_string()))?;
    let widened = kernel
        .widened(width_mm)
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    let gaussians = gaussian_terms(&widened, albedo);
    use crate::model::RadialProfile;
    let dirac = std::array::from_fn(|c| widened.dirac_weight()[c] * albedo[c]);
    notes.push(format!(
        "one kernel unit is {width_mm:.4} mm; Godot leaves {:.0} % / {:.0} % / {:.0} % of the light unblurred at the entry point",
        100.0 * widened.dirac_weight()[0],
        100.0 * widened.dirac_weight()[1],
        100.0 * widened.dirac_weight()[2]
    ));
    let transmission = match get("subsurf_scatter_transmittance_enabled") {
        Some((Value::Bool(true), _)) => TransmissionId::ThinObject,
        _ => TransmissionId::Off,
    };
    if transmission != TransmissionId::Off {
        notes.push("Godot's transmittance is its own Gaussian of the shadow-map thickness, not the profile's T(d): read as thin-object transmission with the profile's own".into());
    }
    let roughness = match get("roughness") {
        Some((Value::Number(x), _)) => x.clamp(0.0, 1.0),
        _ => 1.0,
    };
    let name = match get("resource_name") {
        Some((Value::Text(s), _)) if !s.trim().is_empty() => s.clone(),
        _ => path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "Imported Godot material".into()),
    };
    let preset = Preset {
        name,
        description: "What Godot 4 draws from a StandardMaterial3D's subsurface scattering.".into(),
        source: path.display().to_string(),
        profile: ProfileSpec::Gaussians(GaussiansSpec { gaussians, dirac }),
        rendering: RenderingSpec {
            texturing: TexturingId::PostScatter,
            transmission,
            specular: DualLobeSpec {
                roughness,
                lobe0_roughness_multiplier: 1.0,
                lobe1_roughness_multiplier: 1.0,
                lobe_mix: 0.5,
            },
            ..RenderingSpec::default()
        },
        ..Preset::default()
    };
    preset
        .validate()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    if let Some(note) = round_trip_note(&comments, path, &preset) {
        notes.push(note);
    }
    let keep = |k: &str| {
        k == "albedo_color"
            || k == "roughness"
            || k == "resource_name"
            || k.starts_with("subsurf_scatter")
    };
    Ok(vec![ImportedLook {
        preset,
        kind: "Godot 4 StandardMaterial3D",
        fields: raw.into_iter().filter(|(k, _)| keep(k)).collect(),
        notes,
    }])
}

/// The subsurface fields a look is read from: the strength, skin mode and
/// albedo (Godot's defaults where they are missing, material.cpp), after
/// checking scattering is on.
fn sss_fields(
    fields: &[(String, Value, usize)],
    path: &Path,
) -> Result<(f64, bool, [f64; 3]), ImportError> {
    let get = |k: &str| {
        fields
            .iter()
            .find(|(n, _, _)| n == k)
            .map(|(_, v, l)| (v, *l))
    };
    let field = |k: &str| format!("[resource].{k}");
    let enabled = match get("subsurf_scatter_enabled") {
        Some((Value::Bool(b), _)) => *b,
        None => false,
        Some(_) => {
            return Err(ImportError::field(
                path,
                field("subsurf_scatter_enabled"),
                "not true or false",
            ))
        }
    };
    if !enabled {
        return Err(ImportError::field(
            path,
            field("subsurf_scatter_enabled"),
            "false or missing: the material has no subsurface scattering to import",
        ));
    }
    // Godot's defaults (material.cpp): strength 0, skin mode off.
    let strength = match get("subsurf_scatter_strength") {
        Some((Value::Number(x), _)) => *x,
        None => 0.0,
        Some(_) => {
            return Err(ImportError::field(
                path,
                field("subsurf_scatter_strength"),
                "not a number",
            ))
        }
    };
    if !(0.0..=1.0).contains(&strength) {
        return Err(ImportError::field(
            path,
            field("subsurf_scatter_strength"),
            format!("{strength} is outside Godot's 0–1"),
        ));
    }
    let skin = matches!(
        get("subsurf_scatter_skin_mode"),
        Some((Value::Bool(true), _))
    );
    let albedo = match get("albedo_color") {
        Some((Value::Color(c), _)) => c.map(srgb_decode),
        None => [1.0; 3],
        Some(_) => {
            return Err(ImportError::field(
                path,
                field("albedo_color"),
                "not a Color",
            ))
        }
    };
    Ok((strength, skin, albedo))
}

/// The widened kernel as Gaussian terms, each weighted by the albedo.
fn gaussian_terms(
    widened: &crate::model::gaussian::GaussianSum,
    albedo: [f64; 3],
) -> Vec<GaussianTerm> {
    // One Gaussian term per channel and kernel term (their variances differ
    // by channel in skin mode), weighted by the albedo; the light Godot
    // leaves at the entry point is the Dirac part.
    let mut gaussians = Vec::new();
    for c in 0..3 {
        for t in widened.channel_terms(c) {
            let mut weights = [0.0; 3];
            weights[c] = t.weight * albedo[c];
            gaussians.push(GaussianTerm {
                variance_mm2: t.variance_mm2,
                weights,
            });
        }
    }
    gaussians
}

/// A file scatterlab wrote names the look it came from in its comments
/// (`Provenance::line`: `written by scatterlab V from "NAME" (PATH)`). Where
/// that look can be found (PATH as written, beside the file, or a shipped
/// preset of that file name) and has that name, the note measures what
/// Godot draws against it (`fit::shape_error` and the total reflectance);
/// otherwise it quotes the error the file states. None for other files.
fn round_trip_note(comments: &[&str], path: &Path, drawn: &Preset) -> Option<String> {
    let line = comments
        .iter()
        .find(|c| c.contains("written by scatterlab "))?;
    let rest = &line[line.find("written by scatterlab ")?..];
    let (_, after) = rest.split_once(" from \"")?;
    let (name, after) = after.split_once("\" (")?;
    let source = after.rsplit_once(')')?.0;
    let source_path = Path::new(source);
    let file_name = source_path.file_name()?.to_str()?;
    let dir = path.parent().unwrap_or(Path::new(""));
    // Only small regular files: a comment must not make the import read a
    // device or a huge file.
    let from_disk = [
        source_path.to_owned(),
        dir.join(source_path),
        dir.join(file_name),
    ]
    .into_iter()
    .find(|p| p.metadata().is_ok_and(|m| m.is_file() && m.len() < 1 << 20))
    .and_then(|p| Preset::load(&p).ok().map(|l| (l, p.display().to_string())));
    let found = from_disk
        .or_else(|| {
            crate::settings::library::load(file_name)
                .ok()
                .map(|l| (l, format!("the shipped preset {file_name}")))
        })
        .filter(|(l, _)| l.name == name);
    let (look, at) = match found {
        Some(f) => f,
        None => {
            let stated = comments
                .iter()
                .find_map(|c| c.split_once("relative L2 error of r·R(r) "))
                .map(|(_, e)| e.trim_end_matches('.').to_owned());
            return Some(match stated {
                Some(e) => format!("written by scatterlab from \"{name}\" ({source}), not found here; the file states Godot's shape error of r·R(r) as {e}"),
                None => format!("written by scatterlab from \"{name}\" ({source}), not found here: open it as Compare A to see what Godot changes"),
            });
        }
    };
    let (target, model) = (look.build_profile().ok()?, drawn.build_profile().ok()?);
    let e = crate::model::fit::shape_error(target.as_ref(), model.as_ref());
    let (t, m) = (target.total_reflectance(), model.total_reflectance());
    let colour: [f64; 3] = std::array::from_fn(|c| {
        if t[c] > 0.0 {
            // Rounded to the 0.1 % shown, without a "-0.0".
            (1000.0 * (m[c] / t[c] - 1.0)).round() / 10.0 + 0.0
        } else {
            0.0
        }
    });
    Some(format!(
        "round trip against \"{name}\" ({at}): Godot draws it with a shape error of r·R(r) of {:.4} (R {:.4}, G {:.4}, B {:.4}) and its total reflectance changed by {:+.1} % / {:+.1} % / {:+.1} %",
        e.iter().fold(0.0f64, |a, b| a.max(*b)),
        e[0], e[1], e[2], colour[0], colour[1], colour[2]
    ))
}
