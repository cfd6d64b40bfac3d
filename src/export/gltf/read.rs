//! The glTF reader: every material with `KHR_materials_volume` read as a
//! look, each field checked and named by its JSON path (the mapping is
//! the writer's, in `export/gltf.rs`, inverted).

use super::*;

/// A number array of `n` finite values at `field`.
fn numbers(v: &Value, n: usize, path: &Path, field: &str) -> Result<Vec<f64>, ImportError> {
    let a = v.as_array().filter(|a| a.len() == n).ok_or_else(|| {
        ImportError::field(path, field, format!("{v} is not an array of {n} numbers"))
    })?;
    a.iter()
        .map(|x| {
            x.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                ImportError::field(path, field, format!("{x} is not a finite number"))
            })
        })
        .collect()
}

fn number(v: &Value, path: &Path, field: &str) -> Result<f64, ImportError> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ImportError::field(path, field, format!("{v} is not a finite number")))
}

fn rgb_in_unit(v: &Value, path: &Path, field: &str) -> Result<Rgb, ImportError> {
    let n = numbers(v, 3, path, field)?;
    let c = [n[0], n[1], n[2]];
    if let Some(x) = c.iter().find(|x| !(0.0..=1.0).contains(*x)) {
        return Err(ImportError::field(
            path,
            field,
            format!("{x} is outside 0–1"),
        ));
    }
    Ok(c)
}

/// Whether the file at `path` is a `.gltf` that a look can be read from
/// (some material has `KHR_materials_volume`), rather than a mesh alone:
/// what a file dropped on the editor is taken as.
pub fn gltf_has_volume(path: &Path) -> bool {
    crate::export::import::read_text(path)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .and_then(|d| d.get("materials").and_then(Value::as_array).cloned())
        .is_some_and(|ms| {
            ms.iter()
                .any(|m| m.pointer(&format!("/extensions/{VOLUME}")).is_some())
        })
}

/// Reads every material with `KHR_materials_volume` of a `.gltf` as a look.
pub fn read(
    text: &str,
    path: &Path,
    options: &ImportOptions,
) -> Result<Vec<ImportedLook>, ImportError> {
    let doc: Value = serde_json::from_str(text)
        .map_err(|e| ImportError::file(path, format!("malformed glTF JSON: {e}")))?;
    if doc
        .pointer("/asset/version")
        .and_then(Value::as_str)
        .is_none()
    {
        return Err(ImportError::not_engine(
            path,
            "no asset.version: not a glTF 2.0 file",
        ));
    }
    let materials = doc
        .get("materials")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    let mut looks = Vec::new();
    for (i, m) in materials.iter().enumerate() {
        let Some(vol) = m.pointer(&format!("/extensions/{VOLUME}")) else {
            continue;
        };
        looks.push(read_material(m, vol, i, path, options)?);
    }
    if looks.is_empty() {
        return Err(ImportError::not_engine(
            path,
            format!("no material has {VOLUME}: a glTF without a subsurface volume (a mesh is opened with File → Open mesh)"),
        ));
    }
    Ok(looks)
}

fn read_material(
    m: &Value,
    vol: &Value,
    index: usize,
    path: &Path,
    options: &ImportOptions,
) -> Result<ImportedLook, ImportError> {
    let name = m
        .get("name")
        .and_then(Value::as_str)
        .unwrap_or("glTF material")
        .to_owned();
    let mut r = MaterialReading {
        path,
        index,
        fields: Vec::new(),
        notes: Vec::new(),
    };
    let (distance, colour) = r.attenuation(vol)?;
    // glTF is in metres (glTF 2.0 §3.4); a file written in other units
    // is read with --metres-per-unit.
    let mm_per_unit = 1e3 * options.metres_per_unit.unwrap_or(1.0);
    if let Some(m) = options.metres_per_unit {
        r.notes.push(format!(
            "distances read in units of {m} m (--metres-per-unit), not glTF's metre"
        ));
    }
    let mfp_mm: Rgb = std::array::from_fn(|c| distance / -colour[c].ln() * mm_per_unit);
    let albedo = r.albedo(m)?;
    let colour_field = r.at(&format!("{VOLUME}.attenuationColor"));
    let d = crate::export::materialx::scattering_distance(
        mfp_mm,
        albedo,
        &colour_field,
        path,
        &mut r.notes,
    )?;
    let rendering = r.rendering(m)?;
    let preset = crate::export::import::burley_preset(
        path,
        name,
        "Read from a glTF material's volume extensions.",
        albedo,
        d,
        rendering,
    );
    preset
        .validate()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    Ok(ImportedLook {
        preset,
        kind: "glTF KHR_materials_volume",
        fields: r.fields,
        notes: r.notes,
    })
}

/// One material being read: its file and index (for the fields' JSON
/// paths), the fields read so far and the notes on them.
struct MaterialReading<'a> {
    path: &'a Path,
    index: usize,
    fields: Vec<(String, String)>,
    notes: Vec<String>,
}

