//! The reader of MaterialX documents: every `open_pbr_surface` and
//! `standard_surface` node, with the document's colour spaces and units.
//! References, in the MaterialX repository: `libraries/bxdf/
//! open_pbr_surface.mtlx` and `standard_surface.mtlx` (the inputs and
//! their defaults, used where a document leaves an input out: OpenPBR
//! subsurface_weight 0, subsurface_color 0.8, subsurface_radius 1.0,
//! subsurface_radius_scale (1.0, 0.5, 0.25), specular_ior 1.5,
//! specular_roughness 0.3; Standard Surface subsurface 0,
//! subsurface_color 1, subsurface_radius 1 (a colour: the mean free path
//! per channel), subsurface_scale 1, specular_IOR 1.5, specular_roughness
//! 0.2); the MaterialX Specification (a `colorspace` attribute applies to
//! the element and everything in it, an input's own overrides it; a value
//! with `unittype="distance"` is in its `unit`, one without in scene
//! units). The subsurface becomes Burley's d = ℓ/s(A) (the writer's rule,
//! Christensen & Burley 2015 eq. 5), ℓ the mean free path in mm.

use super::super::import::{srgb_decode, ImportError, ImportOptions, ImportedLook};
use crate::model::burley::ScalingFit;
use crate::model::Rgb;
use crate::settings::rendering::{DualLobeSpec, RenderingSpec};
use std::path::Path;

/// MaterialX's standard distance units (stdlib `UD_stdlib_distance`), in mm.
const DISTANCE_UNITS_MM: [(&str, f64); 10] = [
    ("nanometer", 1e-6),
    ("micron", 1e-3),
    ("millimeter", 1.0),
    ("centimeter", 10.0),
    ("inch", 25.4),
    ("foot", 304.8),
    ("yard", 914.4),
    ("meter", 1000.0),
    ("kilometer", 1e6),
    ("mile", 1_609_344.0),
];

/// Scene units where a document states none and `--metres-per-unit` is
/// not given: USD's default (metersPerUnit 0.01), the usual home of
/// MaterialX, said in a note.
const DEFAULT_SCENE_UNIT_MM: f64 = 10.0;

pub fn read(
    text: &str,
    path: &Path,
    options: &ImportOptions,
) -> Result<Vec<ImportedLook>, ImportError> {
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| ImportError::file(path, format!("malformed XML: {e}")))?;
    let root = doc.root_element();
    if root.tag_name().name() != "materialx" {
        return Err(ImportError::file(
            path,
            format!(
                "the root element is <{}>, not <materialx>: not a MaterialX document",
                root.tag_name().name()
            ),
        ));
    }
    let mut looks = Vec::new();
    for node in root.descendants().filter(|n| n.is_element()) {
        let kind = match node.tag_name().name() {
            "open_pbr_surface" => Shader::OpenPbr,
            "standard_surface" => Shader::StandardSurface,
            _ => continue,
        };
        looks.push(read_shader(node, kind, path, options)?);
    }
    if looks.is_empty() {
        return Err(ImportError::file(
            path,
            "no open_pbr_surface or standard_surface node: no subsurface scatterlab can read",
        ));
    }
    Ok(looks)
}

#[derive(Clone, Copy, PartialEq)]
enum Shader {
    OpenPbr,
    StandardSurface,
}

/// An input of a shader node: its value text, unit and colour space
/// (its own or the nearest enclosing element's), or where it comes from
/// when it is connected.
struct Input<'a> {
    value: Option<&'a str>,
    connected: bool,
    unit: Option<&'a str>,
    colorspace: Option<&'a str>,
}

fn input<'a>(node: roxmltree::Node<'a, 'a>, name: &str) -> Option<Input<'a>> {
    let i = node.children().find(|c| {
        c.is_element() && c.tag_name().name() == "input" && c.attribute("name") == Some(name)
    })?;
    let colorspace = i.ancestors().find_map(|a| a.attribute("colorspace"));
    Some(Input {
        value: i.attribute("value"),
        connected: i.attribute("nodename").is_some()
            || i.attribute("nodegraph").is_some()
            || i.attribute("interfacename").is_some()
            || i.attribute("output").is_some(),
        unit: i.attribute("unit"),
        colorspace,
    })
}

