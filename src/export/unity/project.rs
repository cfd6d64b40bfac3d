//! A Unity project as HDRP sees its diffusion profiles: every
//! `DiffusionProfileSettings` asset with its `.meta` GUID, and every
//! material that names one. HDRP's own code is the reference (HDRP 13,
//! needle-mirror/com.unity.render-pipelines.high-definition, and the
//! Unity-Technologies/Graphics master):
//! - a material holds its profile as `_DiffusionProfileAsset`, the asset's
//!   GUID packed into a Vector4 (`HDUtils.ConvertGUIDToVector4`, HDUtils.cs
//!   lines 913–943: the 32 hex digits as 16 bytes in order, read as four
//!   little-endian floats), and `_DiffusionProfileHash`, the profile's
//!   `hash` as a float's bits (DiffusionProfileMaterialUI.cs lines 38–45,
//!   `HDShadowUtils.Asfloat`); a LayeredLit's layers add 0–3 to both names,
//!   and a Shader Graph property `X` holds the hash with the GUID in
//!   `X_Asset` (DiffusionProfileShaderProperty.cs line 29);
//! - a profile's `hash` is `0x40000000 | (MonoStringHash(guid) & 0x7FFFFF)`
//!   (DiffusionProfileHashTable.cs lines 20–58): a float in [2, 4);
//! - a Diffusion Profile List is a VolumeProfile (script
//!   d7fd9488000d3734a9e00ee676215985) with a `DiffusionProfileList`
//!   component (script 7a7ff42a8c5be6646ad3975f3a54c1eb, the meta of the
//!   former DiffusionProfileOverride.cs) whose `diffusionProfiles.m_Value`
//!   lists references; HDRP draws at most 16 profiles, slot 0 the neutral
//!   one (DiffusionProfileSettings.cs lines 9–10), so a list holds 15
//!   ("Limit of 15 diffusion profiles reached.",
//!   DiffusionProfileSettingsListUI.cs lines 64–66).

use crate::export::import::{ImportError, ImportedLook};
use std::path::{Path, PathBuf};

/// `DiffusionProfileSettings.cs.meta`'s GUID: the `m_Script` of a profile.
pub const PROFILE_SCRIPT_GUID: &str = "b2686e09ec7aef44bad2843e4416f057";
/// `VolumeProfile`'s script GUID.
pub const VOLUME_PROFILE_SCRIPT_GUID: &str = "d7fd9488000d3734a9e00ee676215985";
/// `DiffusionProfileList`'s script GUID.
pub const PROFILE_LIST_SCRIPT_GUID: &str = "7a7ff42a8c5be6646ad3975f3a54c1eb";
/// The profiles a list may hold: 16 slots less the neutral one.
pub const HDRP_LIST_SLOTS: usize = 15;

/// One diffusion profile of the project.
#[derive(Debug, Clone)]
pub struct ProjectProfile {
    pub path: PathBuf,
    pub guid: String,
    pub look: ImportedLook,
}

/// One reference of a material to a profile.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialUse {
    pub material: PathBuf,
    /// The Vector4 property holding the GUID (`_DiffusionProfileAsset`).
    pub asset_property: String,
    /// The float property holding the hash (`_DiffusionProfileHash`).
    pub hash_property: String,
    pub guid: String,
}

/// What a project scan found.
#[derive(Debug, Default)]
pub struct Project {
    pub profiles: Vec<ProjectProfile>,
    /// References to a profile found above.
    pub uses: Vec<MaterialUse>,
    /// References to none of them (a deleted or package profile).
    pub unresolved: Vec<MaterialUse>,
    /// Files looked at and left out, with why.
    pub skipped: Vec<(PathBuf, String)>,
    /// Materials read.
    pub materials: usize,
}

/// The GUID in a `.meta` file's text (`guid: <32 hex>`).
pub fn meta_guid(meta_text: &str) -> Option<String> {
    meta_text.lines().find_map(|l| {
        let g = l.trim().strip_prefix("guid:")?.trim();
        (g.len() == 32 && g.chars().all(|c| c.is_ascii_hexdigit())).then(|| g.to_ascii_lowercase())
    })
}

