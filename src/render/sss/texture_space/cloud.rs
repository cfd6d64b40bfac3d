//! `texture-space --neighbours 3d`: the gather by 3D neighbourhood. The
//! irradiance atlas's texels are the point cloud of Jensen & Buhler 2002
//! (§3: each a surface element with its point, area and light), the
//! atlas's quadtree their hierarchy (`shaders/texture_space_tree.wgsl`
//! builds it in one compute pass a frame), and each SSS pixel sums the
//! profile over it by true 3D distance (`shaders/texture_space_cloud.wgsl`
//! states the estimator), so the skin near in 3D but far in UV (closed lids
//! and lips, the far side of the ear: issue 53's diagnosis) is gathered
//! as the ground truth integrates it. The UV layout's seams do not matter
//! to it. Within the near field the pixel's own sheet is read on screen,
//! as `texture-space` reads it.

use crate::render::context::GpuError;
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::gpu_types::{CloudNode, CloudUniforms, TreeLevel};
use crate::render::mesh::Mesh;
use crate::render::pipelines::{buffer_entry, texture_entry, uniform_entry};
use crate::render::sss::SssFrame;

/// θ: a node counts whole where its bounding radius is at most θ times its
/// centroid's distance from the pixel (Jensen & Buhler 2002's solid-angle
/// criterion, as a ratio of lengths). 0.5 was the first value measured; the
/// bench tool `texture_space_on_the_scan` measures others.
pub const DEFAULT_THETA: f32 = 0.3;

/// The smallest near field (mm) the gather by 3D neighbourhood takes: the
/// texel under the pixel would otherwise weigh R(≈0), and the atlas's
/// texels (0.5–1 mm on the heads) are too coarse for the green and blue
/// cores.
pub const MIN_NEAR_MM: f32 = 1.0;

/// The tree of an `size × size` atlas: levels 1 (size/2 a side) to the
/// root, one after another in one storage buffer.
pub(super) struct Tree {
    size: u32,
    nodes: wgpu::Buffer,
    /// Level l's offset in nodes (l ≥ 1; 0 unused).
    offsets: [u32; 16],
    /// The root's level: log₂ size.
    top: u32,
    /// [`texel_area_cap_mm2`] for the mesh last drawn, by its key.
    cap: (u64, f32),
    /// The 4× atlas of each texel's surface and light, and its resolve
    /// (`fs_atlas_coverage`).
    coverage_msaa: wgpu::TextureView,
    coverage: wgpu::TextureView,
}


impl Tree {
    /// The tree's buffer for an atlas of `size` texels a side (a power of
    /// two), or why this device cannot bind it.
    pub fn new(device: &wgpu::Device, size: u32) -> Result<Self, GpuError> {
        if !size.is_power_of_two() {
            return Err(GpuError::Readback(format!(
                "texture-space --neighbours 3d: the tree halves a power of two, not {size}"
            )));
        }
        let top = size.trailing_zeros();
        let mut offsets = [0u32; 16];
        let mut count = 0u64;
        for l in 1..=top {
            offsets[l as usize] = count as u32;
            count += u64::from(size >> l).pow(2);
        }
        let bytes = count * std::mem::size_of::<CloudNode>() as u64;
        let limit = device
            .limits()
            .max_storage_buffer_binding_size
            .min(device.limits().max_buffer_size);
        if bytes > limit {
            return Err(GpuError::AtlasTreeTooLarge {
                size,
                half: size / 2,
                bytes,
                limit,
            });
        }
        let nodes = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("texture-space tree"),
            size: bytes.max(48),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let texture = |label, samples| super::passes::atlas_texture(device, label, size, samples);
        Ok(Self {
            size,
            nodes,
            offsets,
            top,
            cap: (0, f32::MAX),
            coverage_msaa: texture("texture-space coverage (4×)", super::passes::COVERAGE_SAMPLES),
            coverage: texture("texture-space coverage", 1),
        })
    }

    pub fn size(&self) -> u32 {
        self.size
    }

    /// Takes `mesh`'s [`texel_area_cap_mm2`] (kept while the mesh is the
    /// same).
    pub fn set_mesh(&mut self, mesh: &Mesh) {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        super::rays::mesh_key(mesh).hash(&mut h);
        mesh.metres_per_unit.to_bits().hash(&mut h);
        let key = h.finish();
        if self.cap.0 != key {
            self.cap = (key, texel_area_cap_mm2(mesh, self.size));
        }
    }

    /// The gather's uniforms for this tree.
    pub fn uniforms(&self, theta: f32, near_mm: f32) -> CloudUniforms {
        let o = &self.offsets;
        CloudUniforms {
            offsets: [
                [o[0], o[1], o[2], o[3]],
                [o[4], o[5], o[6], o[7]],
                [o[8], o[9], o[10], o[11]],
                [o[12], o[13], o[14], o[15]],
            ],
            top: self.top,
            theta,
            near_mm: near_mm.max(MIN_NEAR_MM),
            max_area_mm2: self.cap.1,
        }
    }

