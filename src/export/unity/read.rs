//! The reader of HDRP's diffusion profile assets (see the module above for
//! the HDRP sources each rule comes from).

use super::*;
use yaml_rust2::YamlLoader;

/// HDRP's `DiffusionProfileSettings.Version` (Migration.cs).
const VERSIONS: [&str; 3] = [
    "Initial",
    "DiffusionProfileRework",
    "SplitScatteringDistance",
];

/// The shortest distance HDRP draws: `UpdateKernel` caps S = 1/d at 2²⁴
/// per mm, so d = 0 there is d = 2⁻²⁴ mm, scattering nothing.
const HDRP_MIN_DISTANCE_MM: f64 = 1.0 / 16_777_216.0;

/// Keys under which HDRP assets keep references to profile assets:
/// a volume component's `diffusionProfiles` (`DiffusionProfileList`,
/// `DiffusionProfileOverride`; the list is its `m_Value`), the HDRP Global
/// Settings' and the older HDRP asset's `diffusionProfileSettingsList`,
/// the latter's `m_ObsoleteDiffusionProfileSettingsList` and the single
/// `diffusionProfileSettings` of HDRP 5–6.
const REFERENCE_KEYS: [&str; 4] = [
    "diffusionProfiles",
    "diffusionProfileSettingsList",
    "m_ObsoleteDiffusionProfileSettingsList",
    "diffusionProfileSettings",
];

/// Every diffusion profile in a Unity YAML asset: one per profile asset
/// (m_Version 1, 2), up to 16 in an m_Version 0 asset, and those a list
/// or volume profile refers to, read from the assets their GUIDs name.
pub fn read(text: &str, path: &Path) -> Result<Vec<ImportedLook>, ImportError> {
    read_depth(text, path, 0)
}

fn read_depth(text: &str, path: &Path, depth: usize) -> Result<Vec<ImportedLook>, ImportError> {
    let mut looks = Vec::new();
    let mut references = Vec::new();
    let mut behaviours = 0;
    for (line, doc) in documents(text, path)? {
        let mb = &doc["MonoBehaviour"];
        if mb.is_badvalue() {
            continue;
        }
        behaviours += 1;
        let at = |field: &str| format!("MonoBehaviour (line {line}).{field}");
        let profile = &mb["profile"];
        let profiles = mb["profiles"].as_vec().filter(|v| !v.is_empty());
        collect_references(mb, &at(""), &mut references);
        if !is_map(profile) && profiles.is_none() {
            // Another Unity object (a volume component, a list).
            continue;
        }
        let version = match &mb["m_Version"] {
            Yaml::BadValue => {
                // Assets from before the field (HDRP 5–6) hold an array.
                if profiles.is_some() && !is_map(profile) {
                    0
                } else {
                    return Err(ImportError::field(
                        path,
                        at("m_Version"),
                        "missing: HDRP writes it in every diffusion profile asset",
                    ));
                }
            }
            v => {
                let n = v.as_i64().ok_or_else(|| {
                    ImportError::field(
                        path,
                        at("m_Version"),
                        format!("{} is not an integer", show(v)),
                    )
                })?;
                usize::try_from(n).ok().filter(|n| *n < VERSIONS.len()).ok_or_else(|| {
                    ImportError::field(
                        path,
                        at("m_Version"),
                        format!(
                            "{n} is not a version HDRP has written (0 {}, 1 {}, 2 {}); a newer HDRP may have written it",
                            VERSIONS[0], VERSIONS[1], VERSIONS[2]
                        ),
                    )
                })?
            }
        };
        let asset_name = mb["m_Name"].as_str().unwrap_or("").to_owned();
        if version == 0 {
            for (i, p) in profiles.into_iter().flatten().enumerate() {
                let field = format!("profiles[{i}]");
                looks.push(profile_look(p, path, &at(&field), version, &asset_name)?);
            }
        } else if is_map(profile) {
            looks.push(profile_look(
                profile,
                path,
                &at("profile"),
                version,
                &asset_name,
            )?);
        }
    }
    if looks.is_empty() && !references.is_empty() {
        if depth > 0 {
            return Err(ImportError::file(
                path,
                "a list of diffusion profiles refers to another list, not to a profile",
            ));
        }
        for (field, guid) in references {
            let asset = find_asset(path, &guid).ok_or_else(|| {
                ImportError::field(
                    path,
                    &field,
                    format!(
                        "the profile with GUID {guid} is not in this Unity project (no .meta file with it in the Assets folder the file is in, or beside the file outside a project); import the profile's .asset itself"
                    ),
                )
            })?;
            let text = super::super::import::read_text(&asset)?;
            looks.extend(read_depth(&text, &asset, depth + 1)?);
        }
    }
    if looks.is_empty() {
        // A Unity asset of another kind (a material, lighting data, a
        // volume profile without a diffusion profile list).
        return Err(ImportError::not_engine(
            path,
            if behaviours == 0 {
                "no Unity object in the file: not an HDRP asset".to_owned()
            } else {
                "no diffusion profile in the file: it holds neither a `profile` (HDRP 2019.1 and later), a `profiles` array (earlier) nor a list of profile references".to_owned()
            },
        ));
    }
    Ok(looks)
}