/// `HDUtils.ConvertGUIDToVector4`: the GUID's 16 bytes, in order, as four
/// little-endian floats.
pub fn guid_to_vector4(guid: &str) -> Option<[f32; 4]> {
    if guid.len() != 32 || !guid.is_ascii() {
        return None;
    }
    let mut bytes = [0u8; 16];
    for (i, b) in bytes.iter_mut().enumerate() {
        *b = u8::from_str_radix(&guid[2 * i..2 * i + 2], 16).ok()?;
    }
    Some(std::array::from_fn(|k| {
        f32::from_le_bytes([
            bytes[4 * k],
            bytes[4 * k + 1],
            bytes[4 * k + 2],
            bytes[4 * k + 3],
        ])
    }))
}

/// `HDUtils.ConvertVector4ToGUID`: the inverse.
pub fn vector4_to_guid(v: [f32; 4]) -> String {
    v.iter()
        .flat_map(|f| f.to_le_bytes())
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Mono's `string.GetHashCode` as HDRP copies it (`MonoStringHash`): two
/// interleaved djb2-xor hashes over the UTF-16 units, 32-bit wrapping.
fn mono_string_hash(s: &str) -> i32 {
    let units: Vec<u16> = s.encode_utf16().collect();
    let (mut h1, mut h2) = (5381i32, 5381i32);
    let mut i = 0;
    while i < units.len() {
        h1 = (h1 << 5).wrapping_add(h1) ^ units[i] as i32;
        if i + 1 >= units.len() {
            break;
        }
        h2 = (h2 << 5).wrapping_add(h2) ^ units[i + 1] as i32;
        i += 2;
    }
    h1.wrapping_add(h2.wrapping_mul(1_566_083_941))
}

/// The `hash` HDRP gives a profile asset with this GUID
/// (`GetDiffusionProfileHash`: the mantissa of Mono's hash under the
/// exponent of 2.0, so the float is finite and in [2, 4)).
pub fn hdrp_profile_hash(guid: &str) -> u32 {
    let h = mono_string_hash(guid) as u32;
    (0b1000_0000u32 << 23) | (h & 0x7F_FFFF)
}

/// A Unity YAML float, as its writer prints one (`1.0959463e-38`).
pub fn unity_float(v: f32) -> String {
    if v == 0.0 {
        "0".into()
    } else if (1e-4..1e7).contains(&v.abs()) {
        format!("{v}")
    } else {
        let s = format!("{v:e}");
        match s.split_once('e') {
            Some((m, e)) if !e.starts_with('-') => format!("{m}e+{e}"),
            _ => s,
        }
    }
}

/// `{r: …, g: …, b: …, a: …}` of a material's colour line.
fn parse_vector4(text: &str) -> Option<[f32; 4]> {
    let body = text.trim().strip_prefix('{')?.strip_suffix('}')?;
    let mut out = [0f32; 4];
    for (i, key) in ["r", "g", "b", "a"].iter().enumerate() {
        let part = body.split(',').nth(i)?.trim();
        let v = part
            .strip_prefix(key)?
            .trim_start()
            .strip_prefix(':')?
            .trim();
        out[i] = v.parse().ok()?;
    }
    Some(out)
}

/// The profile references of a material's text: (asset property, hash
/// property, the GUID), all-zero vectors (no profile) left out.
pub fn material_references(text: &str) -> Vec<(String, String, Result<String, String>)> {
    let mut out = Vec::new();
    for line in text.lines() {
        let t = line.trim_start();
        let Some(item) = t.strip_prefix("- ") else {
            continue;
        };
        let Some((key, value)) = item.split_once(':') else {
            continue;
        };
        let key = key.trim();
        let hash_key = if let Some(layer) = key.strip_prefix("_DiffusionProfileAsset") {
            if !(layer.is_empty() || matches!(layer, "0" | "1" | "2" | "3")) {
                continue;
            }
            format!("_DiffusionProfileHash{layer}")
        } else if let Some(base) = key.strip_suffix("_Asset") {
            // A Shader Graph property's hash float (only where the
            // material has that float: other `_Asset` colours are not ours).
            let float_line = format!("- {base}:");
            if !text
                .lines()
                .any(|l| l.trim_start().starts_with(&float_line))
            {
                continue;
            }
            base.to_owned()
        } else {
            continue;
        };
        let Some(v) = parse_vector4(value) else {
            continue;
        };
        if v.iter().all(|x| *x == 0.0) {
            continue;
        }
        let guid = if v.iter().all(|x| x.is_finite()) {
            Ok(vector4_to_guid(v))
        } else {
            Err(format!(
                "{key} {value}: not finite, so the GUID's bits are lost"
            ))
        };
        out.push((key.to_owned(), hash_key, guid));
    }
    out
}

/// Every file under `dir`, sorted, hidden folders left out.
fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for p in entries {
        let hidden = p
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.starts_with('.'));
        if p.is_dir() {
            if !hidden {
                walk(&p, out)?;
            }
        } else {
            out.push(p);
        }
    }
    Ok(())
}

