//! Rust twins of the WGSL uniform and storage structs, and the WGSL
//! constants beside them. Scalars are named and packed four to a row,
//! modes are `u32`; each struct has a size assertion here and its field
//! names and offsets checked against naga's layout of its twin
//! (`tests/shaders.rs`).

use bytemuck::{Pod, Zeroable};

/// Declares a `#[repr(C)]` Pod struct uploaded to the GPU and lists each
/// field's name, byte offset and type in `FIELDS`, which `tests/shaders.rs`
/// compares with its WGSL twin as naga lays it out.
macro_rules! gpu_struct {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $field:ident : $ty:ty,)* }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Debug, Clone, Copy, Pod, Zeroable)]
        pub struct $name { $($(#[$fm])* pub $field: $ty,)* }
        impl $name {
            /// Each field's name, byte offset and type as written (its WGSL
            /// twin must match).
            pub const FIELDS: &'static [(&'static str, usize, &'static str)] = &[$((
                stringify!($field),
                std::mem::offset_of!($name, $field),
                stringify!($ty),
            ),)*];
        }
    };
}

/// `SceneUniforms::transmission_mode` (`TRANSMISSION_*` in `shaders/scene.wgsl`).
pub const TRANSMISSION_OFF: u32 = 0;
pub const TRANSMISSION_THIN: u32 = 1;
pub const TRANSMISSION_THICK: u32 = 2;
/// `SceneUniforms::pattern` (`PATTERN_*` in `shaders/scene.wgsl`).
pub const PATTERN_LIT: u32 = 0;
pub const PATTERN_STEP: u32 = 1;
pub const PATTERN_CHECKERBOARD: u32 = 2;
/// `SceneUniforms::specular_model` (`SPECULAR_*` in `shaders/scene.wgsl`).
pub const SPECULAR_DUAL_GGX: u32 = 0;
pub const SPECULAR_KELEMEN: u32 = 1;
/// `SceneUniforms::albedo_map_mode` and `roughness_map_mode`
/// (`MAP_*` in `shaders/scene.wgsl`).
pub const MAP_MODULATES: u32 = 0;
pub const MAP_ABSOLUTE: u32 = 1;
/// The albedo is `surface_albedo`; the map is not read (albedo only).
pub const MAP_LOOK: u32 = 2;
/// `BurleyUniforms::flags` bits (`SAMPLING_*` in `shaders/sss_burley.wgsl`;
/// [`crate::render::BurleySampling::shader_flags`]).
pub const SAMPLING_R2_ROTATION: u32 = 1;
pub const SAMPLING_CENTRE_WEIGHT: u32 = 2;
pub const SAMPLING_BILINEAR: u32 = 4;
/// The diffuse target's alpha on eyes and teeth (`DIFFUSE_ALPHA_NOT_SKIN`
/// in `shaders/scene.wgsl` and `shaders/sss_common.wgsl`): no skin, so no
/// light for the skin around it, its weight kept.
pub const DIFFUSE_ALPHA_NOT_SKIN: f32 = -1.0;
/// The diffuse target's alpha on the background, its clear value
/// (`DIFFUSE_ALPHA_BACKGROUND` in `shaders/sss_common.wgsl`): no surface
/// seen, its weight renormalised away.
pub const DIFFUSE_ALPHA_BACKGROUND: f32 = -2.0;