fn numbers(text: &str, n: usize, path: &Path, field: &str) -> Result<Vec<f64>, ImportError> {
    let v: Vec<&str> = text.split(',').map(str::trim).collect();
    if v.len() != n {
        return Err(ImportError::field(
            path,
            field,
            format!(
                "\"{text}\" has {} values, a {} needs {n}",
                v.len(),
                if n == 1 { "float" } else { "color3" }
            ),
        ));
    }
    v.iter()
        .map(|s| {
            let x: f64 = s
                .parse()
                .map_err(|_| ImportError::field(path, field, format!("\"{s}\" is not a number")))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(ImportError::field(
                    path,
                    field,
                    format!("{x} is not a finite number"),
                ))
            }
        })
        .collect()
}

/// A colour value in linear Rec. 709, from the colour spaces MaterialX's
/// default configuration names for values.
fn to_linear_rec709(
    c: Rgb,
    space: Option<&str>,
    path: &Path,
    field: &str,
) -> Result<Rgb, ImportError> {
    match space.unwrap_or("lin_rec709") {
        "lin_rec709" | "none" | "" => Ok(c),
        "srgb_texture" => Ok(c.map(srgb_decode)),
        "g22_rec709" => Ok(c.map(|v| v.max(0.0).powf(2.2))),
        "g18_rec709" => Ok(c.map(|v| v.max(0.0).powf(1.8))),
        "acescg" | "lin_ap1" => {
            // AP1 to Rec. 709 primaries, both D60/D65 via the ACES CAT
            // (the matrix OCIO's ACES configs use).
            let m = [
                [1.705_050_8, -0.621_792_1, -0.083_258_7],
                [-0.130_256_4, 1.140_804_7, -0.010_548_3],
                [-0.024_003_4, -0.128_968_9, 1.152_972_3],
            ];
            Ok(std::array::from_fn(|i| (0..3).map(|j| m[i][j] * c[j]).sum()))
        }
        other => Err(ImportError::field(
            path,
            field,
            format!("colour space \"{other}\" is not one scatterlab converts (lin_rec709, srgb_texture, g22_rec709, g18_rec709, acescg)"),
        )),
    }
}

/// A shader node's inputs as they are read: what each was read as (for
/// the fields list) and what had to be assumed (the notes).
struct ShaderInputs<'a> {
    node: roxmltree::Node<'a, 'a>,
    path: &'a Path,
    fields: Vec<(String, String)>,
    notes: Vec<String>,
}

impl ShaderInputs<'_> {
    /// Where an input is, for errors: `shader[name=N].input`.
    fn at(&self, input: &str) -> String {
        let shader = self.node.attribute("name").unwrap_or("material");
        format!("{}[name={shader}].{input}", self.node.tag_name().name())
    }

    /// A float input and its unit; its default where it is missing or
    /// driven by a node graph (noted).
    fn float(&mut self, name: &str, default: f64) -> Result<(f64, Option<String>), ImportError> {
        match input(self.node, name) {
            Some(i) if i.value.is_some() => {
                let v = numbers(i.value.unwrap_or_default(), 1, self.path, &self.at(name))?[0];
                self.fields.push((
                    name.to_owned(),
                    match i.unit {
                        Some(u) => format!("{v} {u}"),
                        None => v.to_string(),
                    },
                ));
                Ok((v, i.unit.map(str::to_owned)))
            }
            Some(i) if i.connected => {
                self.notes.push(format!(
                    "{name} is driven by a node graph: read as its default {default}"
                ));
                Ok((default, None))
            }
            _ => Ok((default, None)),
        }
    }

    /// A colour input in linear Rec.709 and its unit; its default where
    /// it is missing or driven by a node graph (noted).
    fn colour3(&mut self, name: &str, default: Rgb) -> Result<(Rgb, Option<String>), ImportError> {
        match input(self.node, name) {
            Some(i) if i.value.is_some() => {
                let v = numbers(i.value.unwrap_or_default(), 3, self.path, &self.at(name))?;
                let raw = [v[0], v[1], v[2]];
                let lin = to_linear_rec709(raw, i.colorspace, self.path, &self.at(name))?;
                self.fields.push((
                    name.to_owned(),
                    format!(
                        "({}, {}, {}){}",
                        raw[0],
                        raw[1],
                        raw[2],
                        i.colorspace.map(|s| format!(" {s}")).unwrap_or_default()
                    ),
                ));
                Ok((lin, i.unit.map(str::to_owned)))
            }
            Some(i) if i.connected => {
                self.notes.push(format!(
                    "{name} is driven by a node graph: read as its default"
                ));
                Ok((default, None))
            }
            _ => Ok((default, None)),
        }
    }
}

