//! The meshes a glTF export puts its material on (the default head, a
//! sphere, or the artist's mesh on screen with its maps), and the buffer
//! they are written into.

use super::SPHERE_RADIUS_M;
use crate::export::ExportError;
use crate::render::gpu_types::SurfaceKind;
use serde_json::{json, Value};

/// A mesh of the artist's, as the editor shows it, to put the material on
/// (`ExportOptions::gltf_on_mesh`): its name in the file, and how its
/// colour map makes the base colour (`MapColour`, the editor's choice).
#[derive(Debug, Clone)]
pub struct GltfOnMesh {
    pub mesh: std::sync::Arc<crate::render::Mesh>,
    pub name: String,
    pub map_colour: crate::render::textures::MapColour,
}

/// The mesh as glTF wants it: positions (m), unit normals, and one index
/// list per surface kind with its material.
pub(super) struct MeshData {
    pub(super) name: String,
    positions: Vec<[f32; 3]>,
    pub(super) normals: Vec<[f32; 3]>,
    /// TEXCOORD_0 (glTF's top-left origin, as the mesh keeps them); empty
    /// without maps to draw.
    uvs: Vec<[f32; 2]>,
    /// TANGENT (glTF's: unit xyz along +u, w the bitangent's sign, B =
    /// w · N × T), with a normal map; else empty.
    tangents: Vec<[f32; 4]>,
    /// PNG bytes of the base colour's texture (sRGB) and of the normal
    /// texture, where the mesh has them.
    base_colour_png: Option<Vec<u8>>,
    normal_png: Option<Vec<u8>>,
    /// (surface, triangle indices).
    pub(super) parts: Vec<(SurfaceKind, Vec<u32>)>,
    /// `thicknessFactor` (m): the sphere's diameter, or the median of the
    /// mesh's (the head's or the artist's) baked skin thickness.
    pub(super) thickness_m: f64,
}

impl MeshData {
    /// A mesh without maps: its positions (m) and normals, its parts and
    /// its `thicknessFactor` (m).
    fn plain(
        name: &str,
        (positions, normals): (Vec<[f32; 3]>, Vec<[f32; 3]>),
        parts: Vec<(SurfaceKind, Vec<u32>)>,
        thickness_m: f64,
    ) -> Self {
        MeshData {
            name: name.into(),
            positions,
            normals,
            uvs: Vec::new(),
            tangents: Vec::new(),
            base_colour_png: None,
            normal_png: None,
            parts,
            thickness_m,
        }
    }
}

fn unit(n: [f32; 3]) -> [f32; 3] {
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l > 0.0 && l.is_finite() {
        n.map(|v| v / l)
    } else {
        [0.0, 0.0, 1.0]
    }
}

pub(super) fn sphere() -> MeshData {
    let (nu, nv) = (64usize, 32usize);
    let r = SPHERE_RADIUS_M as f32;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for j in 0..=nv {
        let theta = std::f32::consts::PI * j as f32 / nv as f32;
        for i in 0..=nu {
            let phi = 2.0 * std::f32::consts::PI * i as f32 / nu as f32;
            let n = unit([
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ]);
            positions.push(n.map(|x| x * r));
            normals.push(n);
        }
    }
    let row = (nu + 1) as u32;
    let mut idx = Vec::new();
    for j in 0..nv as u32 {
        for i in 0..nu as u32 {
            let (a, b) = (j * row + i, (j + 1) * row + i);
            // Counter-clockwise seen from outside; the poles' collapsed
            // triangles are left out.
            if j != 0 {
                idx.extend_from_slice(&[a, b, a + 1]);
            }
            if j != nv as u32 - 1 {
                idx.extend_from_slice(&[a + 1, b, b + 1]);
            }
        }
    }
    MeshData::plain(
        "sphere",
        (positions, normals),
        vec![(SurfaceKind::Skin, idx)],
        2.0 * SPHERE_RADIUS_M,
    )
}

pub(super) fn head() -> Result<MeshData, ExportError> {
    use crate::render::mesh::{Mesh, DEFAULT_HEAD_METRES_PER_UNIT, DEFAULT_HEAD_OBJ};
    let mesh = Mesh::from_obj_text(
        DEFAULT_HEAD_OBJ,
        "<embedded default head>",
        DEFAULT_HEAD_METRES_PER_UNIT,
    )
    .map_err(|e| ExportError::Encode {
        path: "<embedded default head>".into(),
        message: e.to_string(),
    })?;
    Ok(mesh_data(&mesh, "head"))
}