gpu_struct! {
    /// Twin of `SceneUniforms` in `shaders/scene.wgsl`: the camera, the
    /// light and the look for the shadow and scene passes. Lengths in world
    /// units unless named otherwise.
    pub struct SceneUniforms {
        pub clip_from_world: [[f32; 4]; 4],
        pub view_from_world: [[f32; 4]; 4],
        /// The shadow map's clip transform.
        pub light_clip_from_world: [[f32; 4]; 4],
        /// xyz: the eye; w = 1.
        pub camera_position: [f32; 4],
        /// xyz: towards a directional light (w = 0), or a point light's
        /// position (w = 1).
        pub light_direction: [f32; 4],
        /// rgb: irradiance at normal incidence.
        pub light_radiance: [f32; 4],
        /// The fill and rim lights (`settings::RigLight`): xyz towards
        /// each (unit, directional, unshadowed).
        pub rig_direction: [[f32; 4]; 2],
        /// rgb: each one's irradiance at normal incidence (0: off).
        pub rig_radiance: [[f32; 4]; 2],
        /// rgb: the look's colour (total reflectance), linear.
        pub surface_albedo: [f32; 4],
        /// rgb: transmission tint.
        pub transmission_tint: [f32; 4],
        /// rgb, `preintegrated`: the profile's per-axis σ (mm) per channel,
        /// which picks the mip of the normal map each channel's blurred
        /// normal is read from (FaceWorks' `CalculateMipLevelForBlurredNormal`).
        pub blur_sigma_mm: [f32; 4],
        /// The environment's irradiance / π as nine SH coefficients (rgb
        /// each), in `environment::sh9`'s order.
        pub environment_sh: [[f32; 4]; 9],
        /// The eyeballs (material 1): xyz centre, w radius (0 = none). The
        /// shader draws sclera, iris, pupil and a glossy cornea from the
        /// direction to the centre.
        pub eyes: [[f32; 4]; 2],
        /// 0 post-scatter texturing, 0.5 pre- and post-scatter.
        pub pre_scatter_exponent: f32,
        /// Specular lobe 0's roughness.
        pub roughness0: f32,
        pub specular_f0: f32,
        /// Specular lobe 1's roughness (the dual GGX; = lobe 0 for Kelemen).
        pub roughness1: f32,
        /// Lobe 1's share of the dual GGX.
        pub lobe_mix: f32,
        /// `SPECULAR_*`.
        pub specular_model: u32,
        /// `PATTERN_*`: the lit scene, or a test pattern of irradiance.
        pub pattern: u32,
        /// The checkerboard's period.
        pub pattern_period: f32,
        /// 1 / shadow map size.
        pub shadow_texel: f32,
        /// Depth bias (light clip depth).
        pub shadow_depth_bias: f32,
        /// Normal offset (one shadow texel).
        pub shadow_normal_offset: f32,
        /// Depth range of the orthographic light projection.
        pub shadow_depth_range: f32,
        /// Point light: the shadow's near and far planes, and the distance
        /// at which the light delivers `light_radiance`.
        pub light_near: f32,
        pub light_far: f32,
        pub light_reference_distance: f32,
        pub pad0: f32,
        /// `TRANSMISSION_*`.
        pub transmission_mode: u32,
        /// The transmittance table's range (mm) and entries.
        pub transmittance_range_mm: f32,
        pub transmittance_entries: u32,
        pub mm_per_unit: f32,
        /// 1 for the `preintegrated` method.
        pub preintegrated: u32,
        /// Curvature 1/r (1/mm) at the LUT's first and last rows.
        pub lut_curvature_first: f32,
        pub lut_curvature_last: f32,
        /// 1 = Penner's penumbra table on.
        pub penumbra_on: u32,
        /// `MAP_*`: albedo map absolute, or ×2 modulation of `surface_albedo`.
        pub albedo_map_mode: u32,
        /// `MAP_*`: roughness map absolute, or ×2 scale.
        pub roughness_map_mode: u32,
        /// Thickness map range (mm); 0 = the per-vertex bake.
        pub thickness_map_range_mm: f32,
        pub detail_normal_strength: f32,
        /// Penumbra table: 1/width (1/mm) at its first and last rows.
        pub penumbra_inv_width_first: f32,
        pub penumbra_inv_width_last: f32,
        /// The PCF footprint (mm) on a surface facing the light.
        pub pcf_footprint_mm: f32,
        pub pad1: f32,
    }
}
const _: () = assert!(std::mem::size_of::<SceneUniforms>() == 3 * 64 + 21 * 16 + 8 * 16);

