//! The screen-space SSS methods, one file each: `burley`, `separable` and
//! `gaussians`, and the ground truth they are judged against,
//! `reference` (object space, on the CPU). `none` and `preintegrated` have no pass of their own: they
//! are lit in the scene pass (`shaders/scene.wgsl`; see `preintegrated.rs`).

pub(super) mod burley;
pub(super) mod gaussians;
pub(super) mod preintegrated;
pub(super) mod reference;
pub(super) mod separable;

use super::frame::FrameEncoder;
use super::gpu_types::SssUniforms;
use super::profile_gpu::ProfileGpu;
use super::settings::Method;
use super::targets::{HdrTarget, Targets};

/// The SSS methods' pipelines, built once with the renderer: switching
/// methods or editing the profile never recompiles a shader. Each method's
/// file builds its own (`gaussians` reuses `separable`'s).
pub(super) struct SssPipelines {
    pub burley: burley::Pipeline,
    pub separable: separable::Pipelines,
}

impl SssPipelines {
    pub fn new(device: &wgpu::Device, module: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self {
        Self {
            burley: burley::Pipeline::new(device, &module("sss_burley")),
            separable: separable::Pipelines::new(device, &module("sss_separable")),
        }
    }
}

/// What the SSS passes of one frame read and write.
pub(super) struct SssFrame<'t> {
    pub targets: &'t Targets,
    pub profile: &'t ProfileGpu,
    /// Pixels whose mask exceeds 1/255 (from the classify pass).
    pub sss_pixels: u64,
    /// Uniforms common to every pass; each pass sets the sample count and
    /// (separable) the direction, follow-surface term and axis rotation.
    pub uniforms: SssUniforms,
    /// GPU counters: samples taken, pixels convolved, pixels skipped by the LOD.
    pub counters: &'t wgpu::Buffer,
    pub lod: bool,
    /// `separable`: stochastic per-pixel axis rotation (Jimenez 2015 §6).
    pub rotate_separable: bool,
}

impl SssFrame<'_> {
    /// The shared uniforms with `count` samples or taps.
    pub fn uniforms(&self, count: u32) -> SssUniforms {
        SssUniforms {
            sample_count: count,
            ..self.uniforms
        }
    }
}

/// Where a method left the scattered irradiance, and what it sampled.
pub(super) struct Scattered {
    pub target: HdrTarget,
    pub samples_per_pixel: u32,
    /// The pass whose samples the GPU counters measured, if any.
    pub counted_pass: Option<&'static str>,
}

/// Records `method`'s passes. `none` and `preintegrated` record nothing.
pub(super) fn encode(
    method: Method,
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    match method {
        Method::None | Method::Preintegrated => Scattered {
            target: HdrTarget::Diffuse,
            samples_per_pixel: 0,
            counted_pass: None,
        },
        Method::Burley => burley::encode(f, p, io),
        // The ground truth, computed on the CPU into the ping target before
        // this frame's composite (`reference.rs`).
        Method::Reference => Scattered {
            target: HdrTarget::Ping,
            samples_per_pixel: 0,
            counted_pass: None,
        },
        Method::Separable => separable::encode(f, p, io),
        Method::Gaussians => gaussians::encode(f, p, io),
    }
}
