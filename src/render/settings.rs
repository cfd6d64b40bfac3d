//! What a frame looks like and what it reports.

/// The method, texturing and transmission choices are the settings' own
/// enums: one definition each, for presets, the command line and the
/// renderer.
pub use crate::settings::rendering::{
    MethodId as Method, TexturingId as TexturingMode, TransmissionId as Transmission,
};
use crate::settings::{OrbitView, RenderingSpec};

/// What one frame looks like.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub method: Method,
    pub texturing: TexturingMode,
    /// Camera and light ([`OrbitView`]: radians and metres).
    pub view: OrbitView,
    /// Turns off per-pixel random rotation (for tests).
    pub deterministic: bool,
    /// Lighting, or a flat irradiance test pattern.
    pub pattern: IrradiancePattern,
    pub transmission: Transmission,
    pub transmission_tint: [f32; 3],
    /// Burley's discrete LOD (no convolution under 1 px, short pattern under 4 px).
    pub lod: bool,
    /// Draw the mesh's coarse level of detail when its edges are under
    /// 10 px; false always draws the finest (as `reference` does, so that
    /// `bench` compares every method on the same surface).
    pub mesh_lod: bool,
    pub specular: Specular,
    /// Specular reflectance at normal incidence (from the IOR).
    pub specular_f0: f32,
    /// Strength of the detail normal map (0 = smooth surface normals).
    pub detail_normal_strength: f32,
    /// The environment's irradiance / π as order-2 SH
    /// ([`super::environment::Environment::irradiance_sh`]).
    pub environment_sh: [[f32; 3]; 9],
    /// Progressive refinement (the editor, once input stops): this frame
    /// is one more sample of a running mean; `None` renders it alone.
    pub progressive: Option<Progressive>,
    /// The ground truth in tiles (the editor): this frame gathers the next
    /// tiles of the view for about a budget and the next frame of the same
    /// view goes on from there; `None` gathers the whole view.
    pub truth_tiles: Option<TruthTiles>,
    /// Where the surface colour comes from on a mesh with a colour map of
    /// its own (the default head's modulating map ignores it).
    pub map_colour: super::textures::MapColour,
    /// The display transform after exposure.
    pub tone_map: super::tonemap::ToneMap,
    /// Draw the environment map set with `Renderer::set_background`
    /// behind the head (`None`: the plain grey).
    pub background: Option<Background>,
}

/// How the environment map is drawn behind the head.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Background {
    /// 0 sharp … 1 its coarsest mip level.
    pub blur: f32,
    /// The map's turn about the up axis (the lighting's SH turned alike:
    /// `environment::rotate_sh_about_up`).
    pub turn_rad: f32,
    /// Multiplier of its radiance (the environment's intensity).
    pub intensity: f32,
}

/// How the editor asks for the ground truth: in square tiles of
/// `tile_px`, those nearest `focus` first (fractions of the frame's width
/// and height: the cursor, else the centre), for about `budget_ms` of
/// gathering a frame. The finished view is the same frame as one gathered
/// whole.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthTiles {
    pub tile_px: u32,
    pub focus: [f32; 2],
    pub budget_ms: f64,
}

/// How far a view's ground truth in tiles has got
/// ([`FrameStats::truth_tiles`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TruthProgress {
    pub tile_px: u32,
    /// Tiles across and down.
    pub columns: u32,
    pub rows: u32,
    /// Per tile, row by row: whether its pixels are the ground truth's
    /// (a tile with no SSS pixel is done from the start).
    pub done: Vec<bool>,
    /// The tiles that hold SSS pixels, and how many of those are done.
    pub skin_tiles: u32,
    pub skin_tiles_done: u32,
    /// SSS pixels gathered and in all.
    pub pixels_done: u64,
    pub pixels_total: u64,
    /// Time spent gathering this view so far, over all its frames (ms).
    pub gather_ms: f64,
}

impl TruthProgress {
    pub fn finished(&self) -> bool {
        self.done.iter().all(|d| *d)
    }

    pub fn tiles_done(&self) -> usize {
        self.done.iter().filter(|d| **d).count()
    }

    /// Whether pixel (x, y) is in a finished tile.
    pub fn is_done(&self, x: u32, y: u32) -> bool {
        let (c, r) = (x / self.tile_px.max(1), y / self.tile_px.max(1));
        c < self.columns && r < self.rows && self.done[(r * self.columns + c) as usize]
    }
}

