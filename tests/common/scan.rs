//! Lee Perry-Smith's scan, the mesh that is not ours, as the yardstick
//! and the GPU truth's tests load and view it.

use scatterlab::render::textures::{self, AlbedoMode, TextureSlot};
use scatterlab::render::{Mesh, Method, RenderSettings};
use scatterlab::settings::OrbitView;
use std::path::Path;

/// The scan as another tool wrote it (glTF at 0.0462 m/unit, external
/// colour and normal maps with V flipped; assets/scan).
pub fn scan() -> Mesh {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scan");
    let mut mesh = Mesh::load(&root.join("LeePerrySmith.glb"), 0.0462).unwrap();
    let maps = std::sync::Arc::make_mut(&mut mesh.textures);
    let mut albedo = textures::load(&root.join("Map-COL.jpg"), TextureSlot::Albedo).unwrap();
    albedo.flip_v();
    maps.albedo = albedo;
    maps.albedo_mode = AlbedoMode::Absolute;
    let normal_map = root.join("Infinite-Level_02_Tangent_SmoothUV.jpg");
    let mut normal = textures::load(&normal_map, TextureSlot::Normal).unwrap();
    normal.flip_v();
    maps.normal = normal;
    mesh
}

/// The scan at ~1 mm a pixel (the bench's 640×360 head shots are 0.8–0.9
/// mm): 20° of view at the framing distance over 192 pixels, the ground
/// truth's settings.
pub fn scan_view(mesh: &Mesh, yaw_deg: f32, light: (f32, f32)) -> RenderSettings {
    RenderSettings {
        width: 192,
        height: 192,
        method: Method::Reference,
        view: OrbitView {
            camera_yaw_rad: yaw_deg.to_radians(),
            camera_distance_m: mesh.framing_distance_m(30f32.to_radians()),
            fov_y_rad: 20f32.to_radians(),
            light_azimuth_rad: light.0.to_radians(),
            light_elevation_rad: light.1.to_radians(),
            ..OrbitView::default()
        },
        mesh_lod: false,
        lod: false,
        deterministic: true,
        ..RenderSettings::default()
    }
}
