//! The profile's GPU resources (sample patterns, kernels, tables), uploaded
//! once per distinct [`ProfileInputs`] and reused by every later frame.

use super::gpu_types::GpuTap;
use super::inputs::{gaussian_taps, ProfileInputs};
use super::readback::f32_to_half;
use wgpu::util::DeviceExt;

pub(super) struct ProfileGpu {
    /// Fingerprint of the inputs these buffers hold.
    pub key: u64,
    /// Penner's D(θ, κ) table, filterable.
    pub preintegrated_lut: wgpu::TextureView,
    /// Penner's scattered-shadow table, filterable.
    pub penumbra_lut: wgpu::TextureView,
    pub transmittance: wgpu::Buffer,
    /// Burley's main pattern followed by the LOD's short one.
    pub burley_samples: wgpu::Buffer,
    /// r·R_N(r) per channel (Burley's weights).
    pub profile_lut: wgpu::Buffer,
    pub separable_taps: wgpu::Buffer,
    /// One 13-tap buffer and RGB weight per Gaussian of `gaussians`.
    pub gaussians: Vec<(wgpu::Buffer, [f32; 3], f32)>,
    /// `separable`'s depth weight σ (mm), 0 for the Jimenez 2012 lerp.
    pub separable_depth_sigma_mm: f32,
    pub burley_count: u32,
    pub low_count: u32,
    pub tap_count: u32,
    pub gaussian_tap_count: u32,
    /// The widest channel's 0.997-energy radius (mm): the LOD's disk size.
    pub filter_radius_mm: f32,
    /// [`super::BurleySampling::shader_flags`].
    pub burley_flags: u32,
}

impl ProfileGpu {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &ProfileInputs) -> Self {
        let storage = |label, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let table = |label, (width, height): (usize, usize), data: &[[f32; 4]]| {
            device
                .create_texture_with_data(
                    queue,
                    &wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d {
                            width: width as u32,
                            height: height as u32,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        // Filterable on every adapter (Rgba32Float is not).
                        format: wgpu::TextureFormat::Rgba16Float,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    bytemuck::cast_slice(
                        &data
                            .iter()
                            .flat_map(|v| v.map(f32_to_half))
                            .collect::<Vec<u16>>(),
                    ),
                )
                .create_view(&Default::default())
        };
        let mut burley = inputs.samples.clone();
        burley.extend_from_slice(&inputs.low_samples);
        Self {
            key: inputs.fingerprint(),
            preintegrated_lut: table(
                "pre-integrated lut",
                (inputs.lut_layout.width, inputs.lut_layout.height),
                &inputs.preintegrated_lut,
            ),
            penumbra_lut: table(
                "penumbra lut",
                (inputs.penumbra_layout.width, inputs.penumbra_layout.height),
                &inputs.penumbra_lut,
            ),
            transmittance: storage("transmittance", bytemuck::cast_slice(&inputs.transmittance)),
            burley_samples: storage("burley samples", bytemuck::cast_slice(&burley)),
            profile_lut: storage("profile lut", bytemuck::cast_slice(&inputs.lut)),
            separable_taps: storage("separable taps", bytemuck::cast_slice(&inputs.taps)),
            gaussians: inputs
                .gaussians
                .iter()
                .map(|(sigma, weight)| {
                    let taps: Vec<GpuTap> = gaussian_taps(*sigma, inputs.gaussian_taps);
                    (
                        storage("gaussian taps", bytemuck::cast_slice(&taps)),
                        *weight,
                        *sigma,
                    )
                })
                .collect(),
            burley_count: inputs.samples.len() as u32,
            low_count: inputs.low_samples.len() as u32,
            tap_count: inputs.taps.len() as u32,
            gaussian_tap_count: gaussian_taps(1.0, inputs.gaussian_taps).len() as u32,
            filter_radius_mm: inputs.filter_radius_mm,
            separable_depth_sigma_mm: inputs.separable_depth_sigma_mm,
            burley_flags: inputs.burley_sampling.shader_flags(),
        }
    }
}
