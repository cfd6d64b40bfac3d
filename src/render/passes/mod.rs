//! The frame's fixed passes, one file each, in the order they run:
//! `shadow` (the light's depth map), `scene` (G-buffer: diffuse irradiance
//! and SSS mask, specular, albedo, linear depth, stencil), `classify`
//! (counts the SSS pixels and marks them in the stencil) and `composite`
//! (a method's result, or its running mean, with specular and albedo,
//! tonemapped). The SSS methods' passes sit between classify and
//! composite, under `sss/`. Each pass is a small struct: `new` builds its
//! pipeline once, `encode` records it into a [`super::frame::FrameEncoder`]
//! (`ClassifyPass::count` also reads its count back;
//! `CompositePass::accumulate` records the running mean).

pub(super) mod classify;
pub(super) mod composite;
pub(super) mod scene;
pub(super) mod shadow;

use super::framing::Framing;
use super::mesh::Mesh;
use super::settings::RenderSettings;
use wgpu::util::DeviceExt;

/// One level of detail on the GPU.
pub(super) struct MeshLod {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    pub index_count: u32,
    /// Mean edge length (mesh units).
    mean_edge: f32,
}

impl MeshLod {
    pub fn new(device: &wgpu::Device, mesh: &Mesh) -> Self {
        Self {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("vertices"),
                contents: bytemuck::cast_slice(&mesh.vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("indices"),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            index_count: mesh.indices.len() as u32,
            mean_edge: mesh.mean_edge(),
        }
    }

    /// Draws the mesh with `pipeline` and `groups` (groups 0, 1, …).
    pub fn draw_with(
        &self,
        pass: &mut wgpu::RenderPass,
        pipeline: &wgpu::RenderPipeline,
        groups: &[&wgpu::BindGroup],
    ) {
        pass.set_pipeline(pipeline);
        for (i, g) in groups.iter().enumerate() {
            pass.set_bind_group(i as u32, *g, &[]);
        }
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }

    /// Draws the mesh with `pipeline` and `bind_group` (group 0).
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass,
        pipeline: &wgpu::RenderPipeline,
        bind_group: &wgpu::BindGroup,
    ) {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}

/// Draw the coarse level of detail while its mean edge is at most this
/// many pixels: at that size the subdivided triangles (a quarter the area)
/// cost lavapipe ~25 ms more scene pass at 640×360 (measured) for
/// silhouettes no one can see; closer shots get the smooth mesh.
const LOD_EDGE_PX: f32 = 10.0;

/// The coarsest level of detail (of `lods`, finest first) whose mean edge
/// spans at most [`LOD_EDGE_PX`] pixels at the mesh's distance, else the
/// finest.
pub(super) fn pick_lod(lods: &[MeshLod], framing: &Framing, s: &RenderSettings) -> usize {
    let px_per_unit = framing.pixels_per_unit(s);
    (0..lods.len())
        .rev()
        .find(|&k| k == 0 || lods[k].mean_edge * px_per_unit <= LOD_EDGE_PX)
        .unwrap_or(0)
}

/// A depth attachment cleared to 1 (and its stencil to 0 with `stencil`).
fn depth_attachment(
    view: &wgpu::TextureView,
    stencil: bool,
) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: stencil.then_some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(0),
            store: wgpu::StoreOp::Store,
        }),
    })
}

/// Four zeroed u32 GPU counters and the buffer they are read back through.
pub(super) fn counter_buffers(
    device: &wgpu::Device,
    label: &'static str,
) -> (wgpu::Buffer, wgpu::Buffer) {
    let counters = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(&[0u32; 4]),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: 16,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    (counters, read)
}