/// Reads the project at `root` (its `Assets` folder, or `root` itself if it
/// has none): every diffusion profile with its GUID, and every material's
/// references to them.
pub fn scan(root: &Path) -> Result<Project, ImportError> {
    let assets = if root.join("Assets").is_dir() {
        root.join("Assets")
    } else {
        root.to_owned()
    };
    let mut files = Vec::new();
    walk(&assets, &mut files).map_err(|error| ImportError::Read {
        path: assets.clone(),
        error,
    })?;
    let mut p = Project::default();
    let mut refs = Vec::new();
    for f in files {
        let ext = f
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("asset") => {
                let Ok(text) = crate::export::import::read_text(&f) else {
                    p.skipped.push((f, "not text (binary Unity data)".into()));
                    continue;
                };
                if !text.contains(PROFILE_SCRIPT_GUID) {
                    continue;
                }
                let meta = f.with_file_name(format!(
                    "{}.meta",
                    f.file_name()
                        .map(|n| n.to_string_lossy())
                        .unwrap_or_default()
                ));
                let Some(guid) = std::fs::read_to_string(&meta)
                    .ok()
                    .and_then(|t| meta_guid(&t))
                else {
                    p.skipped.push((
                        f,
                        "no .meta file with a GUID beside it: no material can name it".into(),
                    ));
                    continue;
                };
                let mut looks = super::read(&text, &f)?;
                if looks.len() != 1 {
                    p.skipped.push((
                        f,
                        format!(
                            "an m_Version 0 asset of {} profiles: HDRP 7+ lists only single-profile assets (open it in Unity to upgrade it)",
                            looks.len()
                        ),
                    ));
                    continue;
                }
                p.profiles.push(ProjectProfile {
                    path: f,
                    guid,
                    look: looks.remove(0),
                });
            }
            Some("mat") => {
                let Ok(text) = crate::export::import::read_text(&f) else {
                    p.skipped.push((f, "not a text material".into()));
                    continue;
                };
                p.materials += 1;
                for (asset_property, hash_property, guid) in material_references(&text) {
                    match guid {
                        Ok(guid) => refs.push(MaterialUse {
                            material: f.clone(),
                            asset_property,
                            hash_property,
                            guid,
                        }),
                        Err(why) => p.skipped.push((f.clone(), why)),
                    }
                }
            }
            _ => {}
        }
    }
    for r in refs {
        if p.profiles.iter().any(|pr| pr.guid == r.guid) {
            p.uses.push(r);
        } else {
            p.unresolved.push(r);
        }
    }
    Ok(p)
}

/// A Diffusion Profile List (a VolumeProfile with one DiffusionProfileList
/// override) naming `guids`, as Unity writes one (HDRP's sample
/// `Diffusion Profile List.asset`).
pub fn profile_list_asset(name: &str, guids: &[String]) -> String {
    let items: String = guids
        .iter()
        .map(|g| format!("    - {{fileID: 11400000, guid: {g}, type: 2}}\n"))
        .collect();
    let component: u64 = 8160297439640018483;
    format!(
        "%YAML 1.1\n%TAG !u! tag:unity3d.com,2011:\n{}  components:\n  - {{fileID: {component}}}\n{}  active: 1\n  diffusionProfiles:\n    m_OverrideState: 1\n    m_Value:\n{items}",
        super::mono_behaviour(11400000, 0, VOLUME_PROFILE_SCRIPT_GUID, name),
        super::mono_behaviour(component, 3, PROFILE_LIST_SCRIPT_GUID, "DiffusionProfileList"),
    )
}

/// A `.meta` file for a new asset with `guid` (NativeFormatImporter, as
/// Unity writes one for a ScriptableObject asset).
pub fn asset_meta(guid: &str) -> String {
    format!(
        "fileFormatVersion: 2\nguid: {guid}\nNativeFormatImporter:\n  externalObjects: {{}}\n  mainObjectFileID: 11400000\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
    )
}