/// The YAML documents of a Unity asset, each with the line of its `---`
/// header. Unity declares its `!u!` tag once at the top and uses it on
/// every document, which YAML allows only on the first, so each document
/// is parsed on its own without the header (its class and anchor are not
/// needed to read profiles).
fn documents(text: &str, path: &Path) -> Result<Vec<(usize, Yaml)>, ImportError> {
    let mut out = Vec::new();
    let mut body = String::new();
    let mut start = 1;
    let mut flush = |body: &mut String, start: usize| -> Result<(), ImportError> {
        if body.trim().is_empty() {
            body.clear();
            return Ok(());
        }
        let docs = YamlLoader::load_from_str(body).map_err(|e| {
            let m = e.marker();
            ImportError::file(
                path,
                format!("malformed YAML at line {}: {}", start + m.line(), e.info()),
            )
        })?;
        out.extend(docs.into_iter().map(|d| (start, d)));
        body.clear();
        Ok(())
    };
    for (i, line) in text.lines().enumerate() {
        if line.starts_with('%') {
            body.push('\n');
            continue;
        }
        if line.starts_with("---") {
            flush(&mut body, start)?;
            start = i + 1;
            // The header line stays as an empty line so line numbers match.
            body.push('\n');
            continue;
        }
        body.push_str(line);
        body.push('\n');
    }
    flush(&mut body, start)?;
    Ok(out)
}

fn is_map(y: &Yaml) -> bool {
    y.as_hash().is_some()
}

fn show(y: &Yaml) -> String {
    match y {
        Yaml::Real(s) | Yaml::String(s) => format!("\"{s}\""),
        Yaml::Integer(i) => i.to_string(),
        Yaml::Boolean(b) => b.to_string(),
        Yaml::Null => "empty".into(),
        Yaml::Array(_) => "a list".into(),
        Yaml::Hash(_) => "a mapping".into(),
        _ => "not a value".into(),
    }
}

/// A number field: finite, or an error naming it.
fn number(y: &Yaml, path: &Path, field: &str) -> Result<f64, ImportError> {
    let v = match y {
        Yaml::Real(_) => y.as_f64(),
        Yaml::Integer(i) => Some(*i as f64),
        _ => None,
    };
    match v {
        Some(v) if v.is_finite() => Ok(v),
        Some(v) => Err(ImportError::field(
            path,
            field,
            format!("{v} is not a finite number"),
        )),
        None if y.is_badvalue() => Err(ImportError::field(path, field, "missing")),
        None => Err(ImportError::field(
            path,
            field,
            format!("{} is not a number", show(y)),
        )),
    }
}

/// An optional number: `None` where the field is absent.
fn optional(y: &Yaml, path: &Path, field: &str) -> Result<Option<f64>, ImportError> {
    if y.is_badvalue() {
        Ok(None)
    } else {
        number(y, path, field).map(Some)
    }
}

