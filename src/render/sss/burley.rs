//! `burley` (Golubev 2018, `shaders/sss_burley.wgsl`): one pass over an
//! importance-sampled disk with per-pixel rotation, energy-normalised
//! bilateral weights on the Euclidean distance and a discrete LOD. At a
//! high count (`--samples 2304`) it is the converged screen-space Burley
//! the sample-count studies compare against; the ground truth is
//! `reference` (`sss/reference.rs`), which shares none of this.

use super::{Scattered, SssFrame, SssPipelines};
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::gpu_types::BurleyUniforms;
use crate::render::targets::HdrTarget;

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let gpu = io.profile;
    let (samples, n, label) = (&gpu.burley_samples, gpu.burley_count, "sss burley");
    let u = f.uniform("sss uniforms", bytemuck::bytes_of(&io.uniforms(n)));
    let lod = f.uniform(
        "burley uniforms",
        bytemuck::bytes_of(&BurleyUniforms {
            low_count: gpu.low_count,
            filter_radius_mm: gpu.filter_radius_mm,
            lod_on: io.lod as u32,
            flags: gpu.burley_flags,
        }),
    );
    let t = io.targets;
    let bg = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &p.burley_layout,
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
        &p.burley,
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
