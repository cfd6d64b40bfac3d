//! The shadow pass: the mesh's depth from the light, into a 2048² map the
//! scene pass filters (PCF) and reads raw (thickness), and the ground truth
//! reads back. Skipped while the light and the level of detail hold.

use super::super::frame::{buf, FrameEncoder};
use super::super::gpu_types::SceneUniforms;
use super::super::pipelines::{shadow_pipeline, uniform_entry};
use super::{depth_attachment, MeshLod};

/// The shadow map's size (texels per side). 2048: on the scan (bounding
/// radius 0.3 m, a texel of 0.3 mm, PCF over 1.2 mm, depth bias 1.2 mm)
/// closed lids and lips get 4.6 % of the lit level more light than Cycles'
/// ray-traced sun gives them, against 10.3 % at 1024² (2.4 % at 4096², for
/// 2.6× the shadow pass's time on lavapipe); tools/cycles_heads.sh,
/// docs/accuracy.md (issue 53, item 3).
pub(in crate::render) const SHADOW_SIZE: u32 = 2048;

pub(in crate::render) struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    /// The map's texture (read back by `reference`).
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    /// Comparison sampler (PCF).
    pub sampler: wgpu::Sampler,
    /// The light transform and level of detail the map was last drawn
    /// with: the map depends only on them, so an unchanged light skips the
    /// pass.
    key: Option<([[f32; 4]; 4], usize)>,
}

impl ShadowPass {
    /// Built from the scene module's `vs_shadow`, reading the scene's
    /// uniforms (the light's clip transform).
    pub fn new(
        device: &wgpu::Device,
        scene_module: &wgpu::ShaderModule,
        scene_uniforms: &wgpu::Buffer,
    ) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow"),
            entries: &[uniform_entry::<SceneUniforms>(
                0,
                wgpu::ShaderStages::VERTEX_FRAGMENT,
            )],
        });
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: SHADOW_SIZE,
                height: SHADOW_SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Depth32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        Self {
            pipeline: shadow_pipeline(device, scene_module, &layout),
            bind_group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shadow"),
                layout: &layout,
                entries: &[buf(0, scene_uniforms)],
            }),
            view: texture.create_view(&Default::default()),
            texture,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow pcf"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            key: None,
        }
    }

    /// Forgets what the map holds (after a failed frame).
    pub fn invalidate(&mut self) {
        self.key = None;
    }

    /// Draws the map for `light_clip` at level of detail `lod_index`
    /// unless it already holds them (or `reuse`: the scene pass is reused).
    pub fn encode(
        &mut self,
        f: &mut FrameEncoder,
        lod: &MeshLod,
        light_clip: [[f32; 4]; 4],
        lod_index: usize,
        reuse: bool,
    ) {
        if reuse || self.key == Some((light_clip, lod_index)) {
            return;
        }
        let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow"),
            color_attachments: &[],
            depth_stencil_attachment: depth_attachment(&self.view, false),
            timestamp_writes: f
                .timer
                .render("shadow", (SHADOW_SIZE * SHADOW_SIZE) as u64, 0),
            ..Default::default()
        });
        lod.draw(&mut pass, &self.pipeline, &self.bind_group);
        // Set as recorded: a frame that fails afterwards must call
        // `invalidate` (`Renderer::render_inner` does).
        self.key = Some((light_clip, lod_index));
    }
}
