//! `burley` (Golubev 2018, `shaders/sss_burley.wgsl`): one pass over an
//! importance-sampled disk with per-pixel rotation, energy-normalised
//! bilateral weights on the Euclidean distance and a discrete LOD. At a
//! high count (`--samples 2304`) it is the converged screen-space Burley
//! the sample-count studies compare against; the ground truth is
//! `reference` (`sss/reference.rs`), which shares its irradiance (light,
//! shadow map, PCF, maps) but none of its disk, pixel grid or weights.

use super::{Scattered, SssFrame, SssPipelines};
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::gpu_types::{BurleyUniforms, SssUniforms};
use crate::render::inputs::ProfileInputs;
use crate::render::pipelines::{
    buffer_entry, fullscreen_pipeline, texture_entry, uniform_entry, Output, Stencil, HDR,
};
use crate::render::profile_gpu::storage;
use crate::render::targets::HdrTarget;

/// `burley` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "burley",
    label: "burley (Golubev 2018 disk)",
    quality: super::Quality::Samples,
    stochastic: super::Stochastic::Always,
    reads: super::Reads {
        separable_kernel: false,
        penner_tables: false,
        gaussians: false,
    },
    penner_in_scene_pass: false,
    ground_truth: false,
    baseline: false,
    variant: "",
    colour: [31, 119, 180],
    encode,
};

/// `burley`'s share of the profile on the GPU.
pub(in crate::render) struct Buffers {
    /// The main pattern followed by the LOD's short one.
    samples: wgpu::Buffer,
    /// r·R_N(r) per channel (the weights), then the CDF.
    profile_lut: wgpu::Buffer,
    /// Samples of the main pattern.
    count: u32,
    /// Low-LOD count, filter radius (the widest channel's 0.997-energy
    /// radius, mm) and sampling flags; `lod_on` is set per frame.
    uniforms: BurleyUniforms,
}

impl Buffers {
    pub fn new(device: &wgpu::Device, inputs: &ProfileInputs) -> Self {
        let mut samples = inputs.samples.clone();
        samples.extend_from_slice(&inputs.low_samples);
        Self {
            samples: storage(device, "burley samples", bytemuck::cast_slice(&samples)),
            profile_lut: storage(device, "profile lut", bytemuck::cast_slice(&inputs.lut)),
            count: inputs.samples.len() as u32,
            uniforms: BurleyUniforms {
                low_count: inputs.low_samples.len() as u32,
                filter_radius_mm: inputs.filter_radius_mm,
                lod_on: 0,
                flags: inputs.burley_sampling.shader_flags(),
            },
        }
    }
}

/// `burley`'s layout and pipeline (`fs_burley`, testing the stencil).
pub(in crate::render) struct Pipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl Pipeline {
    pub fn new(device: &wgpu::Device, module: &wgpu::ShaderModule) -> Self {
        let storage = wgpu::BufferBindingType::Storage { read_only: true };
        let frag = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sss burley"),
            entries: &[
                uniform_entry::<SssUniforms>(0, frag),
                texture_entry(1),
                texture_entry(2),
                buffer_entry(3, storage, frag),
                buffer_entry(4, storage, frag),
                buffer_entry(
                    5,
                    wgpu::BufferBindingType::Storage { read_only: false },
                    frag,
                ),
                uniform_entry::<BurleyUniforms>(6, frag),
            ],
        });
        Self {
            pipeline: fullscreen_pipeline(
                device,
                module,
                "fs_burley",
                &layout,
                Output::Replace(HDR),
                Stencil::Test,
            ),
            layout,
        }
    }
}

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let gpu = &io.profile.burley;
    let (samples, n, label) = (&gpu.samples, gpu.count, "sss burley");
    let u = f.uniform("sss uniforms", bytemuck::bytes_of(&io.uniforms(n)));
    let lod = f.uniform(
        "burley uniforms",
        bytemuck::bytes_of(&BurleyUniforms {
            lod_on: io.lod as u32,
            ..gpu.uniforms
        }),
    );
    let t = io.targets;
    let bg = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &p.burley.layout,
        entries: &[
            buf(0, &u),
            tex(1, t.view(HdrTarget::Diffuse)),
            tex(2, &t.linear_depth),
            buf(3, samples),
            buf(4, &gpu.profile_lut),
            buf(5, io.counters),
            buf(6, &lod),
        ],
    });
    f.fullscreen(
        Some(t.view(HdrTarget::Ping)),
        &p.burley.pipeline,
        &bg,
        label,
        (io.sss_pixels, io.sss_pixels * n as u64),
        false,
        true,
    );
    Scattered {
        target: HdrTarget::Ping,
        samples_per_pixel: n,
        counted_pass: Some(label),
    }
}
