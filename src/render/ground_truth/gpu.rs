//! The gather on the GPU: `shaders/ground_truth.wgsl` walks the same
//! clusters, quadtrees and profile table as [`Cloud::gather`] (flattened
//! here into storage buffers), one compute invocation per point, by the
//! same rules and constants. The points themselves (each probe moved onto
//! the surface, with its pixel's steps there, and the k × k points of a
//! supersampled pixel) come from the CPU's [`Cloud::gather_points`], so
//! both paths gather at the same points.
//!
//! The irradiance the walk evaluates afresh (pieces below the cells, and
//! those read over a pixel's footprint) comes from a WGSL module the
//! caller prefixes, which defines `surface_irradiance`: the tests give it
//! the functions their CPU twins compute (`gpu_gather_is_the_cpu_gather`).
//!
//! Held to the CPU path, not to itself: the CPU walks in f64 and this in
//! f32, so the two agree to rounding, and the tests say how far.

use super::table::ProfileTable;
use super::{Cloud, GatherPoint};
use crate::render::gpu_types::GatherParams;
use crate::render::{GpuContext, GpuError};
use wgpu::util::DeviceExt;

/// Points a dispatch gathers at most (one submission each, so that no
/// single submission runs long enough for a driver's watchdog).
const POINTS_PER_DISPATCH: usize = 8192;

/// A cloud's clusters, cells and profile on the GPU, and the gather's
/// pipeline with its irradiance module.
pub struct GpuCloud {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: GatherParams,
    params_buffer: wgpu::Buffer,
    tree: wgpu::Buffer,
    node_e: wgpu::Buffer,
    table: wgpu::Buffer,
}

/// f32 bits, with infinities (the table's "no limit") as the largest
/// finite value: WGSL leaves arithmetic on infinities undefined.
fn finite_bits(v: f32) -> u32 {
    if v.is_infinite() {
        f32::MAX.copysign(v).to_bits()
    } else {
        v.to_bits()
    }
}

/// The table's entries as `TableEntry` (density and leaf side, CDF and
/// decay length, slope), 12 floats each.
fn table_entries(t: &ProfileTable) -> Vec<u32> {
    let mut out = Vec::with_capacity(12 * t.density.len());
    for i in 0..t.density.len() {
        let d = t.density[i];
        let c = t.cdf[i];
        let s = t.d1[i];
        out.extend(
            [
                d[0],
                d[1],
                d[2],
                t.leaf_mm[i],
                c[0],
                c[1],
                c[2],
                t.decay_mm[i],
                s[0],
                s[1],
                s[2],
                0.0,
            ]
            .map(finite_bits),
        );
    }
    out
}

/// The cells' tree as the shader reads it, in 32-bit words: the clusters
/// (5 vec4s each), the roots (4 vec4s each) from vec4 `roots_at`, the leaf
/// order from vec4 `order_at`, padded to whole vec4s.
fn tree_words(cells: &super::Cells) -> (Vec<u32>, u32, u32) {
    // Clusters (5 vec4s), roots (4 vec4s), the leaf order (4 a vec4).
    let mut tree: Vec<u32> = Vec::with_capacity(
        20 * cells.clusters.len() + 16 * cells.roots.len() + cells.order.len() + 4,
    );
    for cl in &cells.clusters {
        let (leaf, a, b) = match cl.kind {
            super::cluster::ClusterKind::Inner(left) => (0u32, left, 0u32),
            super::cluster::ClusterKind::Leaf { first, count } => (1, first, count),
        };
        let f = |v: f32| v.to_bits();
        tree.extend([cl.centre.x, cl.centre.y, cl.centre.z, cl.radius].map(f));
        tree.extend(cl.power.map(f));
        tree.push(leaf);
        tree.extend(cl.dipole[0].to_array().map(f));
        tree.push(a);
        tree.extend(cl.dipole[1].to_array().map(f));
        tree.push(b);
        tree.extend(cl.dipole[2].to_array().map(f));
        tree.push(0);
    }
    let roots_at = (tree.len() / 4) as u32;
    for r in &cells.roots {
        for (k, extra) in [r.side_mm, r.reach_mm, r.area_mm2].into_iter().enumerate() {
            tree.extend(r.corners[k].to_array().map(f32::to_bits));
            tree.push(extra.to_bits());
        }
        tree.extend([r.tri, r.levels, r.offset, 0]);
    }
    let order_at = (tree.len() / 4) as u32;
    tree.extend(&cells.order);
    while !tree.len().is_multiple_of(4) || tree.is_empty() {
        tree.push(0);
    }
    (tree, roots_at, order_at)
}