/// A loaded mesh's positions in metres, normals and parts by surface
/// kind, its thickness the median of its skin's baked thickness.
fn mesh_data(mesh: &crate::render::Mesh, name: &str) -> MeshData {
    let m = mesh.metres_per_unit;
    let positions = mesh
        .vertices
        .iter()
        .map(|v| v.position.map(|x| x * m))
        .collect();
    let normals = mesh.vertices.iter().map(|v| unit(v.normal)).collect();
    let mut parts: Vec<(SurfaceKind, Vec<u32>)> = Vec::new();
    for t in mesh.indices.chunks_exact(3) {
        let kind = SurfaceKind::of(mesh.vertices[t[0] as usize].material);
        match parts.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, v)) => v.extend_from_slice(t),
            None => parts.push((kind, t.to_vec())),
        }
    }
    parts.sort_by_key(|(k, _)| k.code() as u32);
    let mut skin: Vec<f64> = mesh
        .vertices
        .iter()
        .filter(|v| SurfaceKind::of(v.material) == SurfaceKind::Skin)
        .map(|v| v.thickness_mm as f64)
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    skin.sort_by(f64::total_cmp);
    let median_mm = skin.get(skin.len() / 2).copied().unwrap_or(10.0);
    MeshData::plain(name, (positions, normals), parts, median_mm * 1e-3)
}

/// `on`'s mesh with its UVs and maps: the colour map as the base colour's
/// texture where the mesh has one of its own (as `on.map_colour` draws
/// it: the map, the map scaled to the look's albedo `albedo` on average,
/// or none), and its normal map with the tangents the viewport used; a
/// 1×1 map is a default, not written.
pub(super) fn mesh_data_on(on: &GltfOnMesh, albedo: [f64; 3]) -> Result<MeshData, ExportError> {
    use crate::render::textures::{albedo_map_mean, AlbedoMode, MapColour};
    let mut data = mesh_data(&on.mesh, &on.name);
    data.uvs = on.mesh.vertices.iter().map(|v| v.uv).collect();
    let t = &on.mesh.textures;
    let real = |img: &crate::render::textures::TextureImage| img.width * img.height > 1;
    if t.albedo_mode == AlbedoMode::Absolute && real(&t.albedo) {
        let mut img = t.albedo.clone();
        // As the viewport: a tinted map with no used texels is the look's
        // albedo alone (no texture).
        let shown = match (on.map_colour, albedo_map_mean(&img)) {
            (MapColour::Map, _) => true,
            (MapColour::Tinted, Some(mean)) => {
                tint(&mut img, albedo, mean);
                true
            }
            (MapColour::Tinted, None) | (MapColour::Look, _) => false,
        };
        if shown {
            data.base_colour_png = Some(png(&img, &on.name)?);
        }
    }
    if real(&t.normal) {
        data.normal_png = Some(png(&t.normal, &on.name)?);
        // The tangents the viewport's normal mapping used, so that readers
        // need not make their own (the validator warns where they must);
        // glTF asks for unit xyz and w = ±1 (§3.7.2.1).
        data.tangents = on
            .mesh
            .vertices
            .iter()
            .map(|v| gltf_tangent(v.tangent, v.normal))
            .collect();
    }
    Ok(data)
}

/// A vertex's tangent as glTF takes it: xyz of unit length (a degenerate
/// one replaced by a unit vector across the normal), w ±1.
fn gltf_tangent(t: [f32; 4], n: [f32; 3]) -> [f32; 4] {
    let v = glam::Vec3::from_slice(&t[..3]);
    let xyz = if v.length_squared() > 1e-12 && v.is_finite() {
        v.normalize()
    } else {
        glam::Vec3::from(unit(n)).any_orthonormal_vector()
    };
    [xyz.x, xyz.y, xyz.z, if t[3] < 0.0 { -1.0 } else { 1.0 }]
}

/// Scales an sRGB colour map in linear light so that its mean `mean`
/// becomes `albedo` (clamped to 1): the editor's "map tinted by the look's
/// albedo", baked.
fn tint(img: &mut crate::render::textures::TextureImage, albedo: [f64; 3], mean: [f32; 3]) {
    use crate::model::colour::{linear_to_srgb8, srgb8_to_linear};
    if img.channels != 4 {
        return;
    }
    let k: [f32; 3] = std::array::from_fn(|c| albedo[c] as f32 / mean[c].max(1e-3));
    for p in img.texels.chunks_exact_mut(4) {
        for c in 0..3 {
            p[c] = linear_to_srgb8((srgb8_to_linear(p[c]) * k[c]).clamp(0.0, 1.0));
        }
    }
}

/// A map as PNG bytes (RGBA, or grey for one channel).
fn png(img: &crate::render::textures::TextureImage, name: &str) -> Result<Vec<u8>, ExportError> {
    let colour = if img.channels == 4 {
        image::ExtendedColorType::Rgba8
    } else {
        image::ExtendedColorType::L8
    };
    let mut out = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut out),
        &img.texels,
        img.width,
        img.height,
        colour,
    )
    .map_err(|e| ExportError::Encode {
        path: name.into(),
        message: e.to_string(),
    })?;
    Ok(out)
}