/// The name of the material that uses the shader `node`, else the
/// shader's own.
fn look_name(node: roxmltree::Node) -> String {
    let shader_name = node.attribute("name").unwrap_or("material");
    node.document()
        .descendants()
        .filter(|m| m.is_element() && m.tag_name().name() == "surfacematerial")
        .find(|m| {
            m.children().any(|i| {
                i.is_element()
                    && i.attribute("name") == Some("surfaceshader")
                    && i.attribute("nodename") == Some(shader_name)
            })
        })
        .and_then(|m| m.attribute("name"))
        .unwrap_or(shader_name)
        .to_owned()
}

impl Shader {
    /// The subsurface weight, colour, radius, radius scale, IOR and
    /// roughness inputs' names.
    fn input_names(self) -> [&'static str; 6] {
        match self {
            Shader::OpenPbr => [
                "subsurface_weight",
                "subsurface_color",
                "subsurface_radius",
                "subsurface_radius_scale",
                "specular_ior",
                "specular_roughness",
            ],
            Shader::StandardSurface => [
                "subsurface",
                "subsurface_color",
                "subsurface_scale",
                "subsurface_radius",
                "specular_IOR",
                "specular_roughness",
            ],
        }
    }

    /// The defaults of the subsurface colour, the radius scale and the
    /// roughness (each shader's own specification).
    fn defaults(self) -> (Rgb, Rgb, f64) {
        match self {
            Shader::OpenPbr => ([0.8; 3], [1.0, 0.5, 0.25], 0.3),
            Shader::StandardSurface => ([1.0; 3], [1.0; 3], 0.2),
        }
    }
}

/// Millimetres per unit of the radius: its MaterialX distance unit, else
/// the scene unit (`--metres-per-unit`, or USD's centimetre), noted.
fn mm_per_unit(
    unit: Option<&str>,
    options: &ImportOptions,
    at_radius: &str,
    path: &Path,
    notes: &mut Vec<String>,
) -> Result<f64, ImportError> {
    Ok(match unit {
        Some(u) => DISTANCE_UNITS_MM
            .iter()
            .find(|(n, _)| *n == u)
            .map(|(_, mm)| *mm)
            .ok_or_else(|| {
                ImportError::field(
                    path,
                    at_radius,
                    format!("unit \"{u}\" is not a MaterialX distance unit"),
                )
            })?,
        None => match options.metres_per_unit {
            Some(m) => {
                notes.push(format!("the document gives the radius no unit: read in scene units of {m} m (--metres-per-unit)"));
                m * 1000.0
            }
            None => {
                notes.push(
                    "the document gives the radius no unit: read in centimetres, USD's default scene unit; --metres-per-unit sets another".into(),
                );
                DEFAULT_SCENE_UNIT_MM
            }
        },
    })
}

/// Burley's scattering distance d = ℓ/s(A) per channel (Christensen &
/// Burley 2015 eq. 5) from the mean free path in mm, within Burley's range:
/// over it is an error (a wrong unit), under it is held at the shortest.
pub(in crate::export) fn scattering_distance(
    mfp_mm: Rgb,
    albedo: Rgb,
    at_radius: &str,
    path: &Path,
    notes: &mut Vec<String>,
) -> Result<Rgb, ImportError> {
    if let Some(c) = (0..3).find(|&c| !(mfp_mm[c] >= 0.0)) {
        return Err(ImportError::field(
            path,
            at_radius,
            format!(
                "{} mm in {} is negative",
                mfp_mm[c],
                ["red", "green", "blue"][c]
            ),
        ));
    }
    let (lo, hi) = crate::model::burley::DISTANCE_RANGE_MM;
    let d: Rgb = std::array::from_fn(|c| mfp_mm[c] / ScalingFit::Perpendicular.scale(albedo[c]));
    if let Some(c) = (0..3).find(|&c| d[c] > hi) {
        return Err(ImportError::field(
            path,
            at_radius,
            format!(
                "{} mm in {} is over {hi} mm: check the unit",
                d[c],
                ["red", "green", "blue"][c]
            ),
        ));
    }
    if d.iter().any(|v| *v < lo) {
        notes.push(format!(
            "a channel's path is under {lo} mm (no scattering): held at {lo} mm"
        ));
    }
    Ok(d.map(|v| v.max(lo)))
}