/// One frame of progressive refinement: its SSS result joins the running
/// mean in accumulator `slot` (0: A, 1: B of a comparison) as sample
/// `frame` (0 starts a new mean), with the stochastic methods' per-pixel
/// rotations offset by `frame` × the golden ratio's fraction of a turn (a
/// rank-1 sequence: each new frame lands in the widest gap left by the
/// ones before). Frame 0 is the same image as a frame rendered alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progressive {
    pub slot: usize,
    pub frame: u32,
}

impl Progressive {
    /// Fraction of a turn added to every pixel's sample rotation.
    pub fn rotation_offset(&self) -> f32 {
        const GOLDEN_FRACTION: f64 = 0.618_033_988_749_895;
        (self.frame as f64 * GOLDEN_FRACTION).fract() as f32
    }
}

impl RenderSettings {
    /// The one way from a look's rendering settings and a view to a frame's
    /// settings, for the editor and the command line (the bench's fixed
    /// scenes set theirs directly; specular does not enter its error). Every
    /// field of the spec is named: a new one does not compile until it is
    /// placed here or marked as read elsewhere.
    pub fn for_look(
        rendering: &RenderingSpec,
        view: OrbitView,
        environment_sh: [[f32; 3]; 9],
        (width, height): (u32, u32),
    ) -> Self {
        let RenderingSpec {
            method,
            // Burley's pattern and the separable kernel are profile inputs
            // (`ProfileInputs::for_method`), not frame settings.
            samples: _,
            taps: _,
            lod,
            texturing,
            transmission,
            // Read where a thickness map is loaded (`app/viewport.rs`,
            // `cli/render.rs`).
            thickness_remap_mm: _,
            transmission_tint,
            ior: _,
            // Unity's export scale (`model::units::UnityProfile`); a mesh's
            // own units come with the mesh.
            world_scale_m_per_unit: _,
            specular,
            // The editor resolves it into the profile's albedo before a
            // frame (`app::viewport::Look`).
            albedo_in_material: _,
        } = rendering;
        Self {
            width,
            height,
            method: *method,
            texturing: *texturing,
            view,
            transmission: *transmission,
            transmission_tint: transmission_tint.map(|v| v as f32),
            lod: *lod,
            specular: Specular::dual_ggx(specular),
            // From the IOR (Fresnel at normal incidence).
            specular_f0: rendering.f0() as f32,
            environment_sh,
            ..Self::default()
        }
    }
}

/// The specular model (its own buffer; never blurred).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Specular {
    /// Unreal's dual GGX: two roughnesses mixed by `lobe_mix`.
    DualGgx {
        roughness0: f32,
        roughness1: f32,
        lobe_mix: f32,
    },
    /// Kelemen/Szirmay-Kalos with a Beckmann lobe (d'Eon 2007).
    Kelemen { roughness: f32 },
}

impl Specular {
    /// Unreal's dual lobes: each lobe's roughness is the material's times
    /// its multiplier, at most 1.
    pub fn dual_ggx(s: &crate::settings::rendering::DualLobeSpec) -> Self {
        Self::DualGgx {
            roughness0: (s.roughness * s.lobe0_roughness_multiplier).min(1.0) as f32,
            roughness1: (s.roughness * s.lobe1_roughness_multiplier).min(1.0) as f32,
            lobe_mix: s.lobe_mix as f32,
        }
    }
}

/// Irradiance for test scenes: lit normally, a step at world x = 0, or a
/// checkerboard, each of the key light's irradiance (its intensity ×
/// colour; flat, unshaded, the fill and rim left out).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IrradiancePattern {
    Lit,
    Step,
    Checkerboard { period_mm: f32 },
}

/// The default sky's SH, integrated once per process (a 128 × 256 grid).
fn default_environment_sh() -> [[f32; 3]; 9] {
    static SH: std::sync::OnceLock<[[f32; 3]; 9]> = std::sync::OnceLock::new();
    *SH.get_or_init(|| super::environment::Environment::default().irradiance_sh())
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            method: Method::default(),
            texturing: TexturingMode::PreAndPostScatter,
            view: OrbitView::default(),
            deterministic: false,
            pattern: IrradiancePattern::Lit,
            transmission: Transmission::ThinObject,
            transmission_tint: [1.0, 1.0, 1.0],
            lod: true,
            mesh_lod: true,
            // The default look's: Unreal's SubsurfaceProfile defaults
            // (Roughness0 0.75 and Roughness1 1.30 as multipliers of a
            // material roughness of 0.55, LobeMix 0.85) and IOR 1.4, F0 =
            // ((1.4 − 1)/(1.4 + 1))² (settings::rendering), so a frame with
            // default settings is the default look's.
            specular: Specular::dual_ggx(&RenderingSpec::default().specular),
            specular_f0: RenderingSpec::default().f0() as f32,
            detail_normal_strength: 1.0,
            environment_sh: default_environment_sh(),
            progressive: None,
            truth_tiles: None,
            map_colour: Default::default(),
            tone_map: Default::default(),
            background: None,
        }
    }
}