impl MaterialReading<'_> {
    /// The JSON path of an extension's field `f`.
    fn at(&self, f: &str) -> String {
        format!("materials[{}].extensions.{f}", self.index)
    }

    /// `KHR_materials_volume`'s attenuation distance (over 0) and colour
    /// (each channel strictly inside 0–1: a finite mean free path).
    fn attenuation(&mut self, vol: &Value) -> Result<(f64, Rgb), ImportError> {
        let path = self.path;
        let dist_field = self.at(&format!("{VOLUME}.attenuationDistance"));
        let distance = match vol.get("attenuationDistance") {
            Some(v) => number(v, path, &dist_field)?,
            None => {
                return Err(ImportError::field(
                    path,
                    dist_field,
                    "missing: its default, +∞, is a volume that neither absorbs nor scatters",
                ))
            }
        };
        if !(distance > 0.0) {
            return Err(ImportError::field(
                path,
                dist_field,
                format!("{distance} must be over 0 (the schema's exclusive minimum)"),
            ));
        }
        let colour_field = self.at(&format!("{VOLUME}.attenuationColor"));
        let colour = match vol.get("attenuationColor") {
            Some(v) => rgb_in_unit(v, path, &colour_field)?,
            None => [1.0; 3],
        };
        self.fields
            .push(("attenuationDistance".to_owned(), distance.to_string()));
        self.fields
            .push(("attenuationColor".to_owned(), format!("{colour:?}")));
        if let Some(c) = (0..3).find(|&c| !(colour[c] > 0.0 && colour[c] < 1.0)) {
            return Err(ImportError::field(
                path,
                colour_field,
                format!(
                    "{} in {}: σt = −ln(c)/d is {} there, no finite mean free path",
                    colour[c],
                    ["red", "green", "blue"][c],
                    if colour[c] >= 1.0 { "0" } else { "∞" }
                ),
            ));
        }
        Ok((distance, colour))
    }

    /// The multi-scatter albedo (`KHR_materials_volume_scatter`), else the
    /// base colour.
    fn albedo(&mut self, m: &Value) -> Result<Rgb, ImportError> {
        let path = self.path;
        if let Some(s) = m.pointer(&format!("/extensions/{VOLUME_SCATTER}")) {
            let (key, v) = ["multiscatterColorFactor", "multiscatterColor"]
                .iter()
                .find_map(|k| s.get(*k).map(|v| (*k, v)))
                .unwrap_or(("multiscatterColorFactor", &Value::Null));
            let field = self.at(&format!("{VOLUME_SCATTER}.{key}"));
            let a = if v.is_null() {
                // The draft's default (README line 72).
                [0.0; 3]
            } else {
                rgb_in_unit(v, path, &field)?
            };
            self.fields.push((key.to_owned(), format!("{a:?}")));
            return Ok(a);
        }
        let field = format!(
            "materials[{}].pbrMetallicRoughness.baseColorFactor",
            self.index
        );
        let a = match m.pointer("/pbrMetallicRoughness/baseColorFactor") {
            Some(v) => {
                let n = numbers(v, 4, path, &field)?;
                rgb_in_unit(&json!([n[0], n[1], n[2]]), path, &field)?
            }
            None => [1.0; 3],
        };
        self.notes.push(format!(
            "no {VOLUME_SCATTER} (a draft): the albedo is the base colour"
        ));
        self.fields
            .push(("baseColorFactor".to_owned(), format!("{a:?}")));
        Ok(a)
    }

    /// The surface: the index of refraction (glTF's 1.5 when absent), the
    /// diffuse transmission's tint and the roughness.
    fn rendering(&mut self, m: &Value) -> Result<RenderingSpec, ImportError> {
        let path = self.path;
        let mut rendering = RenderingSpec::default();
        if let Some(ior) = m.pointer(&format!("/extensions/{IOR}/ior")) {
            let ior = number(ior, path, &self.at(&format!("{IOR}.ior")))?;
            self.fields.push(("ior".to_owned(), ior.to_string()));
            let (lo, hi) = crate::settings::rendering::limits::IOR;
            rendering.ior = ior.clamp(lo, hi);
            if rendering.ior != ior {
                self.notes.push(format!(
                    "ior {ior} is held as {}, scatterlab's specular range",
                    rendering.ior
                ));
            }
        } else {
            // KHR_materials_ior's default when absent: glTF's 1.5.
            rendering.ior = 1.5;
        }
        if let Some(t) = m.pointer(&format!(
            "/extensions/{DIFFUSE_TRANSMISSION}/diffuseTransmissionColorFactor"
        )) {
            rendering.transmission_tint = rgb_in_unit(
                t,
                path,
                &self.at(&format!(
                    "{DIFFUSE_TRANSMISSION}.diffuseTransmissionColorFactor"
                )),
            )?;
            self.fields.push((
                "diffuseTransmissionColorFactor".to_owned(),
                format!("{:?}", rendering.transmission_tint),
            ));
        }
        if let Some(r) = m.pointer("/pbrMetallicRoughness/roughnessFactor") {
            let r = number(
                r,
                path,
                &format!(
                    "materials[{}].pbrMetallicRoughness.roughnessFactor",
                    self.index
                ),
            )?;
            rendering.specular.roughness = r.clamp(0.0, 1.0);
        }
        Ok(rendering)
    }
}
