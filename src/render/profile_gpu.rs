//! The profile's GPU resources, uploaded once per distinct
//! [`ProfileInputs`] and reused by every later frame. Each method's file
//! under `sss/` uploads and owns its share (`burley::Buffers`,
//! `separable::Buffers`, `gaussians::Buffers`, `preintegrated::Tables`);
//! the scene pass reads the transmittance table and Penner's tables.

use super::inputs::ProfileInputs;
use super::readback::f32_to_half;
use super::sss;
use super::textures::sampled_texture;
use wgpu::util::DeviceExt;

pub(super) struct ProfileGpu {
    /// Fingerprint of the inputs these buffers hold.
    pub key: u64,
    /// The thin-slab transmittance T(d)/total (the scene pass's).
    pub transmittance: wgpu::Buffer,
    /// Each method's buffers.
    pub methods: sss::Buffers,
}

impl ProfileGpu {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &ProfileInputs) -> Self {
        Self {
            key: inputs.fingerprint(),
            transmittance: storage(
                device,
                "transmittance",
                bytemuck::cast_slice(&inputs.transmittance),
            ),
            methods: sss::Buffers::new(device, queue, &inputs.methods),
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