fn read_shader(
    node: roxmltree::Node,
    kind: Shader,
    path: &Path,
    options: &ImportOptions,
) -> Result<ImportedLook, ImportError> {
    // The material that uses the shader names the look; else the shader.
    let name = look_name(node);
    let [weight_in, colour_in, radius_in, scale_in, ior_in, rough_in] = kind.input_names();
    let (default_colour, default_scale, default_rough) = kind.defaults();
    let mut r = ShaderInputs {
        node,
        path,
        fields: Vec::new(),
        notes: Vec::new(),
    };
    let (weight, _) = r.float(weight_in, 0.0)?;
    let (albedo, _) = r.colour3(colour_in, default_colour)?;
    // The mean free path ℓ per channel and the unit it is in.
    let (mfp, unit) = match kind {
        Shader::OpenPbr => {
            let (radius, unit) = r.float(radius_in, 1.0)?;
            let (scale, _) = r.colour3(scale_in, default_scale)?;
            (scale.map(|s| s * radius), unit)
        }
        Shader::StandardSurface => {
            let (scale, unit_a) = r.float(radius_in, 1.0)?;
            let (radius, unit_b) = r.colour3(scale_in, default_scale)?;
            (radius.map(|r| r * scale), unit_a.or(unit_b))
        }
    };
    let mm_per_unit = mm_per_unit(
        unit.as_deref(),
        options,
        &r.at(radius_in),
        path,
        &mut r.notes,
    )?;
    let (ior, _) = r.float(ior_in, 1.5)?;
    let (roughness, _) = r.float(rough_in, default_rough)?;
    if !(0.0..=1.0).contains(&weight) {
        return Err(ImportError::field(
            path,
            r.at(weight_in),
            format!("{weight} is outside 0–1"),
        ));
    }
    if weight == 0.0 {
        r.notes.push(format!(
            "{weight_in} is 0: the renderer draws diffuse reflection only; the look here is the subsurface the document would scatter with"
        ));
    } else if weight < 1.0 {
        r.notes.push(format!(
            "{weight_in} is {weight}: the renderer mixes {:.0} % diffuse reflection with the scattering; the look here is the scattering alone",
            100.0 * (1.0 - weight)
        ));
    }
    if let Some(c) = (0..3).find(|&c| !(0.0..=1.0).contains(&albedo[c])) {
        return Err(ImportError::field(
            path,
            r.at(colour_in),
            format!("{} (linear) is outside 0–1", albedo[c]),
        ));
    }
    let mfp_mm = mfp.map(|v| v * mm_per_unit);
    let d = scattering_distance(mfp_mm, albedo, &r.at(radius_in), path, &mut r.notes)?;
    let ior_v = ior.clamp(1.0, 2.0);
    if ior_v != ior {
        r.notes.push(format!(
            "{ior_in} {ior} is held as {ior_v}, scatterlab's specular range"
        ));
    }
    let ShaderInputs {
        fields, mut notes, ..
    } = r;
    let preset = super::super::import::burley_preset(
        path,
        name.clone(),
        &format!("Read from a MaterialX {}.", node.tag_name().name()),
        albedo,
        d,
        RenderingSpec {
            ior: ior_v,
            specular: DualLobeSpec {
                roughness: roughness.clamp(0.0, 1.0),
                lobe0_roughness_multiplier: 1.0,
                lobe1_roughness_multiplier: 1.0,
                lobe_mix: 0.5,
            },
            ..RenderingSpec::default()
        },
    );
    notes.push("MaterialX has one specular lobe: the look's two lobes are the same".into());
    preset
        .validate()
        .map_err(|e| ImportError::file(path, e.to_string()))?;
    Ok(ImportedLook {
        preset,
        kind: match kind {
            Shader::OpenPbr => "MaterialX OpenPBR Surface",
            Shader::StandardSurface => "MaterialX Standard Surface",
        },
        fields,
        notes,
    })
}