fn color(y: &Yaml, path: &Path, field: &str) -> Result<Rgb, ImportError> {
    if !is_map(y) {
        return Err(ImportError::field(
            path,
            field,
            if y.is_badvalue() {
                "missing".to_owned()
            } else {
                format!("{} is not a colour {{r, g, b, a}}", show(y))
            },
        ));
    }
    Ok([
        number(&y["r"], path, &format!("{field}.r"))?,
        number(&y["g"], path, &format!("{field}.g"))?,
        number(&y["b"], path, &format!("{field}.b"))?,
    ])
}

fn vector2(y: &Yaml, path: &Path, field: &str) -> Result<(f64, f64), ImportError> {
    if !is_map(y) {
        return Err(ImportError::field(
            path,
            field,
            "missing or not a vector {x, y}",
        ));
    }
    Ok((
        number(&y["x"], path, &format!("{field}.x"))?,
        number(&y["y"], path, &format!("{field}.y"))?,
    ))
}

fn enum_field(y: &Yaml, path: &Path, field: &str, names: &[&str]) -> Result<usize, ImportError> {
    let v = number(y, path, field)?;
    let i = v as usize;
    if v < 0.0 || v.fract() != 0.0 || i >= names.len() {
        let known: Vec<String> = names
            .iter()
            .enumerate()
            .map(|(i, n)| format!("{i} {n}"))
            .collect();
        return Err(ImportError::field(
            path,
            field,
            format!("{v} is not one of HDRP's values ({})", known.join(", ")),
        ));
    }
    Ok(i)
}

fn rgb_text(c: Rgb) -> String {
    format!("({}, {}, {})", c[0], c[1], c[2])
}

/// HDRP's scattering distance (one HDR colour before version 2, an LDR
/// colour and its multiplier from version 2), checked, as (colour in mm,
/// multiplier); a distance HDRP draws as no scattering is held at
/// scatterlab's shortest.
fn distance_fields(
    p: &Yaml,
    path: &Path,
    at: &str,
    version: usize,
    fields: &mut Vec<(String, String)>,
    notes: &mut Vec<String>,
) -> Result<(Rgb, f64), ImportError> {
    let f = |name: &str| format!("{at}.{name}");
    // The distance: one HDR colour before version 2; an LDR colour and its
    // multiplier from version 2 (the product is HDRP's d, in mm at the
    // profile's world scale).
    let colour = color(&p["scatteringDistance"], path, &f("scatteringDistance"))?;
    fields.push(("scatteringDistance".into(), rgb_text(colour)));
    let multiplier = if version >= 2 {
        let m = number(
            &p["scatteringDistanceMultiplier"],
            path,
            &f("scatteringDistanceMultiplier"),
        )?;
        fields.push(("scatteringDistanceMultiplier".into(), m.to_string()));
        if m < 0.0 {
            return Err(ImportError::field(
                path,
                f("scatteringDistanceMultiplier"),
                format!("{m} is negative (HDRP's [Min(0)])"),
            ));
        }
        m
    } else {
        1.0
    };
    for (c, name) in ["r", "g", "b"].into_iter().enumerate() {
        if colour[c] < 0.0 {
            return Err(ImportError::field(
                path,
                format!("{}.{name}", f("scatteringDistance")),
                format!("{} is negative: a distance is at least 0", colour[c]),
            ));
        }
    }
    let d: Rgb = std::array::from_fn(|c| colour[c] * multiplier);
    let max_mm = crate::model::burley::DISTANCE_RANGE_MM.1;
    if let Some(c) = (0..3).find(|&c| d[c] > max_mm) {
        return Err(ImportError::field(
            path,
            f("scatteringDistance"),
            format!(
                "{} mm in {} is over {max_mm} mm: not a distance light scatters in a real material",
                d[c],
                ["red", "green", "blue"][c]
            ),
        ));
    }
    // d = 0 (S capped at 2²⁴) scatters nothing; scatterlab's shortest
    // distance, 0.1 µm, draws the same at any pixel size.
    let min_mm = crate::model::burley::DISTANCE_RANGE_MM.0;
    let short: Vec<&str> = (0..3)
        .filter(|&c| d[c] < min_mm)
        .map(|c| ["red", "green", "blue"][c])
        .collect();
    if !short.is_empty() {
        notes.push(format!(
            "HDRP's distance in {} is {} mm or less (it draws it as {:.1e} mm: no scattering); held as {min_mm} mm",
            short.join(" and "),
            min_mm,
            HDRP_MIN_DISTANCE_MM
        ));
    }
    let (mm, multiplier) = if multiplier > 0.0 {
        (
            std::array::from_fn(|c| colour[c].max(min_mm / multiplier)),
            multiplier,
        )
    } else {
        ([min_mm; 3], 1.0)
    };
    Ok((mm, multiplier))
}