/// `text` (a material) with the reference in `asset_property` pointed at
/// the profile `guid`: the Vector4 and the hash float rewritten, every
/// other line as it was. An error if the material has no such lines.
pub fn repoint_material(
    text: &str,
    asset_property: &str,
    hash_property: &str,
    guid: &str,
) -> Result<String, String> {
    let v = guid_to_vector4(guid).ok_or_else(|| format!("{guid} is not a GUID"))?;
    let hash = f32::from_bits(hdrp_profile_hash(guid));
    let (mut asset_done, mut hash_done) = (false, false);
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        let indent = &line[..line.len() - t.len()];
        let eol = if line.ends_with("\r\n") {
            "\r\n"
        } else if line.ends_with('\n') {
            "\n"
        } else {
            ""
        };
        if t.starts_with(&format!("- {asset_property}:")) {
            out.push_str(&format!(
                "{indent}- {asset_property}: {{r: {}, g: {}, b: {}, a: {}}}{eol}",
                unity_float(v[0]),
                unity_float(v[1]),
                unity_float(v[2]),
                unity_float(v[3])
            ));
            asset_done = true;
        } else if t.starts_with(&format!("- {hash_property}:")) {
            out.push_str(&format!(
                "{indent}- {hash_property}: {}{eol}",
                unity_float(hash)
            ));
            hash_done = true;
        } else {
            out.push_str(line);
        }
    }
    if !(asset_done && hash_done) {
        return Err(format!(
            "no {} line",
            if asset_done {
                hash_property
            } else {
                asset_property
            }
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HDRP's shipped profiles' `hash` fields (tests/data/hdrp: Skin
    /// 1075477546, Foliage 1081692787) from their GUIDs as HDRP's
    /// DefaultSettingsVolumeProfile.asset names them (Skin
    /// 404820c4cf36ad944862fa59c56064f0, Foliage
    /// 2384dbf2c1c420f45a792fbc315fbfb1): published numbers, not ours.
    #[test]
    fn profile_hash_is_hdrps() {
        assert_eq!(
            hdrp_profile_hash("404820c4cf36ad944862fa59c56064f0"),
            1_075_477_546
        );
        assert_eq!(
            hdrp_profile_hash("2384dbf2c1c420f45a792fbc315fbfb1"),
            1_081_692_787
        );
    }

    /// HDRP's sample Fern.mat holds `_DiffusionProfileAsset: {r:
    /// 6.669458e-36, g: 5.261928e+31, b: -1.1107148e+32, a: 2.9494916e-23}`
    /// for its Foliage profile, GUID fcd70d05840926746a3daff4f0a00e1a
    /// (HDRP 13 Samples~/MaterialSamples, Fern.mat lines 362–363, and
    /// Foliage.asset.meta): read both ways.
    #[test]
    fn guid_vectors_are_hdrps() {
        let text = "    - _DiffusionProfileAsset: {r: 6.669458e-36, g: 5.261928e+31, b: -1.1107148e+32, a: 2.9494916e-23}\n    - _DiffusionProfileHash: 2.0536408\n";
        let refs = material_references(text);
        assert_eq!(refs.len(), 1);
        assert_eq!(refs[0].2.as_deref(), Ok("fcd70d05840926746a3daff4f0a00e1a"));
        assert_eq!(refs[0].1, "_DiffusionProfileHash");
        let v = guid_to_vector4("fcd70d05840926746a3daff4f0a00e1a").unwrap();
        assert_eq!(
            v,
            [6.669458e-36, 5.261928e+31, -1.1107148e+32, 2.9494916e-23]
        );
        assert_eq!(unity_float(v[1]), "5.261928e+31");
        // Its hash float, as the material holds it.
        assert_eq!(
            f32::from_bits(hdrp_profile_hash("fcd70d05840926746a3daff4f0a00e1a")),
            2.0536408
        );
        // What we write parses back to the same bits.
        let again = repoint_material(
            text,
            "_DiffusionProfileAsset",
            "_DiffusionProfileHash",
            "fcd70d05840926746a3daff4f0a00e1a",
        )
        .unwrap();
        assert_eq!(
            material_references(&again)[0].2.as_deref(),
            Ok("fcd70d05840926746a3daff4f0a00e1a")
        );
    }
}
