//! glTF 2.0 (.gltf with its buffers and images, or .glb) loading: every
//! triangle primitive of the default scene, with its node transforms;
//! TEXCOORD_0 is required, normals and tangents are used when present
//! (generated otherwise); base colour, normal and metallic-roughness
//! (green = roughness) textures come from the materials.

use super::{Mesh, MeshError};
use crate::render::gpu_types::{SurfaceKind, Vertex};
use crate::render::textures::{
    from_dynamic, AlbedoMode, MeshTextures, RoughnessMode, TextureImage, TextureSlot,
};
use bytemuck::Zeroable;
use glam::{Mat3, Mat4, Vec3};
use std::path::Path;
use std::sync::Arc;

pub(super) fn load(path: &Path, metres_per_unit: f32) -> Result<Mesh, MeshError> {
    let origin = path.display().to_string();
    let load_error = |message: String| MeshError::Load {
        path: origin.clone(),
        message,
    };
    check_glb_header(path).map_err(load_error)?;
    let (doc, buffers, images) = gltf::import(path).map_err(|e| load_error(e.to_string()))?;
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| load_error("the file has no scene".into()))?;
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let mut has_normals = true;
    let mut textures = MeshTextures::default();
    let mut material_seen = false;
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    // glTF nodes form a forest; a hostile file can make a node its own
    // descendant, which would loop forever.
    let mut visited = vec![false; doc.nodes().len()];
    while let Some((node, parent)) = stack.pop() {
        match visited.get_mut(node.index()) {
            Some(seen) if !*seen => *seen = true,
            _ => {
                return Err(load_error(format!(
                    "node {} is reached twice: the node hierarchy is not a tree",
                    node.index()
                )))
            }
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        stack.extend(node.children().map(|c| (c, world)));
        let Some(mesh) = node.mesh() else { continue };
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        for (k, prim) in mesh.primitives().enumerate() {
            if prim.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let part = format!("mesh '{}' primitive {k}", mesh.name().unwrap_or("unnamed"));
            check_accessors(&prim).map_err(|e| load_error(format!("{part}: {e}")))?;
            let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let positions: Vec<[f32; 3]> = reader
                .read_positions()
                .ok_or_else(|| load_error(format!("{part} has no POSITION")))?
                .collect();
            let uvs: Vec<[f32; 2]> = reader
                .read_tex_coords(0)
                .ok_or_else(|| MeshError::NoUvs {
                    path: origin.clone(),
                    part: part.clone(),
                })?
                .into_f32()
                .collect();
            let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
            let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
            has_normals &= normals.is_some();
            if uvs.len() != positions.len() {
                return Err(load_error(format!(
                    "{part}: {} UVs for {} positions",
                    uvs.len(),
                    positions.len()
                )));
            }
            let names = [prim.material().name(), mesh.name(), node.name()]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
                .join(" ");
            let kind = part_kind(&names);
            let base = vertices.len() as u32;
            for (i, p) in positions.iter().enumerate() {
                let n = normals
                    .as_ref()
                    .and_then(|n| n.get(i))
                    .map(|n| (normal_matrix * Vec3::from(*n)).normalize_or_zero())
                    .unwrap_or(Vec3::ZERO);
                let tangent = tangents
                    .as_ref()
                    .and_then(|t| t.get(i))
                    .map(|t| {
                        let d = (Mat3::from_mat4(world) * Vec3::new(t[0], t[1], t[2]))
                            .normalize_or_zero();
                        [d.x, d.y, d.z, if t[3] < 0.0 { -1.0 } else { 1.0 }]
                    })
                    .unwrap_or([0.0; 4]);
                vertices.push(Vertex {
                    position: world.transform_point3(Vec3::from(*p)).into(),
                    normal: n.into(),
                    uv: uvs[i],
                    tangent,
                    material: kind.code(),
                    ..Vertex::zeroed()
                });
            }
            match reader.read_indices() {
                Some(ix) => indices.extend(ix.into_u32().map(|i| base + i)),
                None => indices.extend(base..base + positions.len() as u32),
            }
            if let Some(bad) = indices[..].iter().find(|&&i| i as usize >= vertices.len()) {
                return Err(load_error(format!("{part}: index {bad} is out of range")));
            }
            // The skin's maps: the first primitive that is not an eye or teeth.
            if !material_seen && kind == SurfaceKind::Skin {
                material_seen = true;
                read_material(&prim.material(), &images, &origin, &mut textures)?;
            }
        }
    }
    let mut mesh = Mesh::from_triangles(vertices, indices, &origin, metres_per_unit, has_normals)?;
    mesh.textures = Arc::new(textures);
    Ok(mesh)
}