gpu_struct! {
    /// Twin of `SssUniforms` in `shaders/sss_common.wgsl`: what every
    /// screen-space SSS pass reads.
    pub struct SssUniforms {
        /// Pixels.
        pub size: [f32; 2],
        /// Pixels per world unit at depth 1: height / (2 tan(fov_y / 2)).
        pub pixels_per_unit_at_depth_1: f32,
        pub mm_per_unit: f32,
        /// The progressive-refinement frame's rotation offset (turns).
        pub rotation_offset_turns: f32,
        /// 1: no per-pixel rotation (tests).
        pub deterministic: u32,
        /// Samples (`burley`) or taps (`separable`).
        pub sample_count: u32,
        /// The profile table's largest radius (mm) and entries.
        pub lut_radius_mm: f32,
        pub lut_entries: u32,
        /// Follow surface: > 0, the 2012 lerp per mm; < 0, −1/(2σ²) of
        /// Jimenez 2015 eq. 7.
        pub follow_surface: f32,
        /// A separable pass's blur direction (pixels).
        pub direction: [f32; 2],
        /// 1 = stochastic axis rotation (Jimenez 2015 §6).
        pub rotate_axis: u32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
        /// rgb: output multiplier (a Gaussian's weight when accumulating).
        pub weight: [f32; 4],
    }
}
const _: () = assert!(std::mem::size_of::<SssUniforms>() == 80);

gpu_struct! {
    /// Twin of `TextureSpaceUniforms` in `shaders/texture_space_scene.wgsl`:
    /// where `texture-space` hands over from the screen to the atlas.
    pub struct TextureSpaceUniforms {
        /// Samples nearer than this (mm, before the SSS mask scales the
        /// radii) are read on screen, the rest in the atlas; 0: all in
        /// the atlas.
        pub near_field_mm: f32,
        pub pad0: f32,
        pub pad1: f32,
        pub pad2: f32,
    }
}
const _: () = assert!(std::mem::size_of::<TextureSpaceUniforms>() == 16);

gpu_struct! {
    /// Twin of `CloudUniforms` in `shaders/texture_space_cloud.wgsl`:
    /// `texture-space --neighbours 3d`'s tree and where it hands over.
    pub struct CloudUniforms {
        /// Level l's offset in the tree's nodes (l ≥ 1), four to a row.
        pub offsets: [[u32; 4]; 4],
        /// The root's level (its side is one node).
        pub top: u32,
        /// A node counts whole where its radius is at most θ times its
        /// centroid's distance.
        pub theta: f32,
        /// The near field's radius (mm, before the SSS mask scales it).
        pub near_mm: f32,
        /// The most surface (mm²) one texel stands for ([`TreeLevel`]'s).
        pub max_area_mm2: f32,
    }
}
const _: () = assert!(std::mem::size_of::<CloudUniforms>() == 80);

gpu_struct! {
    /// Twin of `TreeLevel` in `shaders/texture_space_tree.wgsl`: one level
    /// of `texture-space --neighbours 3d`'s tree to build.
    pub struct TreeLevel {
        /// This level's side in nodes.
        pub side: u32,
        /// 1: built from the atlas's texels; above, from the level below.
        pub level: u32,
        /// The level below's offset in the nodes.
        pub below: u32,
        /// This level's offset.
        pub at: u32,
        /// The most surface (mm²) one texel stands for: a sliver triangle
        /// that covers one texel's centre would otherwise lend it its
        /// whole surface-to-UV stretch (`cloud::texel_area_cap_mm2`).
        pub max_area_mm2: f32,
        pub pad0: f32,
        pub pad1: f32,
        pub pad2: f32,
    }
}
const _: () = assert!(std::mem::size_of::<TreeLevel>() == 32);

gpu_struct! {
    /// Twin of `Node` in `shaders/texture_space_tree.wgsl` (and
    /// `texture_space_cloud.wgsl`): a node of the atlas's point cloud.
    pub struct CloudNode {
        /// Σ A·E (rgb) and Σ A (mm²).
        pub light: [f32; 4],
        /// The area-weighted centroid (mm) and the bounding radius (mm).
        pub sphere: [f32; 4],
        /// The area-weighted mean squared distance from the centroid (mm²),
        /// then nothing.
        pub spread: [f32; 4],
    }
}
const _: () = assert!(std::mem::size_of::<CloudNode>() == 48);

gpu_struct! {
    /// Twin of `BurleyUniforms` in `shaders/sss_burley.wgsl`: the discrete
    /// LOD and the sampling flags.
    pub struct BurleyUniforms {
        /// Samples of the low-LOD pattern stored after the main one.
        pub low_count: u32,
        /// The widest channel's 0.997 radius (mm): the disk the LOD sizes.
        pub filter_radius_mm: f32,
        /// 1 = LOD on.
        pub lod_on: u32,
        /// `SAMPLING_*` bits.
        pub flags: u32,
    }
}
const _: () = assert!(std::mem::size_of::<BurleyUniforms>() == 16);