/// The gather's parameters: the profile table's axis, the cloud's reach,
/// where the roots and the leaf order start, and Gauss–Legendre's nodes.
fn gather_params(cloud: &Cloud, roots_at: u32, order_at: u32) -> GatherParams {
    let t = cloud.table();
    let cells = &**cloud.cells();
    let (nodes, weights) = crate::model::quad::gl8();
    GatherParams {
        ln_r0: t.ln_r0 as f32,
        inv_step: t.inv_step as f32,
        r0_mm: t.r0_mm as f32,
        r_max_mm: t.r_max_mm as f32,
        epsilon_mm: t.epsilon_mm as f32,
        reach_mm: cloud.reach_mm as f32,
        count: 0,
        first: 0,
        cdf_zero: [t.cdf_zero[0], t.cdf_zero[1], t.cdf_zero[2], 0.0],
        roots_at,
        order_at,
        clusters: cells.clusters.len() as u32,
        uneven: t.uneven,
        gl_nodes: std::array::from_fn(|r| std::array::from_fn(|c| nodes[4 * r + c] as f32)),
        gl_weights: std::array::from_fn(|r| std::array::from_fn(|c| weights[4 * r + c] as f32)),
    }
}

impl GpuCloud {
    /// Uploads `cloud` and builds the gather with `irradiance_wgsl`, the
    /// module that defines `surface_irradiance` (see the shader's head),
    /// whose bind groups 0.. have the layouts `groups` (the gather's own
    /// group is the next).
    pub fn new(
        ctx: &GpuContext,
        cloud: &Cloud,
        irradiance_wgsl: &str,
        groups: &[&wgpu::BindGroupLayout],
    ) -> Result<Self, GpuError> {
        let cells = &**cloud.cells();
        let limit = ctx.device.limits().max_storage_buffer_binding_size;
        let (tree, roots_at, order_at) = tree_words(cells);
        let node_e: Vec<f32> = if cells.node_e.is_empty() {
            vec![0.0; 4]
        } else {
            cells.node_e.iter().flatten().copied().collect()
        };
        for (what, bytes) in [
            ("the clusters and roots", 4 * tree.len() as u64),
            ("the cells' irradiance", 4 * node_e.len() as u64),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge { what, bytes, limit });
            }
        }
        let t = cloud.table();
        let params = gather_params(cloud, roots_at, order_at);
        let device = &ctx.device;
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let own = groups.len();
        let source = format!(
            "{irradiance_wgsl}\n{}",
            include_str!("../../../shaders/ground_truth.wgsl")
                .replace("@group(0)", &format!("@group({own})"))
        );
        let needed = 4 + irradiance_wgsl.matches("var<storage").count() as u32;
        let allowed = ctx.device.limits().max_storage_buffers_per_shader_stage;
        if needed > allowed {
            return Err(GpuError::Device(format!(
                "the GPU ground truth reads {needed} storage buffers in one shader and this device allows {allowed}: use the CPU ground truth"
            )));
        }
        ctx.checked("the ground truth's gather (compute)", || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("ground_truth.wgsl"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let compute = wgpu::ShaderStages::COMPUTE;
            let entry = |binding, read_only| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: compute,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            };
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ground truth gather"),
                entries: &[
                    wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: compute,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                    entry(1, true),
                    entry(2, true),
                    entry(3, true),
                    entry(4, false),
                ],
            });
            let mut layouts: Vec<&wgpu::BindGroupLayout> = groups.to_vec();
            layouts.push(&layout);
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ground truth gather"),
                bind_group_layouts: &layouts.iter().map(|l| Some(*l)).collect::<Vec<_>>(),
                ..Default::default()
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("ground truth gather"),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some("cs_gather"),
                compilation_options: Default::default(),
                cache: None,
            });
            Self {
                pipeline,
                layout,
                params,
                params_buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("ground truth params"),
                    size: std::mem::size_of::<GatherParams>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                tree: storage("ground truth tree", bytemuck::cast_slice(&tree)),
                node_e: storage("ground truth cells", bytemuck::cast_slice(&node_e)),
                table: storage(
                    "ground truth table",
                    bytemuck::cast_slice(&table_entries(t)),
                ),
            }
        })
    }

    /// The gather at each point: what [`Cloud::gather_at`] gives there,
    /// to f32 rounding. `None` for a point whose walk did not finish here:
    /// it needed more than the shader's stack, or the driver ended its
    /// loops first (lavapipe's 65,535 iterations a invocation; see the
    /// shader's head); the caller gathers those points on the CPU.
    /// `groups` are the irradiance module's bind groups, in the order of
    /// the layouts given to [`GpuCloud::new`].
    pub fn gather(
        &self,
        ctx: &GpuContext,
        points: &[GatherPoint],
        groups: &[&wgpu::BindGroup],
    ) -> Result<Vec<Option<[f32; 3]>>, GpuError> {
        let v = self.dispatch(ctx, points, groups)?;
        if std::env::var_os("SCATTERLAB_TIMINGS").is_some() {
            let state = |w: f32| v.iter().filter(|p| p[3] == w).count();
            eprintln!(
                "timing: GPU gather: {} points, {} outgrew the stack, {} ended by the driver",
                points.len(),
                state(2.0),
                state(3.0)
            );
        }
        Ok(v.iter()
            .map(|&[r, g, b, state]| {
                (state == 1.0 && [r, g, b].iter().all(|c| c.is_finite())).then_some([r, g, b])
            })
            .collect())
    }

    /// Each point's (rgb, state) as the shader writes it (`cs_gather`).
    fn dispatch(
        &self,
        ctx: &GpuContext,
        points: &[GatherPoint],
        groups: &[&wgpu::BindGroup],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        if points.is_empty() {
            return Ok(Vec::new());
        }
        let device = &ctx.device;
        let mut data: Vec<[f32; 4]> = Vec::with_capacity(3 * points.len());
        for p in points {
            data.push([p.x_mm.x, p.x_mm.y, p.x_mm.z, p.profile_scale]);
            data.push([p.pixel_dx_mm.x, p.pixel_dx_mm.y, p.pixel_dx_mm.z, 0.0]);
            data.push([p.pixel_dy_mm.x, p.pixel_dy_mm.y, p.pixel_dy_mm.z, 0.0]);
        }
        let bytes = 16 * data.len() as u64;
        let limit = device.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: "the points to gather",
                bytes,
                limit,
            });
        }
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ground truth points"),
            contents: bytemuck::cast_slice(&data),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ground truth points readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = ctx.checked("the ground truth's gather (bind group)", || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ground truth"),
                layout: &self.layout,
                entries: &[
                    (0, &self.params_buffer),
                    (1, &self.tree),
                    (2, &self.node_e),
                    (3, &self.table),
                    (4, &buffer),
                ]
                .map(|(binding, b)| wgpu::BindGroupEntry {
                    binding,
                    resource: b.as_entire_binding(),
                }),
            })
        })?;
        for first in (0..points.len()).step_by(POINTS_PER_DISPATCH) {
            let count = POINTS_PER_DISPATCH.min(points.len() - first);
            let params = GatherParams {
                first: first as u32,
                count: count as u32,
                ..self.params
            };
            ctx.queue
                .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&params));
            let mut enc = device.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("ground truth gather"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.pipeline);
                for (k, g) in groups.iter().enumerate() {
                    pass.set_bind_group(k as u32, *g, &[]);
                }
                pass.set_bind_group(groups.len() as u32, &bind, &[]);
                pass.dispatch_workgroups(count.div_ceil(64) as u32, 1, 1);
            }
            if first + count >= points.len() {
                enc.copy_buffer_to_buffer(&buffer, 0, &read, 0, bytes);
            }
            ctx.queue.submit([enc.finish()]);
        }
        let (tx, rx) = std::sync::mpsc::channel();
        read.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        let failed = |e: String| GpuError::Readback(format!("the ground truth's points: {e}"));
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| failed(e.to_string()))?;
        rx.recv()
            .map_err(|e| failed(e.to_string()))?
            .map_err(|e| failed(e.to_string()))?;
        let mapped = read
            .slice(..)
            .get_mapped_range()
            .map_err(|e| failed(e.to_string()))?;
        let v: &[[f32; 4]] = bytemuck::cast_slice(&mapped);
        let out = (0..points.len()).map(|i| v[3 * i]).collect();
        drop(mapped);
        read.unmap();
        Ok(out)
    }
}