/// The glTF buffer being written: its bytes, views and accessors (glTF
/// 2.0 §3.6). Every view starts on a 4-byte boundary (§3.6.2.4).
#[derive(Default)]
pub(super) struct Buffer {
    pub(super) bytes: Vec<u8>,
    pub(super) views: Vec<Value>,
    pub(super) accessors: Vec<Value>,
}

impl Buffer {
    /// Appends `chunk` as a view for `target` (34962 ARRAY_BUFFER, 34963
    /// ELEMENT_ARRAY_BUFFER, none for an image); its index.
    fn view(&mut self, chunk: &[u8], target: Option<u32>) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": chunk.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bytes.extend_from_slice(chunk);
        self.views.push(v);
        self.views.len() - 1
    }

    /// Float vectors as a vertex attribute's accessor (5126 FLOAT,
    /// §5.1.3); its index.
    fn floats<const N: usize>(&mut self, v: &[[f32; N]], kind: &str) -> usize {
        let bytes: Vec<u8> = v
            .iter()
            .flat_map(|p| p.iter().flat_map(|x| x.to_le_bytes()))
            .collect();
        let view = self.view(&bytes, Some(34962));
        self.accessors.push(
            json!({"bufferView": view, "componentType": 5126, "count": v.len(), "type": kind}),
        );
        self.accessors.len() - 1
    }

    /// The vertex attributes: positions (with their bounds, §5.1.4),
    /// normals, and the UVs and tangents where the mesh has maps.
    fn attributes(&mut self, data: &MeshData) -> Value {
        let count = data.positions.len();
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &data.positions {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let position = self.floats(&data.positions, "VEC3");
        self.accessors[position]["min"] = json!(lo);
        self.accessors[position]["max"] = json!(hi);
        let normal = self.floats(&data.normals, "VEC3");
        let mut attributes = json!({"POSITION": position, "NORMAL": normal});
        if data.uvs.len() == count {
            attributes["TEXCOORD_0"] = json!(self.floats(&data.uvs, "VEC2"));
        }
        if data.tangents.len() == count {
            attributes["TANGENT"] = json!(self.floats(&data.tangents, "VEC4"));
        }
        attributes
    }

    /// One primitive per surface part, each with its material: the skin's
    /// is `materials[0]`, the eyes' and teeth's are added.
    pub(super) fn primitives(&mut self, data: &MeshData, materials: &mut Vec<Value>) -> Vec<Value> {
        let attributes = self.attributes(data);
        let mut primitives = Vec::new();
        for (kind, idx) in &data.parts {
            let material = match kind {
                SurfaceKind::Skin => 0,
                SurfaceKind::Eye => {
                    materials.push(json!({"name": "eye", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.78, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.05}}));
                    materials.len() - 1
                }
                SurfaceKind::Teeth => {
                    materials.push(json!({"name": "teeth", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.72, 0.65, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.3}}));
                    materials.len() - 1
                }
            };
            let bytes: Vec<u8> = idx.iter().flat_map(|i| i.to_le_bytes()).collect();
            let view = self.view(&bytes, Some(34963));
            // 5125 UNSIGNED_INT.
            self.accessors.push(
                json!({"bufferView": view, "componentType": 5125, "count": idx.len(), "type": "SCALAR"}),
            );
            primitives.push(json!({
                "attributes": attributes.clone(),
                "indices": self.accessors.len() - 1,
                "material": material,
            }));
        }
        primitives
    }

    /// The mesh's maps as PNG images in the buffer (an image's bufferView
    /// and mimeType, §3.8.2), one texture each, put on the `skin`
    /// material: the base colour's texture is the albedo (the map, or the
    /// map tinted to the look's), which glTF multiplies by the factor
    /// (§3.9.2), so the factor is 1. The images and textures, if any.
    pub(super) fn maps(
        &mut self,
        data: &MeshData,
        skin: &mut Value,
    ) -> Option<(Vec<Value>, Vec<Value>)> {
        let (mut images, mut textures) = (Vec::new(), Vec::new());
        let mut texture = |buffer: &mut Buffer, png: &Option<Vec<u8>>| {
            png.as_ref().map(|png| {
                let view = buffer.view(png, None);
                images.push(json!({"bufferView": view, "mimeType": "image/png"}));
                textures.push(json!({"source": images.len() - 1, "sampler": 0}));
                textures.len() - 1
            })
        };
        if let Some(k) = texture(self, &data.base_colour_png) {
            skin["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": k});
            skin["pbrMetallicRoughness"]["baseColorFactor"] = json!([1.0, 1.0, 1.0, 1.0]);
        }
        if let Some(k) = texture(self, &data.normal_png) {
            skin["normalTexture"] = json!({"index": k});
        }
        (!textures.is_empty()).then_some((images, textures))
    }
}