    /// Draws the 4× coverage atlas and resolves it.
    pub fn draw_coverage(&self, f: &mut FrameEncoder, io: &SssFrame, pipeline: &wgpu::RenderPipeline) {
        let label = "sss texture-space coverage";
        let colour = [Some(wgpu::RenderPassColorAttachment {
            view: &self.coverage_msaa,
            resolve_target: Some(&self.coverage),
            depth_slice: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Discard,
            },
        })];
        let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &colour,
            depth_stencil_attachment: None,
            timestamp_writes: f.timer.render(label, u64::from(self.size).pow(2), 0),
            ..Default::default()
        });
        io.drawn.draw_with(&mut pass, pipeline, &[io.scene_bind]);
    }

    /// Builds the tree from the atlas's three textures, level by level,
    /// in one compute pass.
    pub fn build(
        &self,
        f: &mut FrameEncoder,
        pipelines: &Pipelines,
        atlas: [&wgpu::TextureView; 3],
    ) {
        let device = f.device;
        let groups: Vec<wgpu::BindGroup> = (1..=self.top)
            .map(|l| {
                let level = TreeLevel {
                    side: self.size >> l,
                    level: l,
                    below: self.offsets[(l - 1) as usize],
                    at: self.offsets[l as usize],
                    max_area_mm2: self.cap.1,
                    pad0: 0.0,
                    pad1: 0.0,
                    pad2: 0.0,
                };
                let u = f.uniform("texture-space tree level", bytemuck::bytes_of(&level));
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("texture-space tree level"),
                    layout: &pipelines.tree_layout,
                    entries: &[
                        buf(0, &u),
                        buf(1, &self.nodes),
                        tex(2, atlas[0]),
                        tex(3, atlas[1]),
                        tex(4, atlas[2]),
                        tex(5, &self.coverage),
                    ],
                })
            })
            .collect();
        let label = "sss texture-space tree";
        let nodes = u64::from(self.offsets[self.top as usize]) + 1;
        let mut pass = f.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: f.timer.compute(label, nodes, 0),
        });
        pass.set_pipeline(&pipelines.tree);
        for (l, group) in (1..=self.top).zip(&groups) {
            let side = self.size >> l;
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(side.div_ceil(8), side.div_ceil(8), 1);
        }
    }

    /// The gather's group 2: the nodes and its uniforms.
    pub fn bind_group(
        &self,
        f: &FrameEncoder,
        layout: &wgpu::BindGroupLayout,
        uniforms: &CloudUniforms,
    ) -> wgpu::BindGroup {
        let u = f.uniform("texture-space cloud", bytemuck::bytes_of(uniforms));
        f.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("texture-space cloud"),
            layout,
            entries: &[buf(0, &self.nodes), buf(1, &u), tex(2, &self.coverage)],
        })
    }
}

/// The tree's build (a compute pipeline of its own module) and the
/// gather's group-2 layout.
pub(super) struct Pipelines {
    tree: wgpu::ComputePipeline,
    tree_layout: wgpu::BindGroupLayout,
    pub gather_layout: wgpu::BindGroupLayout,
}

impl Pipelines {
    pub fn new(device: &wgpu::Device, tree_module: &wgpu::ShaderModule) -> Self {
        let compute = wgpu::ShaderStages::COMPUTE;
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: compute,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let tree_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("texture-space tree"),
            entries: &[
                uniform_entry::<TreeLevel>(0, compute),
                buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: false }, compute),
                texture(2),
                texture(3),
                texture(4),
                texture(5),
            ],
        });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("texture-space tree"),
            bind_group_layouts: &[Some(&tree_layout)],
            ..Default::default()
        });
        let tree = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("texture-space tree"),
            layout: Some(&pl),
            module: tree_module,
            entry_point: Some("cs_tree"),
            compilation_options: Default::default(),
            cache: None,
        });
        let frag = wgpu::ShaderStages::FRAGMENT;
        let gather_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("texture-space cloud"),
            entries: &[
                buffer_entry(0, wgpu::BufferBindingType::Storage { read_only: true }, frag),
                uniform_entry::<CloudUniforms>(1, frag),
                texture_entry(2),
            ],
        });
        Self {
            tree,
            tree_layout,
            gather_layout,
        }
    }
}

/// How many times the typical texel's surface one texel may stand for.
const AREA_CAP: f32 = 64.0;

/// The most surface (mm²) one texel of a `size²` atlas may stand for on
/// `mesh`: [`AREA_CAP`] times the median over its skin's UV area of the
/// surface per texel (each triangle's mm² of surface per unit² of UV over
/// size²). A texel is given its triangle's stretch times its own UV area,
/// exact where the triangle covers it; a sliver triangle, thin in UV, that
/// happens to cover one texel's centre would lend that texel far more
/// surface than the sliver has.
pub(super) fn texel_area_cap_mm2(mesh: &Mesh, size: u32) -> f32 {
    let mm = 1000.0 * mesh.metres_per_unit;
    let mut stretch: Vec<(f32, f32)> = mesh
        .indices
        .chunks_exact(3)
        .filter_map(|t| {
            let v = [0, 1, 2].map(|k| mesh.vertices.get(t[k] as usize));
            let [Some(a), Some(b), Some(c)] = v else {
                return None;
            };
            if [a, b, c].iter().all(|v| v.material >= 0.5) {
                return None;
            }
            let p = |v: &crate::render::gpu_types::Vertex| glam::Vec3::from(v.position) * mm;
            let q = |v: &crate::render::gpu_types::Vertex| glam::Vec2::from(v.uv);
            let surface = 0.5 * (p(b) - p(a)).cross(p(c) - p(a)).length();
            let uv = 0.5 * (q(b) - q(a)).perp_dot(q(c) - q(a)).abs();
            (uv > 0.0 && surface.is_finite()).then_some((surface / uv, uv))
        })
        .collect();
    if stretch.is_empty() {
        return f32::MAX;
    }
    stretch.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = 0.5 * stretch.iter().map(|s| s.1).sum::<f32>();
    let mut seen = 0.0;
    let median = stretch
        .iter()
        .find(|s| {
            seen += s.1;
            seen >= half
        })
        .map_or(stretch[stretch.len() - 1].0, |s| s.0);
    AREA_CAP * median / (size as f32 * size as f32)
}