/// The irradiance module of the renderer's GPU ground truth: the scene
/// pass's WGSL (its `shade`, bindings in group 0) and the mesh's
/// interpolation (group 1, [`MeshOnGpu`]).
pub fn scene_irradiance_wgsl() -> String {
    format!(
        "{}\n{}",
        include_str!("../../../shaders/scene.wgsl"),
        include_str!("../../../shaders/ground_truth_scene.wgsl")
    )
}

/// The mesh's vertices and triangles as storage buffers (group 1 of
/// [`scene_irradiance_wgsl`]).
pub struct MeshOnGpu {
    pub layout: wgpu::BindGroupLayout,
    pub bind: wgpu::BindGroup,
}

impl MeshOnGpu {
    pub fn new(ctx: &GpuContext, mesh: &crate::render::Mesh) -> Result<Self, GpuError> {
        let device = &ctx.device;
        let limit = device.limits().max_storage_buffer_binding_size;
        let vertices: &[u8] = bytemuck::cast_slice(&mesh.vertices);
        let indices: &[u8] = bytemuck::cast_slice(&mesh.indices);
        for (what, bytes) in [
            ("the mesh's vertices", vertices.len() as u64),
            ("the mesh's triangles", indices.len() as u64),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge { what, bytes, limit });
            }
        }
        ctx.checked("the ground truth's mesh", || {
            let entry = |binding| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            };
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ground truth mesh"),
                entries: &[entry(0), entry(1)],
            });
            let buffer = |label, contents: &[u8]| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: if contents.is_empty() {
                        &[0; 4]
                    } else {
                        contents
                    },
                    usage: wgpu::BufferUsages::STORAGE,
                })
            };
            let v = buffer("ground truth vertices", vertices);
            let i = buffer("ground truth indices", indices);
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ground truth mesh"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: v.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: i.as_entire_binding(),
                    },
                ],
            });
            Self { layout, bind }
        })
    }
}

#[cfg(test)]
#[path = "gpu_tests.rs"]
mod gpu_tests;
