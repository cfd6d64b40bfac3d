//! `texture-space`'s probe rays (`--probe-rays on`, on a device with ray
//! queries: `GpuContext::ray_queries`): besides reading each of burley's
//! disk samples (Golubev 2018) through the UV layout, the gather casts a
//! probe ray along the triangle's normal through the sample's point,
//! across the profile's sphere, as NVIDIA's RTX Character Rendering SDK
//! does (a disk sample, a probe ray, only skin accepted). The skin it
//! crosses far from the pixel in UV (closed lids and lips, the folds of
//! the ear; issue 53's diagnosis), and the pixel's own sheet where the UV
//! sample lost it at a seam, add their light at the 3D distance the ground
//! truth weighs it by. `shaders/texture_space_rays.wgsl` is the gather and
//! states the estimator.
//!
//! The acceleration structure holds the skin triangles (eyes and teeth do
//! not scatter, as in the ground truth) of the level of detail the scene
//! pass drew, built once per mesh. Measured (docs/accuracy.md), it gains
//! 4–10 points on three of the bench's four head views and gives 1 back
//! on the fourth, at 11–40 × the UV gather's time on lavapipe, so it is
//! off by default.

use crate::render::mesh::Mesh;
use crate::render::pipelines::buffer_entry;
use wgpu::util::DeviceExt;

/// The mesh as the probe rays see it: its skin triangles in an
/// acceleration structure, and each one's normal and UVs.
pub(super) struct RayScene {
    /// Kept alive with the TLAS that refers to it.
    _blas: wgpu::Blas,
    tlas: wgpu::Tlas,
    /// Per skin triangle, in the BLAS's order: its unit normal, then its
    /// three UVs ([`triangle_records`]).
    triangles: wgpu::Buffer,
}

/// A mesh's identity for the cache: its positions, UVs and indices.
pub(super) fn mesh_key(mesh: &Mesh) -> u64 {
    use std::hash::Hasher;
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for v in &mesh.vertices {
        h.write(bytemuck::cast_slice(&v.position));
        h.write(bytemuck::cast_slice(&v.uv));
        h.write_u32(v.material.to_bits());
    }
    h.write(bytemuck::cast_slice(&mesh.indices));
    h.finish()
}

/// The skin triangles' vertex indices: a triangle is skin where all
/// three of its vertices are (`SurfaceKind` code 0).
fn skin_triangles(mesh: &Mesh) -> Vec<[u32; 3]> {
    let skin = |i: u32| {
        mesh.vertices
            .get(i as usize)
            .is_some_and(|v| v.material < 0.5)
    };
    mesh.indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .filter(|t| t.iter().all(|&i| skin(i)))
        .collect()
}

/// Per triangle, 12 floats: its unit normal (right-handed from its
/// winding; the gather takes |n·axis|, so the winding does not matter)
/// and 0, then u0 v0 u1 v1, then u2 v2 0 0. `shaders/texture_space_rays.wgsl`'s
/// `RayTriangle` is its twin.
fn triangle_records(mesh: &Mesh, triangles: &[[u32; 3]]) -> Vec<[f32; 12]> {
    triangles
        .iter()
        .map(|t| {
            let v = t.map(|i| &mesh.vertices[i as usize]);
            let p = v.map(|v| glam::Vec3::from(v.position));
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            [
                n.x, n.y, n.z, 0.0, v[0].uv[0], v[0].uv[1], v[1].uv[0], v[1].uv[1], v[2].uv[0],
                v[2].uv[1], 0.0, 0.0,
            ]
        })
        .collect()
}

