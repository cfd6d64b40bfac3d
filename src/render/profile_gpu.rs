//! The profile's GPU resources that every method shares (the
//! transmittance table the scene pass reads), and the helpers each
//! method's file under `sss/` uploads its own share with (`storage`,
//! `table`); `sss::ProfileGpu` gathers them.

use super::inputs::Shared;
use super::readback::f32_to_half;
use super::textures::sampled_texture;
use wgpu::util::DeviceExt;

/// What every method shares on the GPU.
pub(super) struct SharedGpu {
    /// The thin-slab transmittance T(d)/total (the scene pass's).
    pub transmittance: wgpu::Buffer,
}

impl SharedGpu {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        Self {
            transmittance: storage(
                device,
                "transmittance",
                bytemuck::cast_slice(&shared.transmittance),
            ),
        }
    }
}

/// A read-only storage buffer holding `bytes`.
pub(super) fn storage(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// A filterable RGBA table texture (Rgba16Float: filterable on every
/// adapter, Rgba32Float is not) of `width × height` texels, row-major.
pub(super) fn table(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    (width, height): (usize, usize),
    data: &[[f32; 4]],
) -> wgpu::TextureView {
    let halves: Vec<u16> = data.iter().flat_map(|v| v.map(f32_to_half)).collect();
    sampled_texture(
        device,
        queue,
        label,
        (width as u32, height as u32, 1),
        wgpu::TextureFormat::Rgba16Float,
        bytemuck::cast_slice(&halves),
    )
}
