//! `texture-space`'s passes that draw the mesh: the atlas (the mesh at
//! its UVs) and the gathers at the SSS pixels (through the UV layout, by
//! probe rays, or by 3D neighbourhood), and the atlas's textures.

use super::{rays, Pipelines};
use crate::render::frame::{color_attachment, color_attachment_clearing, FrameEncoder};
use crate::render::gpu_types::{SssUniforms, TextureSpaceUniforms, Vertex};
use crate::render::pipelines::{buffer_entry, texture_entry, uniform_entry, DEPTH_STENCIL, HDR};
use crate::render::sss::{SssFrame, SssPipelines};

/// The two passes that draw the mesh.
pub(super) struct MeshPasses {
    pub(super) atlas: wgpu::RenderPipeline,
    pub(super) gather: wgpu::RenderPipeline,
    pub(super) gather_layout: wgpu::BindGroupLayout,
    /// The probe-ray gather and its group 2, on a device with ray queries.
    pub(super) rays: Option<(wgpu::RenderPipeline, wgpu::BindGroupLayout)>,
    /// The gather by 3D neighbourhood and its atlas (without the scene
    /// pass's transmission), built the first time a frame asks for them.
    pub(super) cloud: Option<CloudPasses>,
}

/// The gather by 3D neighbourhood's passes that draw the mesh.
pub(super) struct CloudPasses {
    pub(super) gather: wgpu::RenderPipeline,
    /// The atlas without the scene pass's transmission term.
    pub(super) atlas: wgpu::RenderPipeline,
    /// The 4× atlas of each texel's surface and light (`fs_atlas_coverage`).
    pub(super) coverage: wgpu::RenderPipeline,
}


/// The atlas's textures.
pub(super) struct Atlas {
    pub(super) size: u32,
    pub(super) irradiance: wgpu::TextureView,
    /// The position (mm) in half floats, and what they left out: GL
    /// cannot render to 32-bit floats.
    pub(super) position: wgpu::TextureView,
    pub(super) position_lo: wgpu::TextureView,
}

impl Atlas {
    pub(super) fn new(device: &wgpu::Device, size: u32) -> Self {
        let make = |label| atlas_texture(device, label, size, 1);
        Self {
            size,
            irradiance: make("texture-space irradiance"),
            position: make("texture-space position"),
            position_lo: make("texture-space position residual"),
        }
    }
}

impl Atlas {
    /// Its three textures, as the tree's build reads them.
    pub(super) fn views(&self) -> [&wgpu::TextureView; 3] {
        [&self.irradiance, &self.position, &self.position_lo]
    }

    /// Draws every triangle at its UVs into it (`fs_atlas`).
    pub(super) fn draw(&self, f: &mut FrameEncoder, io: &SssFrame, pipeline: &wgpu::RenderPipeline) {
        let label = "sss texture-space irradiance";
        let background = wgpu::Color {
            r: 0.0,
            g: 0.0,
            b: 0.0,
            a: crate::render::gpu_types::DIFFUSE_ALPHA_BACKGROUND as f64,
        };
        let colour = [
            Some(color_attachment_clearing(&self.irradiance, Some(background))),
            Some(color_attachment(&self.position, false)),
            Some(color_attachment(&self.position_lo, false)),
        ];
        let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &colour,
            depth_stencil_attachment: None,
            timestamp_writes: f.timer.render(label, (self.size as u64).pow(2), 0),
            ..Default::default()
        });
        io.drawn.draw_with(&mut pass, pipeline, &[io.scene_bind]);
    }
}