/// `texturingMode` and `transmissionMode`, as indices of their values.
fn mode_fields(
    p: &Yaml,
    path: &Path,
    at: &str,
    fields: &mut Vec<(String, String)>,
) -> Result<(usize, usize), ImportError> {
    let f = |name: &str| format!("{at}.{name}");
    let texturing = enum_field(
        &p["texturingMode"],
        path,
        &f("texturingMode"),
        &["PreAndPostScatter", "PostScatter"],
    )?;
    fields.push((
        "texturingMode".into(),
        format!(
            "{texturing} ({})",
            ["Pre and Post-Scatter", "Post-Scatter"][texturing]
        ),
    ));
    let transmission = enum_field(
        &p["transmissionMode"],
        path,
        &f("transmissionMode"),
        &["Regular", "ThinObject"],
    )?;
    fields.push((
        "transmissionMode".into(),
        format!(
            "{transmission} ({})",
            ["Thick Object", "Thin Object"][transmission]
        ),
    ));
    Ok((texturing, transmission))
}

/// `smoothnessMultipliers`, `lobeMix` and `diffuseShadingPower`.
type DualLobeFields = (Option<(f64, f64)>, Option<f64>, Option<f64>);

/// The dual lobe's fields (HDRP 15 and later), each `None` where the file
/// has none; the profile's hash is listed with them.
fn dual_lobe_fields(
    p: &Yaml,
    path: &Path,
    at: &str,
    fields: &mut Vec<(String, String)>,
) -> Result<DualLobeFields, ImportError> {
    let f = |name: &str| format!("{at}.{name}");
    // Dual lobe (HDRP 15 and later); a file without it reads 0, and
    // `Validate` puts the defaults back where diffuseShadingPower is 0.
    let smoothness = if is_map(&p["smoothnessMultipliers"]) {
        Some(vector2(
            &p["smoothnessMultipliers"],
            path,
            &f("smoothnessMultipliers"),
        )?)
    } else {
        None
    };
    let lobe_mix = optional(&p["lobeMix"], path, &f("lobeMix"))?;
    let power = optional(&p["diffuseShadingPower"], path, &f("diffuseShadingPower"))?;
    if let Some((x, y)) = smoothness {
        fields.push(("smoothnessMultipliers".into(), format!("({x}, {y})")));
    }
    if let Some(m) = lobe_mix {
        fields.push(("lobeMix".into(), m.to_string()));
    }
    if let Some(pw) = power {
        fields.push(("diffuseShadingPower".into(), pw.to_string()));
    }
    if let Some(h) = p["hash"].as_i64() {
        fields.push(("hash".into(), h.to_string()));
    }
    Ok((smoothness, lobe_mix, power))
}

/// HDRP's `Validate` clamps of the thickness remap, world scale and IOR,
/// each clamp noted.
fn hdrp_validate(
    (remap_lo, remap_hi): (f64, f64),
    world_scale: f64,
    ior: f64,
    notes: &mut Vec<String>,
) -> ((f64, f64), f64, f64) {
    let remap_hi_v = remap_hi.max(0.0);
    let remap_lo_v = remap_lo.clamp(0.0, remap_hi_v);
    let world_scale_v = world_scale.max(0.001);
    let ior_v = ior.clamp(1.0, 2.0);
    for (field, read, used) in [
        ("thicknessRemap.y", remap_hi, remap_hi_v),
        ("thicknessRemap.x", remap_lo, remap_lo_v),
        ("worldScale", world_scale, world_scale_v),
        ("ior", ior, ior_v),
    ] {
        if read != used {
            notes.push(format!(
                "HDRP clamps {field} {read} to {used} (Validate), as here"
            ));
        }
    }
    ((remap_lo_v, remap_hi_v), world_scale_v, ior_v)
}

