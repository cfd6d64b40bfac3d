//! Meshes: the embedded default head and OBJ files, with smooth normals.

use super::gpu_types::Vertex;
use glam::Vec3;
use std::path::Path;

/// The default head (CC0 MakeHuman hm08, see assets/head/ATTRIBUTION.md).
pub const DEFAULT_HEAD_OBJ: &str = include_str!("../../assets/head/head.obj");
/// Metres per unit of the default head (decimetres).
pub const DEFAULT_HEAD_METRES_PER_UNIT: f32 = 0.1;

/// A triangle mesh ready for upload.
#[derive(Debug, Clone)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub metres_per_unit: f32,
    /// Where the camera looks (mesh units).
    pub focus: [f32; 3],
}

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{path}: cannot load mesh: {message}")]
    Load { path: String, message: String },
    #[error("{path}: the mesh has no triangles")]
    Empty { path: String },
}

impl Mesh {
    pub fn default_head() -> Result<Self, MeshError> {
        Self::from_obj_text(
            DEFAULT_HEAD_OBJ,
            "<embedded default head>",
            DEFAULT_HEAD_METRES_PER_UNIT,
        )
    }

    pub fn load_obj(path: &Path, metres_per_unit: f32) -> Result<Self, MeshError> {
        let text = std::fs::read_to_string(path).map_err(|e| MeshError::Load {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_obj_text(&text, &path.display().to_string(), metres_per_unit)
    }

    /// Parses OBJ text; groups named `eyes`/`teeth` become non-scattering materials.
    pub fn from_obj_text(
        text: &str,
        origin: &str,
        metres_per_unit: f32,
    ) -> Result<Self, MeshError> {
        let mut reader = std::io::BufReader::new(text.as_bytes());
        let opts = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        };
        let (models, _) =
            tobj::load_obj_buf(&mut reader, &opts, |_| Ok((Vec::new(), Default::default())))
                .map_err(|e| MeshError::Load {
                    path: origin.into(),
                    message: e.to_string(),
                })?;
        let mut mesh = Mesh {
            vertices: Vec::new(),
            indices: Vec::new(),
            metres_per_unit,
            focus: [0.0; 3],
        };
        for m in &models {
            let material = match m.name.as_str() {
                "eyes" => 1.0,
                "teeth" => 2.0,
                _ => 0.0,
            };
            let base = mesh.vertices.len() as u32;
            let p = &m.mesh.positions;
            let t = &m.mesh.texcoords;
            for i in 0..p.len() / 3 {
                let uv = if t.len() >= 2 * (i + 1) {
                    [t[2 * i], t[2 * i + 1]]
                } else {
                    [0.0, 0.0]
                };
                mesh.vertices.push(Vertex {
                    position: [p[3 * i], p[3 * i + 1], p[3 * i + 2]],
                    normal: [0.0; 3],
                    uv,
                    material,
                });
            }
            mesh.indices.extend(m.mesh.indices.iter().map(|i| base + i));
        }
        if mesh.indices.is_empty() {
            return Err(MeshError::Empty {
                path: origin.into(),
            });
        }
        mesh.compute_smooth_normals();
        // Look at eye height: 62 % up the bounding box (the face of a head).
        let (lo, hi) = mesh.bounds();
        mesh.focus = [
            0.5 * (lo.x + hi.x),
            lo.y + 0.62 * (hi.y - lo.y),
            0.5 * (lo.z + hi.z),
        ];
        Ok(mesh)
    }

    /// A square of side `size` (units) in the z = 0 plane facing +z, all skin.
    pub fn plane(size: f32, metres_per_unit: f32) -> Self {
        let h = 0.5 * size;
        let v = |x: f32, y: f32, u: f32, w: f32| Vertex {
            position: [x, y, 0.0],
            normal: [0.0, 0.0, 1.0],
            uv: [u, w],
            material: 0.0,
        };
        Mesh {
            vertices: vec![
                v(-h, -h, 0.0, 0.0),
                v(h, -h, 1.0, 0.0),
                v(h, h, 1.0, 1.0),
                v(-h, h, 0.0, 1.0),
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            metres_per_unit,
            focus: [0.0; 3],
        }
    }

    /// Area-weighted vertex normals, merged across UV seams by position.
    pub fn compute_smooth_normals(&mut self) {
        use std::collections::HashMap;
        let key = |p: [f32; 3]| (p[0].to_bits(), p[1].to_bits(), p[2].to_bits());
        let mut acc: HashMap<(u32, u32, u32), Vec3> = HashMap::new();
        for tri in self.indices.chunks_exact(3) {
            let [a, b, c] =
                [tri[0], tri[1], tri[2]].map(|i| Vec3::from(self.vertices[i as usize].position));
            let n = (b - a).cross(c - a); // length = 2·area
            for &i in tri {
                *acc.entry(key(self.vertices[i as usize].position))
                    .or_insert(Vec3::ZERO) += n;
            }
        }
        for v in &mut self.vertices {
            v.normal = acc
                .get(&key(v.position))
                .copied()
                .unwrap_or(Vec3::Y)
                .normalize_or(Vec3::Y)
                .into();
        }
    }

    /// Axis-aligned bounds (min, max) in mesh units.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), v| {
                let p = Vec3::from(v.position);
                (lo.min(p), hi.max(p))
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_head_loads_with_three_materials() {
        let m = Mesh::default_head().unwrap();
        assert!(
            m.indices.len() / 3 > 8000,
            "{} triangles",
            m.indices.len() / 3
        );
        let (lo, hi) = m.bounds();
        // About 31 cm from collar to crown at 0.1 m per unit.
        assert!(
            (hi.y - lo.y) * m.metres_per_unit > 0.25 && (hi.y - lo.y) * m.metres_per_unit < 0.35
        );
        for mat in [0.0, 1.0, 2.0] {
            assert!(
                m.vertices.iter().any(|v| v.material == mat),
                "material {mat}"
            );
        }
        assert!(m
            .vertices
            .iter()
            .all(|v| (Vec3::from(v.normal).length() - 1.0).abs() < 1e-3));
    }

    #[test]
    fn bad_obj_is_an_error() {
        assert!(Mesh::from_obj_text("v 0 0 0\n", "empty.obj", 1.0).is_err());
        assert!(Mesh::load_obj(Path::new("/no/such.obj"), 1.0)
            .unwrap_err()
            .to_string()
            .contains("/no/such.obj"));
    }
}