/// What a frame did: the proof that skipped work was skipped
/// (`render --stats` writes it as JSON, field by field).
#[cfg(feature = "gpu")]
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FrameStats {
    pub method: &'static str,
    /// Every pass the frame ran, in order.
    pub passes: Vec<super::timing::PassStats>,
    pub samples_per_sss_pixel: u32,
    /// Pixels whose SSS mask exceeds 1/255, counted on the GPU.
    pub sss_pixels: u64,
    /// Samples the SSS passes took: counted on the GPU for burley and
    /// reference, sss_pixels × taps for the separable methods.
    pub sss_samples: u64,
    /// Pixels the Burley LOD left unconvolved (disk under one pixel).
    pub lod_skipped_pixels: u64,
    /// GPU time of all SSS passes (ms) from timestamp queries, where the
    /// adapter has them (on lavapipe the "GPU" is the CPU); `None` when no
    /// SSS pass ran.
    pub sss_gpu_ms: Option<f64>,
    /// `reference`: CPU wall time of the ground truth (ms): building its
    /// irradiance cloud (only when the light, look or profile changed) and
    /// the gather over the SSS pixels.
    pub reference_cpu_ms: Option<f64>,
    /// `reference`: the part of `reference_cpu_ms` that built the cells
    /// (`None` where they were kept from an earlier frame).
    pub reference_build_ms: Option<f64>,
    /// `reference --reference-gpu`: the points whose walk the GPU did not
    /// finish (the driver ended its loops, or the stack was too small),
    /// gathered on the CPU instead; `None` when the CPU gathered them all.
    pub reference_gpu_unfinished: Option<u64>,
    /// `reference` in tiles ([`RenderSettings::truth_tiles`]): how far the
    /// view has got with this frame.
    pub truth_tiles: Option<TruthProgress>,
    /// Whether this frame uploaded the profile's tables, patterns and
    /// kernels (false while the profile is unchanged).
    pub profile_uploaded: bool,
    /// Progressive refinement past its first frame: nothing the scene
    /// pass depends on changed, so shadow, scene and classify were skipped.
    pub scene_reused: bool,
    /// GPU memory of the frame's render targets (bytes).
    pub target_bytes: u64,
    /// Triangles drawn (of the level of detail the frame chose).
    pub triangles: u64,
    pub width: u32,
    pub height: u32,
    /// The camera and key light in metres, for another renderer.
    pub camera: CameraRecord,
    pub adapter: String,
    /// The driver and its version ([`super::driver::describe`]): "lavapipe,
    /// Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)".
    pub driver: String,
    /// A lavapipe older than the one the project installs, named with the
    /// line that upgrades it ([`super::driver::advice`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub driver_advice: Option<String>,
}

/// A frame's camera and key light in the renderer's world frame (y up,
/// right-handed, the mesh's units times `metres_per_unit`): what
/// `scatterlab render --stats` writes so that another renderer (Cycles,
/// tests/clients/blender_head.py) can set up the same shot. The camera is
/// a pinhole at `eye_m` looking at `target_m` with `up`, the vertical
/// field of view `fov_y_deg` over `height` pixels; the key light is
/// directional towards `toward_light`, delivering `light_irradiance`
/// (W/m², linear RGB) at normal incidence, or a point light at
/// `point_light_m` (with the renderer's falloff; the Cycles script refuses
/// it). What else lights the frame and is not described here (a fill or
/// rim light, the environment, specular reflection, transmission) is named
/// in `unrecorded`, so that a script can refuse a frame it cannot match.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CameraRecord {
    pub eye_m: [f32; 3],
    pub target_m: [f32; 3],
    pub up: [f32; 3],
    pub fov_y_deg: f32,
    pub width: u32,
    pub height: u32,
    pub toward_light: [f32; 3],
    pub light_irradiance: [f32; 3],
    pub point_light_m: Option<[f32; 3]>,
    pub metres_per_unit: f32,
    pub unrecorded: Vec<&'static str>,
}