/// One serialized `DiffusionProfile` as the look HDRP renders from it.
fn profile_look(
    p: &Yaml,
    path: &Path,
    at: &str,
    version: usize,
    asset_name: &str,
) -> Result<ImportedLook, ImportError> {
    let f = |name: &str| format!("{at}.{name}");
    let mut fields = vec![(
        "m_Version".to_owned(),
        format!("{version} ({})", VERSIONS[version]),
    )];
    let mut notes = Vec::new();
    let name = p["name"]
        .as_str()
        .filter(|n| !n.trim().is_empty())
        .unwrap_or(asset_name)
        .to_owned();
    if !name.is_empty() {
        fields.push(("name".into(), name.clone()));
    }
    let (mm, multiplier) = distance_fields(p, path, at, version, &mut fields, &mut notes)?;
    let tint = color(&p["transmissionTint"], path, &f("transmissionTint"))?;
    fields.push(("transmissionTint".into(), rgb_text(tint)));
    let (texturing, transmission) = mode_fields(p, path, at, &mut fields)?;
    let (remap_lo, remap_hi) = vector2(&p["thicknessRemap"], path, &f("thicknessRemap"))?;
    fields.push((
        "thicknessRemap".into(),
        format!("({remap_lo}, {remap_hi}) mm"),
    ));
    let world_scale = number(&p["worldScale"], path, &f("worldScale"))?;
    fields.push(("worldScale".into(), format!("{world_scale} m/unit")));
    let ior = number(&p["ior"], path, &f("ior"))?;
    fields.push(("ior".into(), ior.to_string()));
    let (smoothness, lobe_mix, power) = dual_lobe_fields(p, path, at, &mut fields)?;

    // `Validate`: the clamps every loaded profile goes through.
    let clamped = hdrp_validate((remap_lo, remap_hi), world_scale, ior, &mut notes);
    let ((remap_lo_v, remap_hi_v), world_scale_v, ior_v) = clamped;
    let (smooth, mix) = match (smoothness, lobe_mix, power) {
        (Some(s), Some(m), Some(p)) if p != 0.0 => (s, m),
        _ => ((1.0, 1.0), 0.5),
    };
    if let Some(p) = power.filter(|p| *p != 0.0 && *p != 1.0) {
        notes.push(format!(
            "diffuseShadingPower {p} (a power on the diffuse cosine) has no counterpart in scatterlab: ignored"
        ));
    }
    let specular = dual_lobe_from_smoothness(
        smooth.0.clamp(0.0, 1.0),
        smooth.1.clamp(1.0, 2.0),
        mix.clamp(0.0, 1.0),
    );
    notes.push(format!(
        "HDRP keeps the albedo in the material: the profile's albedo is 1, as HDRP's filter is normalised; its dual lobe scales smoothness and is read at scatterlab's base roughness {}",
        specular.roughness
    ));
    let tint_v: Rgb = std::array::from_fn(|c| tint[c].clamp(0.0, 16.0));
    if tint_v != tint {
        notes.push(format!(
            "transmissionTint {} is held within 0–16 as {}",
            rgb_text(tint),
            rgb_text(tint_v)
        ));
    }
    let world_scale_max = 1e3;
    if world_scale_v > world_scale_max {
        return Err(ImportError::field(
            path,
            f("worldScale"),
            format!("{world_scale} m per unit is over {world_scale_max}: not a scene scale"),
        ));
    }
    let preset = Preset {
        name: if name.is_empty() {
            "Imported HDRP profile".into()
        } else {
            name
        },
        description: format!(
            "Read from a Unity HDRP diffusion profile (m_Version {version}, {}).",
            VERSIONS[version]
        ),
        source: path.display().to_string(),
        profile: ProfileSpec::Burley(BurleySpec {
            albedo: [1.0; 3],
            shape: BurleyShape::ScatteringDistance { mm, multiplier },
        }),
        rendering: RenderingSpec {
            texturing: [TexturingId::PreAndPostScatter, TexturingId::PostScatter][texturing],
            transmission: [TransmissionId::ThickObject, TransmissionId::ThinObject][transmission],
            thickness_remap_mm: (remap_lo_v, remap_hi_v),
            transmission_tint: tint_v,
            ior: ior_v,
            world_scale_m_per_unit: world_scale_v,
            specular,
            albedo_in_material: true,
            ..RenderingSpec::default()
        },
        ..Preset::default()
    };
    preset
        .validate()
        .map_err(|e| ImportError::field(path, at, e.to_string()))?;
    Ok(ImportedLook {
        preset,
        kind: "Unity HDRP diffusion profile",
        fields,
        notes,
    })
}