/// What a primitive is, from its material's, mesh's and node's names (as
/// character exporters name them: "Eye_L", "Cornea", "Teeth"): 1 for an
/// eye, 2 for teeth, gums or tongue, 0 (skin) otherwise. Eyebrows, lashes
/// and lids are skin-side parts, not eyes. Eyes and teeth take no SSS and
/// the eye is drawn with an iris (`shaders/scene.wgsl`).
pub fn part_kind(names: &str) -> SurfaceKind {
    let n = names.to_ascii_lowercase();
    let has = |ks: &[&str]| ks.iter().any(|k| n.contains(k));
    if has(&["brow", "lash", "lid"]) {
        SurfaceKind::Skin
    } else if has(&["eye", "cornea", "iris", "sclera", "pupil"]) {
        SurfaceKind::Eye
    } else if has(&["teeth", "tooth", "gum", "tongue"]) {
        SurfaceKind::Teeth
    } else {
        SurfaceKind::Skin
    }
}

/// The accessors a primitive's reader will read must hold the types the
/// spec requires (POSITION, NORMAL: float VEC3; TANGENT: float VEC4;
/// TEXCOORD_0: VEC2; indices: unsigned SCALAR) with a stride at least the
/// element size: the gltf crate only debug-asserts these, so a hostile file
/// panicked debug builds (found by fuzzing) and reads garbage in release.
fn check_accessors(prim: &gltf::Primitive) -> Result<(), String> {
    use gltf::accessor::{DataType, Dimensions};
    use gltf::mesh::Semantic;
    let check = |what: &str, a: &gltf::Accessor, dims: Dimensions, types: &[DataType]| {
        if a.dimensions() != dims || !types.contains(&a.data_type()) {
            return Err(format!(
                "{what} accessor {} is {:?} {:?}; it must be {dims:?} of {types:?}",
                a.index(),
                a.dimensions(),
                a.data_type()
            ));
        }
        let stride = a.view().and_then(|v| v.stride()).unwrap_or(a.size());
        if stride < a.size() {
            return Err(format!(
                "{what} accessor {} has a stride of {stride} bytes for {}-byte elements",
                a.index(),
                a.size()
            ));
        }
        // gltf computes offset + stride·(count − 1) + size unchecked: a
        // count of 0 underflowed (found by fuzzing in CI), a huge one
        // overflows. Sparse accessors do the same with their own count.
        let span = |count: usize| {
            count
                .checked_sub(1)?
                .checked_mul(stride)?
                .checked_add(a.size())?
                .checked_add(a.offset())
        };
        if span(a.count()).is_none() {
            return Err(format!(
                "{what} accessor {} has an impossible count {}",
                a.index(),
                a.count()
            ));
        }
        if let Some(sparse) = a.sparse() {
            if span(sparse.count()).is_none() {
                return Err(format!(
                    "{what} accessor {} has an impossible sparse count {}",
                    a.index(),
                    sparse.count()
                ));
            }
        }
        Ok(())
    };
    let float = [DataType::F32];
    for (semantic, a) in prim.attributes() {
        match semantic {
            Semantic::Positions => check("POSITION", &a, Dimensions::Vec3, &float)?,
            Semantic::Normals => check("NORMAL", &a, Dimensions::Vec3, &float)?,
            Semantic::Tangents => check("TANGENT", &a, Dimensions::Vec4, &float)?,
            Semantic::TexCoords(0) => check(
                "TEXCOORD_0",
                &a,
                Dimensions::Vec2,
                &[DataType::F32, DataType::U8, DataType::U16],
            )?,
            _ => {}
        }
    }
    if let Some(a) = prim.indices() {
        check(
            "indices",
            &a,
            Dimensions::Scalar,
            &[DataType::U8, DataType::U16, DataType::U32],
        )?;
    }
    Ok(())
}

