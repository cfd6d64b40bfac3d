//! The frame's offscreen targets, made for one size and kept while it
//! holds: the scene's G-buffer, the SSS ping/pong, the output and, on
//! first use, progressive refinement's running means.

use super::context::GpuContext;
use super::pipelines::{ALBEDO, DEPTH_STENCIL, HDR, OUTPUT};

/// The HDR targets a method reads from and writes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum HdrTarget {
    /// The scene's diffuse irradiance and SSS mask.
    Diffuse,
    Ping,
    /// `separable`'s second pass; the sum of the Gaussians for `gaussians`.
    Pong,
}

pub(super) struct Targets {
    pub size: (u32, u32),
    /// Diffuse, ping, pong (indexed by [`HdrTarget`]).
    hdr: [(wgpu::Texture, wgpu::TextureView); 3],
    pub specular: wgpu::TextureView,
    pub specular_texture: wgpu::Texture,
    /// albedo^post and coverage.
    pub albedo: wgpu::TextureView,
    pub albedo_texture: wgpu::Texture,
    pub linear_depth: wgpu::TextureView,
    pub linear_depth_texture: wgpu::Texture,
    /// Depth buffer; its stencil marks the SSS pixels.
    pub depth_stencil: wgpu::TextureView,
    pub output: wgpu::Texture,
    /// Progressive refinement's running means (A and B), made on first use.
    pub accum: [Option<(wgpu::Texture, wgpu::TextureView)>; 2],
    /// Bytes of GPU memory these targets take.
    pub bytes: u64,
}

impl Targets {
    pub fn new(ctx: &GpuContext, (w, h): (u32, u32)) -> Self {
        let device = &ctx.device;
        let make = |label, format, usage| target_texture(device, label, (w, h), format, usage);
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let mut bytes = 0u64;
        let mut make = |label, format: wgpu::TextureFormat, usage| {
            // Depth24PlusStencil8 has no copy size; count 4 bytes.
            bytes += format.block_copy_size(None).unwrap_or(4) as u64 * w as u64 * h as u64;
            make(label, format, usage)
        };
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let mut hdr = |label| {
            // Copied out for readback and the reference; written by it.
            let t = make(
                label,
                HDR,
                rt | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
            );
            let v = view(&t);
            (t, v)
        };
        let hdr = [hdr("diffuse"), hdr("sss ping"), hdr("sss pong")];
        // Copied out for `render --out FILE.exr`'s layers.
        let rt_copy = rt | wgpu::TextureUsages::COPY_SRC;
        let specular_texture = make("specular", ctx.specular_format, rt_copy);
        let specular = view(&specular_texture);
        let albedo_texture = make("albedo", ALBEDO, rt_copy);
        let albedo = view(&albedo_texture);
        let linear_depth_texture = make(
            "linear depth",
            ctx.linear_depth_format,
            rt | wgpu::TextureUsages::COPY_SRC,
        );
        let linear_depth = view(&linear_depth_texture);
        let depth_stencil = view(&make(
            "depth stencil",
            DEPTH_STENCIL,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        ));
        let output = make(
            "output",
            OUTPUT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        Self {
            size: (w, h),
            hdr,
            specular,
            specular_texture,
            albedo,
            albedo_texture,
            linear_depth,
            linear_depth_texture,
            depth_stencil,
            output,
            accum: [None, None],
            bytes,
        }
    }

    pub fn view(&self, t: HdrTarget) -> &wgpu::TextureView {
        &self.hdr[t as usize].1
    }

    pub fn texture(&self, t: HdrTarget) -> &wgpu::Texture {
        &self.hdr[t as usize].0
    }

    /// The running-mean target `slot` of progressive refinement, made on
    /// first use (a frame rendered alone never allocates it).
    pub fn ensure_accumulator(&mut self, device: &wgpu::Device, slot: usize) {
        if self.accum[slot].is_some() {
            return;
        }
        let texture = target_texture(
            device,
            "progressive mean",
            self.size,
            HDR,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let (w, h) = self.size;
        self.bytes += HDR.block_copy_size(None).unwrap_or(8) as u64 * w as u64 * h as u64;
        let view = texture.create_view(&Default::default());
        self.accum[slot] = Some((texture, view));
    }
}

/// A 2D, single-sample, single-mip render target of `size`.
pub(super) fn target_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}