/// Our dual-lobe roughness multipliers from HDRP's smoothness multipliers
/// at scatterlab's base roughness ρ: the inverse of `unity_dual_lobe`
/// (a lobe of smoothness multiplier k has roughness 1 − k(1 − ρ), i.e. a
/// roughness multiplier (1 − k(1 − ρ))/ρ; HDRP's `lobeMix` weights the
/// smoother lobe, ours the rougher).
pub fn dual_lobe_from_smoothness(secondary: f64, primary: f64, lobe_mix: f64) -> DualLobeSpec {
    let base = DualLobeSpec::default();
    let rho = base.roughness;
    let mult = |k: f64| ((1.0 - k * (1.0 - rho)) / rho).clamp(0.0, 2.0);
    DualLobeSpec {
        roughness: rho,
        lobe0_roughness_multiplier: mult(primary),
        lobe1_roughness_multiplier: mult(secondary),
        lobe_mix: 1.0 - lobe_mix,
    }
}

/// `(field, guid)` of every profile reference under the known keys.
fn collect_references(mb: &Yaml, at: &str, out: &mut Vec<(String, String)>) {
    for key in REFERENCE_KEYS {
        let v = &mb[key];
        let list: Vec<(String, &Yaml)> = if let Some(items) = v["m_Value"].as_vec() {
            items
                .iter()
                .enumerate()
                .map(|(i, y)| (format!("{at}{key}.m_Value[{i}]"), y))
                .collect()
        } else if let Some(items) = v.as_vec() {
            items
                .iter()
                .enumerate()
                .map(|(i, y)| (format!("{at}{key}[{i}]"), y))
                .collect()
        } else if is_map(v) {
            vec![(format!("{at}{key}"), v)]
        } else {
            Vec::new()
        };
        for (field, item) in list {
            if let Some(guid) = item["guid"].as_str().filter(|g| !g.is_empty()) {
                out.push((field, guid.to_owned()));
            }
        }
    }
}

/// The asset whose `.meta` file has `guid`: searched in the Unity
/// project's `Assets` folder the file is in, or, outside a project, in the
/// file's own folder (never higher, so a stray list does not walk the
/// disk), to a bounded number of files.
fn find_asset(from: &Path, guid: &str) -> Option<PathBuf> {
    let needle = format!("guid: {guid}");
    let folder = from.parent()?;
    let root = folder
        .ancestors()
        .find(|a| a.file_name().is_some_and(|n| n == "Assets"))
        .unwrap_or(folder);
    search_meta(root, &needle, &mut 0, 0)
}

fn search_meta(dir: &Path, needle: &str, visited: &mut usize, depth: usize) -> Option<PathBuf> {
    const MAX_FILES: usize = 50_000;
    if depth > 12 || *visited > MAX_FILES {
        return None;
    }
    let entries = std::fs::read_dir(dir).ok()?;
    let mut subdirs = Vec::new();
    for e in entries.flatten() {
        *visited += 1;
        let p = e.path();
        if p.is_dir() {
            subdirs.push(p);
        } else if p.extension().is_some_and(|x| x == "meta") {
            let hit = std::fs::read_to_string(&p)
                .map(|t| t.lines().any(|l| l.trim() == needle))
                .unwrap_or(false);
            if hit {
                let asset = p.with_extension("");
                if asset.is_file() {
                    return Some(asset);
                }
            }
        }
    }
    subdirs.sort();
    subdirs
        .iter()
        .find_map(|d| search_meta(d, needle, visited, depth + 1))
}
