//! Helpers shared by the integration tests (each test file includes this
//! module with `mod common;`).
#![allow(dead_code)]

/// A glTF square with an embedded buffer (see [`quad_gltf_with`]).
pub fn quad_gltf(uvs: bool) -> String {
    quad_gltf_with(uvs, 0.5, false)
}

/// A square of side 2·`half` units facing +z; UVs with glTF's top-left
/// origin (v = 0 at the top edge), or with V up (v = 0 at the bottom) when
/// `v_up`, as files from OpenGL-convention tools come.
pub fn quad_gltf_with(uvs: bool, half: f32, v_up: bool) -> String {
    let mut bytes = Vec::new();
    for p in [
        [-half, -half, 0.0f32],
        [half, -half, 0.0],
        [half, half, 0.0],
        [-half, half, 0.0],
    ] {
        for c in p {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    let (bottom, top) = if v_up { (0.0f32, 1.0) } else { (1.0, 0.0) };
    for t in [[0.0f32, bottom], [1.0, bottom], [1.0, top], [0.0, top]] {
        for c in t {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bytes.extend_from_slice(&i.to_le_bytes());
    }
    // Standard base64 (RFC 4648), written out so the test needs no crate.
    let table = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut b64 = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (k, b)| n | (*b as u32) << (16 - 8 * k));
        for k in 0..4 {
            if k <= chunk.len() {
                b64.push(table[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                b64.push('=');
            }
        }
    }
    let uv_attr = if uvs { r#", "TEXCOORD_0": 1"# } else { "" };
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
 "nodes": [{{"mesh": 0}}],
 "meshes": [{{"name": "quad", "primitives": [{{"attributes": {{"POSITION": 0{uv_attr}}}, "indices": 2}}]}}],
 "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{b64}"}}],
 "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}],
 "accessors": [
  {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-{half}, -{half}, 0.0], "max": [{half}, {half}, 0.0]}},
  {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
  {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}}"#,
        len = bytes.len()
    )
}

/// [`quad_gltf_with`] plus a material whose base colour is an external
/// image file (`uri`, relative to the .gltf), as scans ship their maps.
pub fn quad_gltf_textured(half: f32, v_up: bool, uri: &str) -> String {
    let base = quad_gltf_with(true, half, v_up);
    let base = base.replace(
        r#", "indices": 2}]}],"#,
        r#", "indices": 2, "material": 0}]}],"#,
    );
    let end = base.rfind('}').expect("a JSON object");
    format!(
        r#"{}, "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
 "textures": [{{"source": 0}}], "images": [{{"uri": "{uri}"}}]}}"#,
        &base[..end]
    )
}

pub mod scan;

/// A UV sphere `diameter_m` across as OBJ text (metres), with UVs and
/// normals; `inside_out` winds its faces clockwise seen from outside (a
/// file exported inside out). Written here, not by scatterlab.
pub fn uv_sphere_obj(diameter_m: f32, inside_out: bool) -> String {
    let (n_lat, n_lon) = (24, 48);
    let r = 0.5 * diameter_m;
    let mut text = String::new();
    for i in 0..=n_lat {
        let t = i as f32 / n_lat as f32 * std::f32::consts::PI;
        for j in 0..n_lon {
            let p = j as f32 / n_lon as f32 * std::f32::consts::TAU;
            let n = [t.sin() * p.cos(), t.cos(), t.sin() * p.sin()];
            text += &format!(
                "v {} {} {}\nvt {} {}\nvn {} {} {}\n",
                r * n[0],
                r * n[1],
                r * n[2],
                j as f32 / n_lon as f32,
                1.0 - i as f32 / n_lat as f32,
                n[0],
                n[1],
                n[2]
            );
        }
    }
    let at = |i: usize, j: usize| i * n_lon + j % n_lon + 1;
    for i in 0..n_lat {
        for j in 0..n_lon {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            // Counter-clockwise seen from outside (glTF's and OBJ's front),
            // or clockwise for a file exported inside out.
            let q = if inside_out {
                [a, d, c, b]
            } else {
                [a, b, c, d]
            };
            let [a, b, c, d] = q;
            text += &format!("f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c} {d}/{d}/{d}\n");
        }
    }
    text
}
