//! `gaussians` (d'Eon 2007, Jimenez 2009 in screen space): the profile as
//! a sum of Gaussians, each blurred in two depth-aware 1D passes; each
//! vertical pass adds its Gaussian's RGB weight × result into the output
//! (additive blending), so N Gaussians cost 2N passes.

use super::separable::{self, Into};
use super::{Scattered, SssFrame, SssPipelines};
use crate::render::frame::FrameEncoder;
use crate::render::gpu_types::GpuTap;
use crate::render::inputs::{gaussian_taps, ProfileInputs};
use crate::render::profile_gpu::storage;
use crate::render::targets::HdrTarget;

/// `gaussians` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "gaussians",
    label: "gaussians (d'Eon 2007)",
    quality: super::Quality::Fixed,
    stochastic: super::Stochastic::Never,
    reads: super::Reads {
        separable_kernel: false,
        penner_tables: false,
        gaussians: true,
    },
    penner_in_scene_pass: false,
    ground_truth: false,
    baseline: false,
    variant: "6x2-passes",
    colour: [148, 103, 189],
    encode,
};

/// `gaussians`' share of the profile on the GPU: one tap buffer per
/// Gaussian, with its RGB weight and σ (mm).
pub(in crate::render) struct Buffers {
    gaussians: Vec<(wgpu::Buffer, [f32; 3], f32)>,
    /// Taps of each 1D pass.
    tap_count: u32,
}

impl Buffers {
    pub fn new(device: &wgpu::Device, inputs: &ProfileInputs) -> Self {
        Self {
            gaussians: inputs
                .gaussians
                .iter()
                .map(|(sigma, weight)| {
                    let taps: Vec<GpuTap> = gaussian_taps(*sigma, inputs.gaussian_taps);
                    let buffer = storage(device, "gaussian taps", bytemuck::cast_slice(&taps));
                    (buffer, *weight, *sigma)
                })
                .collect(),
            tap_count: gaussian_taps(1.0, inputs.gaussian_taps).len() as u32,
        }
    }
}

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let gpu = &io.profile.gaussians;
    let taps = gpu.tap_count;
    if gpu.gaussians.is_empty() {
        // No Gaussians set: nothing to add, the diffuse stays unscattered.
        return Scattered {
            target: HdrTarget::Diffuse,
            samples_per_pixel: 0,
            counted_pass: None,
        };
    }
    for (k, (buffer, weight, sigma)) in gpu.gaussians.iter().enumerate() {
        // Each Gaussian follows the surface with its own σ (Jimenez 2015
        // eq. 7 before its σ_max approximation: exact for a Gaussian).
        separable::blur_xy(
            f,
            p,
            io,
            (buffer, taps),
            *sigma,
            Into::Add {
                weight: *weight,
                first: k == 0,
            },
            ["sss gaussian x", "sss gaussian y"],
        );
    }
    Scattered {
        target: HdrTarget::Pong,
        samples_per_pixel: 2 * taps * gpu.gaussians.len() as u32,
        counted_pass: None,
    }
}
