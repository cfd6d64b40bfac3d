//! `separable` (Jimenez 2012, `shaders/sss_separable.wgsl`): the profile
//! core's kernel in two depth-aware 1D passes, sssWidth from world scale
//! and projection, and the follow-surface term. The same 1D pass serves
//! each Gaussian of `gaussians`.

use super::{Scattered, SssFrame, SssPipelines};
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::renderer::HdrTarget;

/// Follow-surface strength (seed 000's SSSS_FOLLOW_SURFACE lerp per mm of
/// depth difference).
const FOLLOW_SURFACE: f32 = 0.5;

/// Blurs `src` along x into ping, then along y into `dst`, with `taps`.
pub(in crate::render) fn blur_xy(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
    taps: (&wgpu::Buffer, u32),
    (src, dst): (HdrTarget, HdrTarget),
    labels: [&'static str; 2],
) {
    let t = io.targets;
    for (dir, from, to, label) in [
        ([1.0, 0.0], src, HdrTarget::Ping, labels[0]),
        ([0.0, 1.0], HdrTarget::Ping, dst, labels[1]),
    ] {
        let u = f.uniform(
            "sss uniforms",
            bytemuck::bytes_of(&io.uniforms(taps.1 as f32, [dir[0], dir[1], FOLLOW_SURFACE, 0.0])),
        );
        let bg = bind_group(
            f.device,
            p,
            &u,
            t.view(from),
            &t.albedo_depth,
            taps.0,
            label,
        );
        f.fullscreen(
            t.view(to),
            &p.separable,
            &bg,
            label,
            (io.sss_pixels, io.sss_pixels * taps.1 as u64),
            false,
        );
    }
}

/// Bind group of one depth-aware 1D pass (or the accumulation).
pub(in crate::render) fn bind_group(
    device: &wgpu::Device,
    p: &SssPipelines,
    uniforms: &wgpu::Buffer,
    src: &wgpu::TextureView,
    albedo_depth: &wgpu::TextureView,
    taps: &wgpu::Buffer,
    label: &'static str,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &p.separable_layout,
        entries: &[
            buf(0, uniforms),
            tex(1, src),
            tex(2, albedo_depth),
            buf(3, taps),
        ],
    })
}

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let gpu = io.profile;
    blur_xy(
        f,
        p,
        io,
        (&gpu.separable_taps, gpu.tap_count),
        (HdrTarget::Diffuse, HdrTarget::Pong),
        ["sss separable x", "sss separable y"],
    );
    Scattered {
        target: HdrTarget::Pong,
        samples_per_pixel: 2 * gpu.tap_count,
        counted_pass: None,
    }
}
