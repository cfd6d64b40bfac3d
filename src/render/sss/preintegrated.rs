//! `preintegrated` (Penner 2011): no screen-space pass. The scene pass
//! (`shaders/scene.wgsl`) looks Penner's D(θ, κ) up from the profile
//! core's ring-integral table (uploaded in `profile_gpu.rs`) with the
//! per-vertex curvature FaceWorks computes, instead of saturate(N·L).

use crate::model::lut::LutLayout;
use crate::render::inputs::ProfileInputs;
use crate::render::profile_gpu::table;
use crate::render::settings::Method;

/// `preintegrated` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "preintegrated",
    label: "preintegrated (Penner 2011)",
    quality: super::Quality::Fixed,
    stochastic: super::Stochastic::Never,
    reads: super::Reads {
        separable_kernel: false,
        penner_tables: true,
        gaussians: false,
    },
    penner_in_scene_pass: true,
    ground_truth: false,
    baseline: false,
    variant: "",
    colour: [140, 86, 75],
    encode: super::no_pass,
};

/// Penner's tables on the GPU, filterable, read by the scene pass.
pub(in crate::render) struct Tables {
    /// D(θ, κ) − saturate(N·L).
    pub lut: wgpu::TextureView,
    /// The scattered shadow across a penumbra.
    pub penumbra: wgpu::TextureView,
}

impl Tables {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &ProfileInputs) -> Self {
        let (lut, pen) = (&inputs.lut_layout, &inputs.penumbra_layout);
        Self {
            lut: table(
                device,
                queue,
                "pre-integrated lut",
                (lut.width, lut.height),
                &inputs.preintegrated_lut,
            ),
            penumbra: table(
                device,
                queue,
                "penumbra lut",
                (pen.width, pen.height),
                &inputs.penumbra_lut,
            ),
        }
    }
}

/// `SceneUniforms::preintegrated` (1 for this method) and the curvature
/// 1/r (1/mm) of the table's first and last rows
/// (`lut_curvature_first`, `lut_curvature_last`).
pub(in crate::render) fn uniforms(method: Method, layout: &LutLayout) -> (u32, f32, f32) {
    (
        method.sss().penner_in_scene_pass as u32,
        1.0 / layout.curvature_radius(0) as f32,
        1.0 / layout.curvature_radius(layout.height - 1) as f32,
    )
}