/// Checks what the gltf crate (1.4) would panic on instead of reporting,
/// both found by fuzzing: a binary header declaring fewer than its own 12
/// bytes (an unchecked subtraction), and a primitive whose POSITION names
/// an accessor that does not exist (indexed unchecked during validation).
fn check_glb_header(path: &Path) -> Result<(), String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let glb = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let len = bytes.len() as u64;
    if glb {
        if let Some(problem) = crate::fsutil::too_short(len, 12, "a binary glTF header (12 bytes)")
        {
            return Err(problem);
        }
        if &bytes[0..4] != b"glTF" {
            return Err(format!(
                "not a binary glTF: it starts with {:?}, not the \"glTF\" magic",
                String::from_utf8_lossy(&bytes[0..4])
            ));
        }
    } else if let Some(problem) = crate::fsutil::too_short(len, 2, "a glTF document") {
        return Err(problem);
    } else if bytes.trim_ascii_start().first() != Some(&b'{')
        && &bytes[0..4.min(bytes.len())] != b"glTF"
    {
        return Err("not a glTF document: a .gltf file is JSON, starting with '{'".into());
    }
    let json: &[u8] = if bytes.len() >= 12 && &bytes[0..4] == b"glTF" {
        let word = |at: usize| {
            bytes
                .get(at..at + 4)
                .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize)
        };
        let declared = word(8).unwrap_or(0);
        if declared < 12 || declared > bytes.len() {
            return Err(format!(
                "binary glTF header declares {declared} bytes; the file has {}",
                bytes.len()
            ));
        }
        match word(12) {
            Some(len) => bytes.get(20..20 + len).unwrap_or(&[]),
            None => &[],
        }
    } else {
        &bytes
    };
    // gltf skips unknown keys without checking their UTF-8, so read the
    // JSON as leniently (the fuzzer's second find hid behind such a key).
    let text = String::from_utf8_lossy(json);
    let Ok(root) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Ok(()); // not JSON: the parser reports it
    };
    let accessors = root["accessors"].as_array().map_or(0, |a| a.len());
    let meshes = root["meshes"].as_array().map(Vec::as_slice).unwrap_or(&[]);
    for (m, mesh) in meshes.iter().enumerate() {
        let prims = mesh["primitives"]
            .as_array()
            .map(Vec::as_slice)
            .unwrap_or(&[]);
        for (k, prim) in prims.iter().enumerate() {
            if let Some(i) = prim["attributes"]["POSITION"].as_u64() {
                if i as usize >= accessors {
                    return Err(format!(
                        "mesh {m} primitive {k}: POSITION names accessor {i}, but there are {accessors}"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The first material's base colour, normal and roughness textures.
fn read_material(
    m: &gltf::Material,
    images: &[gltf::image::Data],
    origin: &str,
    out: &mut MeshTextures,
) -> Result<(), MeshError> {
    let pbr = m.pbr_metallic_roughness();
    let image = |tex: gltf::texture::Texture, slot, channel| {
        images
            .get(tex.source().index())
            .map(|d| decode(d, slot, channel, origin))
            .transpose()
    };
    if let Some(t) = pbr.base_color_texture() {
        if let Some(img) = image(t.texture(), TextureSlot::Albedo, 0)? {
            out.albedo = img;
            out.albedo_mode = AlbedoMode::Absolute;
        }
    }
    if let Some(t) = m.normal_texture() {
        if let Some(img) = image(t.texture(), TextureSlot::Normal, 0)? {
            out.normal = img;
        }
    }
    if let Some(t) = pbr.metallic_roughness_texture() {
        // glTF keeps roughness in the green channel.
        if let Some(img) = image(t.texture(), TextureSlot::Roughness, 1)? {
            out.roughness = img;
            out.roughness_mode = RoughnessMode::Absolute;
        }
    }
    Ok(())
}

/// An embedded or referenced image, 8-bit formats only.
fn decode(
    d: &gltf::image::Data,
    slot: TextureSlot,
    channel: usize,
    origin: &str,
) -> Result<TextureImage, MeshError> {
    use gltf::image::Format;
    let (w, h) = (d.width, d.height);
    let fail = |message: String| {
        MeshError::Texture(crate::render::textures::TextureError::Load {
            path: origin.into(),
            slot: slot.name(),
            message,
        })
    };
    let img = match d.format {
        Format::R8 => image::GrayImage::from_raw(w, h, d.pixels.clone()).map(Into::into),
        Format::R8G8 => image::GrayAlphaImage::from_raw(w, h, d.pixels.clone()).map(Into::into),
        Format::R8G8B8 => image::RgbImage::from_raw(w, h, d.pixels.clone()).map(Into::into),
        Format::R8G8B8A8 => image::RgbaImage::from_raw(w, h, d.pixels.clone()).map(Into::into),
        f => return Err(fail(format!("{f:?} texels are not supported (8-bit only)"))),
    };
    let img: image::DynamicImage =
        img.ok_or_else(|| fail("texel data shorter than the image size".into()))?;
    let img = if channel > 0 {
        // Move the wanted channel to the front (red) for single-channel slots.
        let mut rgba = img.to_rgba8();
        for p in rgba.pixels_mut() {
            p.0[0] = p.0[channel];
        }
        image::DynamicImage::ImageRgba8(rgba)
    } else {
        img
    };
    Ok(from_dynamic(img, slot, origin)?)
}

#[cfg(test)]
mod tests {
    /// A GLB header declaring fewer bytes than the header itself is refused
    /// by name (the gltf crate would panic on it).
    #[test]
    fn short_glb_header_is_refused() {
        let path = std::env::temp_dir().join(format!("scatterlab-glb-{}.glb", std::process::id()));
        let mut bytes = b"glTF".to_vec();
        bytes.extend(2u32.to_le_bytes());
        bytes.extend(4u32.to_le_bytes());
        bytes.extend([0u8; 20]);
        std::fs::write(&path, &bytes).unwrap();
        let e = super::load(&path, 1.0).map(|_| ()).unwrap_err().to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(
            e.contains("scatterlab-glb-") && e.contains("declares 4 bytes"),
            "{e}"
        );
    }

    /// A POSITION accessor that does not exist is refused by name (the
    /// gltf crate's validation would index out of bounds).
    #[test]
    fn missing_position_accessor_is_refused() {
        let json = r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":3}}]}],"accessors":[]}"#;
        let path = std::env::temp_dir().join(format!("scatterlab-acc-{}.gltf", std::process::id()));
        std::fs::write(&path, json).unwrap();
        let e = super::load(&path, 1.0).map(|_| ()).unwrap_err().to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(
            e.contains("scatterlab-acc-") && e.contains("accessor 3"),
            "{e}"
        );
    }

    /// A node that is its own grandchild is refused, not walked forever.
    #[test]
    fn cyclic_node_hierarchy_is_refused() {
        let json = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
            "nodes":[{"children":[1]},{"children":[0]}]}"#;
        let path =
            std::env::temp_dir().join(format!("scatterlab-cycle-{}.gltf", std::process::id()));
        std::fs::write(&path, json).unwrap();
        let e = super::load(&path, 1.0).map(|_| ()).unwrap_err().to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(e.contains("scatterlab-cycle-"), "{e}");
    }
}

#[cfg(test)]
mod part_tests {
    use super::part_kind;

    #[test]
    fn parts_by_name() {
        for (name, kind) in [
            ("Eye_L", 1.0),
            ("Cornea_R mesh", 1.0),
            ("Head Skin", 0.0),
            ("EyeBrows", 0.0),
            ("eyelashes", 0.0),
            ("Teeth_Upper", 2.0),
            ("", 0.0),
        ] {
            assert_eq!(part_kind(name).code(), kind, "{name}");
        }
    }
}