impl MeshPasses {
    /// The gather by 3D neighbourhood's pipeline (groups: the scene's, the
    /// gather's, the tree's), built the first time a frame asks for it.
    pub(super) fn build_cloud(
        &mut self,
        device: &wgpu::Device,
        p: &Pipelines,
        (scene_layout, tree_layout): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    ) {
        if self.cloud.is_some() {
            return;
        }
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("texture-space cloud"),
            bind_group_layouts: &[
                Some(scene_layout),
                Some(&self.gather_layout),
                Some(tree_layout),
            ],
            ..Default::default()
        });
        let vertices = [Some(vertex_layout())];
        let gather = gather_pipeline(device, (&p.cloud, "fs_gather_cloud"), &pl, &vertices);
        let atlas_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("texture-space atlas"),
            bind_group_layouts: &[Some(scene_layout)],
            ..Default::default()
        });
        let atlas = atlas_pipeline(device, (&p.cloud, "fs_atlas_untransmitted"), &atlas_layout);
        let coverage = atlas_pipeline_into(
            device,
            (&p.cloud, "fs_atlas_coverage"),
            &atlas_layout,
            (1, COVERAGE_SAMPLES),
        );
        self.cloud = Some(CloudPasses {
            gather,
            atlas,
            coverage,
        });
    }

    pub(super) fn new(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        scene_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let frag = wgpu::ShaderStages::FRAGMENT;
        let storage = wgpu::BufferBindingType::Storage { read_only: true };
        let gather_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("texture-space gather"),
            entries: &[
                uniform_entry::<SssUniforms>(0, frag),
                texture_entry(1),
                texture_entry(2),
                texture_entry(3),
                texture_entry(4),
                buffer_entry(5, storage, frag),
                buffer_entry(6, storage, frag),
                texture_entry(7),
                uniform_entry::<TextureSpaceUniforms>(8, frag),
            ],
        });
        let layout = |label, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                ..Default::default()
            })
        };
        let atlas_layout = layout("texture-space atlas", &[Some(scene_layout)]);
        let atlas = atlas_pipeline(device, (module, "fs_atlas"), &atlas_layout);
        let vertices = [Some(vertex_layout())];
        let gather_pl = layout(
            "texture-space gather",
            &[Some(scene_layout), Some(&gather_layout)],
        );
        let gather = gather_pipeline(device, (module, "fs_gather"), &gather_pl, &vertices);
        Self {
            atlas,
            gather,
            gather_layout,
            rays: None,
            cloud: None,
        }
    }

    /// Itself, with the probe rays' pipeline built where this frame casts
    /// them (`on`: [`probe_rays`] required ray queries, so their module
    /// exists).
    pub(super) fn with_rays(&mut self, on: bool, p: &SssPipelines, io: &SssFrame) -> &Self {
        if let (true, Some(module)) = (on, p.texture_space.rays.as_ref()) {
            self.build_rays(&io.ctx.device, module, io.scene_layout);
        }
        self
    }

    /// The probe-ray gather's pipeline and its group 2, built the first
    /// time a frame asks for probe rays (a backend compile that frames
    /// without them never pay).
    fn build_rays(
        &mut self,
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        scene_layout: &wgpu::BindGroupLayout,
    ) {
        if self.rays.is_some() {
            return;
        }
        let gather_layout = &self.gather_layout;
        self.rays = Some({
            let rays_layout = rays::layout(device);
            let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("texture-space probe rays"),
                bind_group_layouts: &[Some(scene_layout), Some(gather_layout), Some(&rays_layout)],
                ..Default::default()
            });
            let vertices = [Some(vertex_layout())];
            let pipeline = gather_pipeline(device, (module, "fs_gather_rays"), &pl, &vertices);
            (pipeline, rays_layout)
        });
    }
}

/// The samples a texel of the coverage atlas takes (`fs_atlas_coverage`).
pub(super) const COVERAGE_SAMPLES: u32 = 4;

/// One `size²` HDR target of the atlas with `samples` samples a texel.
pub(super) fn atlas_texture(
    device: &wgpu::Device,
    label: &'static str,
    size: u32,
    samples: u32,
) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: HDR,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// The atlas pass's pipeline: the mesh at its UVs, into the three atlas
/// targets, with `fragment` (`fs_atlas`, or `fs_atlas_untransmitted` for
/// the gather by 3D neighbourhood).
fn atlas_pipeline(
    device: &wgpu::Device,
    (module, fragment): (&wgpu::ShaderModule, &'static str),
    layout: &wgpu::PipelineLayout,
) -> wgpu::RenderPipeline {
    atlas_pipeline_into(device, (module, fragment), layout, (3, 1))
}

/// [`atlas_pipeline`] into `targets` HDR targets of `samples` samples.
fn atlas_pipeline_into(
    device: &wgpu::Device,
    (module, fragment): (&wgpu::ShaderModule, &'static str),
    layout: &wgpu::PipelineLayout,
    (targets, samples): (usize, u32),
) -> wgpu::RenderPipeline {
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("texture-space atlas"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_atlas"),
            compilation_options: Default::default(),
            buffers: &[Some(vertex_layout())],
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment),
            compilation_options: Default::default(),
            targets: &[target(HDR), target(HDR), target(HDR)][..targets],
        }),
        // UV islands are wound either way: nothing is culled, and no
        // depth (islands do not overlap).
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: None,
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        multiview_mask: None,
        cache: None,
    })
}

/// The mesh's vertex buffer as the scene pass reads it ([`Vertex`]).
fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRIBUTES: [wgpu::VertexAttribute; 7] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32, 4 => Float32, 5 => Float32, 6 => Float32x4];
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &ATTRIBUTES,
    }
}

/// The gather pass's pipeline: the scene's vertex shader and culling, and
/// only where the scene pass kept its fragment (depth Equal) on SSS pixels
/// (stencil 1).
fn gather_pipeline(
    device: &wgpu::Device,
    (module, fragment): (&wgpu::ShaderModule, &'static str),
    layout: &wgpu::PipelineLayout,
    vertices: &[Option<wgpu::VertexBufferLayout>],
) -> wgpu::RenderPipeline {
    let sss_pixels = wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Equal,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: wgpu::StencilOperation::Keep,
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("texture-space gather"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: vertices,
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: HDR,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        // The scene pass's culling, and its depth: only the fragment
        // the scene pass kept passes Equal (same vertex shader, same
        // mesh, same uniforms); and only on SSS pixels (stencil 1, as
        // the screen-space passes).
        primitive: wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_STENCIL,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Equal),
            stencil: wgpu::StencilState {
                front: sss_pixels,
                back: sss_pixels,
                read_mask: 0xff,
                write_mask: 0,
            },
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