gpu_struct! {
    /// Twin of `Sample` in `shaders/sss_burley.wgsl`.
    pub struct GpuSample {
        pub radius_mm: f32,
        pub angle: f32,
        pub inv_pdf: f32,
        pub pad: f32,
    }
}
const _: () = assert!(std::mem::size_of::<GpuSample>() == 16);

gpu_struct! {
    /// Twin of `Tap` in `shaders/sss_separable.wgsl`: rgb weight, a = offset (mm).
    pub struct GpuTap {
        pub weight_offset: [f32; 4],
    }
}
const _: () = assert!(std::mem::size_of::<GpuTap>() == 16);

gpu_struct! {
    /// Twin of `CompositeUniforms` in `shaders/composite.wgsl`.
    pub struct CompositeUniforms {
        /// Exposure multiplier.
        pub exposure: f32,
        /// `TONE_*` ([`crate::render::tonemap::ToneMap::shader_id`]).
        pub tone_map: u32,
        /// 1: the environment map is drawn behind the head.
        pub background_on: u32,
        /// Its mip level (0 sharp; higher levels blur).
        pub background_lod: f32,
        /// Its turn about the up axis as a fraction of u (angle / 2π).
        pub background_turn: f32,
        /// Multiplier of its radiance (the environment's intensity).
        pub background_intensity: f32,
        /// The frame's size in pixels (the targets may be larger).
        pub frame_width: f32,
        pub frame_height: f32,
        /// Clip space to a world direction from the eye (the inverse of
        /// projection × the view's rotation).
        pub direction_from_clip: [[f32; 4]; 4],
    }
}
const _: () = assert!(std::mem::size_of::<CompositeUniforms>() == 96);

/// What a surface is: skin scatters; eyes and teeth do not (the eye is
/// drawn with an iris). On the GPU a float vertex attribute
/// (`Vertex::material`, `shaders/scene.wgsl`: 0 skin, 1 eye, 2 teeth, read
/// with thresholds at 0.5 and 1.5 because it is interpolated).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceKind {
    Skin,
    Eye,
    Teeth,
}

impl SurfaceKind {
    /// The vertex attribute's value.
    pub fn code(self) -> f32 {
        match self {
            SurfaceKind::Skin => 0.0,
            SurfaceKind::Eye => 1.0,
            SurfaceKind::Teeth => 2.0,
        }
    }

    /// The kind an (interpolated) attribute value stands for, with the
    /// shader's thresholds.
    pub fn of(code: f32) -> Self {
        if code < 0.5 {
            SurfaceKind::Skin
        } else if code < 1.5 {
            SurfaceKind::Eye
        } else {
            SurfaceKind::Teeth
        }
    }
}

/// Mesh vertex (locations 0–3 in `shaders/scene.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    /// [`SurfaceKind::code`]: 0 skin, 1 eye, 2 teeth.
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

gpu_struct! {
    /// Twin of `GatherParams` in `shaders/ground_truth.wgsl`: the GPU
    /// ground truth's table grid, bounds, dispatch and quadrature.
    pub struct GatherParams {
        /// The table's grid (`ProfileTable`): ln r₀, 1/step, r₀ (mm).
        pub ln_r0: f32,
        pub inv_step: f32,
        pub r0_mm: f32,
        /// Truncation radius, smallest split (mm) and the cloud's reach.
        pub r_max_mm: f32,
        pub epsilon_mm: f32,
        pub reach_mm: f32,
        /// Points in this dispatch and the first of them.
        pub count: u32,
        pub first: u32,
        /// CDF at r = 0 (rgb, and 0).
        pub cdf_zero: [f32; 4],
        /// Where the roots and the leaf order start in `tree` (vec4s), and
        /// the number of clusters.
        pub roots_at: u32,
        pub order_at: u32,
        pub clusters: u32,
        /// The table's splitting tolerance (`TruthBound::uneven`).
        pub uneven: f32,
        /// 8-point Gauss–Legendre on [−1, 1], four a row.
        pub gl_nodes: [[f32; 4]; 2],
        pub gl_weights: [[f32; 4]; 2],
    }
}
