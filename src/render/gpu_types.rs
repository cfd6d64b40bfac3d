//! Rust twins of the WGSL uniform and storage structs. Each has explicit
//! padding (vec4 slots) and a size assertion; the comment names its twin.

use bytemuck::{Pod, Zeroable};

/// Twin of `SceneUniforms` in `shaders/scene.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct SceneUniforms {
    pub clip_from_world: [[f32; 4]; 4],
    pub view_from_world: [[f32; 4]; 4],
    pub camera_position: [f32; 4],
    /// xyz: towards a directional light; for a point light (w = 1) its
    /// position in world units.
    pub light_direction: [f32; 4],
    pub light_radiance: [f32; 4],
    pub surface_albedo: [f32; 4],
    /// x: pre-scatter exponent, y: roughness of lobe 0, z: F0, w: roughness of lobe 1.
    pub params: [f32; 4],
    pub light_clip_from_world: [[f32; 4]; 4],
    /// x: 1/shadow map size, y: depth bias, z: normal offset (world units).
    pub shadow: [f32; 4],
    /// x: 0 lit scene, 1 step in world x, 2 checkerboard; y: period (world units).
    pub pattern: [f32; 4],
    /// x: 1 for the pre-integrated method; y, z: curvature 1/c (1/mm) at the
    /// LUT's first and last rows.
    pub preintegrated: [f32; 4],
    /// x: 0 off, 1 thin object, 2 thick object; y: table range (mm);
    /// z: table size; w: mm per world unit.
    pub transmission: [f32; 4],
    /// rgb: transmission tint.
    pub transmission_tint: [f32; 4],
    /// x: lobe mix of the dual GGX, y: 1 = Kelemen/Szirmay-Kalos lobe.
    pub specular: [f32; 4],
    /// x: albedo map absolute (1) or ×2 modulation of surface_albedo (0);
    /// y: roughness map absolute (1) or ×2 scale (0); z: thickness map
    /// range (mm), 0 = per-vertex bake; w: detail-normal strength.
    pub surface: [f32; 4],
    /// `preintegrated`: xyz: per-channel blend of the detail normal back to
    /// the smooth one; w: 1 = penumbra table on.
    pub preintegrated_normals: [f32; 4],
    /// Penumbra table: x, y: 1/width (1/mm) at its first and last rows;
    /// z: the PCF footprint (mm) on a surface facing the light.
    pub penumbra: [f32; 4],
    /// The environment's irradiance / π as nine SH coefficients (rgb each),
    /// in `environment::sh9`'s order.
    pub environment_sh: [[f32; 4]; 9],
    /// Point light: x, y: shadow near/far (world units); z: the distance
    /// at which the light delivers `light_radiance`.
    pub light_range: [f32; 4],
    /// The eyeballs (material 1): xyz centre (world units), w radius; a
    /// radius of 0 means none. The shader draws sclera, iris, pupil and a
    /// glossy cornea from the direction to the centre.
    pub eyes: [[f32; 4]; 2],
}
const _: () = assert!(std::mem::size_of::<SceneUniforms>() == 3 * 64 + 26 * 16);

/// Twin of `SssUniforms` in `shaders/sss_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct SssUniforms {
    pub size: [f32; 4],
    pub projection: [f32; 4],
    pub params: [f32; 4],
    pub direction: [f32; 4],
    /// rgb: output multiplier (a Gaussian's weight when accumulating).
    pub weight: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<SssUniforms>() == 80);

/// Twin of `Sample` in `shaders/sss_burley.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuSample {
    pub radius_mm: f32,
    pub angle: f32,
    pub inv_pdf: f32,
    pub pad: f32,
}
const _: () = assert!(std::mem::size_of::<GpuSample>() == 16);

/// Twin of `Tap` in `shaders/sss_separable.wgsl`: rgb weight, a = offset (mm).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTap {
    pub weight_offset: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuTap>() == 16);

/// Twin of `CompositeUniforms` in `shaders/composite.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct CompositeUniforms {
    pub exposure: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<CompositeUniforms>() == 16);

/// Mesh vertex (locations 0–3 in `shaders/scene.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    /// 0 skin, 1 eye, 2 teeth.
    pub material: f32,
    /// Mean curvature 1/radius in 1/mm (FaceWorks' per-vertex estimate).
    pub curvature_per_mm: f32,
    /// Thickness (mm) along the inward normal, baked by ray casting.
    pub thickness_mm: f32,
    /// Unit tangent along +u and the bitangent's sign (glTF's TANGENT):
    /// B = w · N × T points along +v, up in the image.
    pub tangent: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<Vertex>() == 60);