impl RayScene {
    /// Builds the structures for `mesh` and submits the build at once (on
    /// its own encoder: a frame whose commands are dropped cannot leave
    /// the cache holding a structure that was never built). `None` where
    /// the mesh has no skin.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, mesh: &Mesh) -> Option<Self> {
        let triangles = skin_triangles(mesh);
        if triangles.is_empty() {
            return None;
        }
        let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.position).collect();
        let input = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::BLAS_INPUT,
            })
        };
        let vertex_buffer = input("probe-ray positions", bytemuck::cast_slice(&positions));
        let index_buffer = input("probe-ray indices", bytemuck::cast_slice(&triangles));
        let size = wgpu::BlasTriangleGeometrySizeDescriptor {
            vertex_format: wgpu::VertexFormat::Float32x3,
            vertex_count: positions.len() as u32,
            index_format: Some(wgpu::IndexFormat::Uint32),
            index_count: Some(3 * triangles.len() as u32),
            // Not opaque: the gather takes every triangle a ray crosses
            // as a candidate, each once.
            flags: wgpu::AccelerationStructureGeometryFlags::NO_DUPLICATE_ANY_HIT_INVOCATION,
        };
        let blas = device.create_blas(
            &wgpu::CreateBlasDescriptor {
                label: Some("probe-ray skin"),
                flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                update_mode: wgpu::AccelerationStructureUpdateMode::Build,
            },
            wgpu::BlasGeometrySizeDescriptors::Triangles {
                descriptors: vec![size.clone()],
            },
        );
        let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
            label: Some("probe-ray scene"),
            max_instances: 1,
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        });
        // The mesh in world units, untransformed.
        const IDENTITY: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        if let Some(slot) = tlas.get_mut_single(0) {
            *slot = Some(wgpu::TlasInstance::new(&blas, IDENTITY, 0, 0xff));
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("probe-ray build"),
        });
        encoder.build_acceleration_structures(
            std::iter::once(&wgpu::BlasBuildEntry {
                blas: &blas,
                geometry: wgpu::BlasGeometries::TriangleGeometries(vec![
                    wgpu::BlasTriangleGeometry {
                        size: &size,
                        vertex_buffer: &vertex_buffer,
                        first_vertex: 0,
                        vertex_stride: 12,
                        index_buffer: Some(&index_buffer),
                        first_index: Some(0),
                        transform_buffer: None,
                        transform_buffer_offset: None,
                    },
                ]),
            }),
            std::iter::once(&tlas),
        );
        queue.submit([encoder.finish()]);
        let records = triangle_records(mesh, &triangles);
        let triangles_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe-ray triangles"),
            contents: bytemuck::cast_slice(&records),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Some(Self {
            _blas: blas,
            tlas,
            triangles: triangles_buffer,
        })
    }

    /// The gather's group 2 ([`layout`]).
    pub fn bind_group(&self, device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("texture-space probe rays"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.tlas.as_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.triangles.as_entire_binding(),
                },
            ],
        })
    }
}

/// The probe-ray gather's own group (2): the acceleration structure and
/// the triangles' records.
pub(super) fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let frag = wgpu::ShaderStages::FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("texture-space probe rays"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: frag,
                ty: wgpu::BindingType::AccelerationStructure {
                    vertex_return: false,
                },
                count: None,
            },
            buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: true }, frag),
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::gpu_types::Vertex;

    fn vertex(position: [f32; 3], uv: [f32; 2], material: f32) -> Vertex {
        Vertex {
            position,
            normal: [0.0, 0.0, 1.0],
            uv,
            material,
            curvature_per_mm: 0.0,
            thickness_mm: 0.0,
            tangent: [1.0, 0.0, 0.0, 1.0],
        }
    }

    /// A skin triangle and one with an eye vertex: only the first is
    /// kept, with its normal (+z by the right-hand rule on its winding)
    /// and its UVs in order.
    #[test]
    fn only_skin_triangles_are_probed() {
        let mut mesh = Mesh::plane(1.0, 0.001);
        mesh.vertices = vec![
            vertex([0.0, 0.0, 0.0], [0.1, 0.2], 0.0),
            vertex([1.0, 0.0, 0.0], [0.3, 0.4], 0.0),
            vertex([0.0, 1.0, 0.0], [0.5, 0.6], 0.0),
            vertex([0.0, 0.0, 1.0], [0.7, 0.8], 1.0),
        ];
        mesh.indices = vec![0, 1, 2, 0, 1, 3];
        let tris = skin_triangles(&mesh);
        assert_eq!(tris, vec![[0, 1, 2]]);
        let r = triangle_records(&mesh, &tris);
        assert_eq!(
            r[0],
            [0.0, 0.0, 1.0, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.0, 0.0]
        );
    }
}
