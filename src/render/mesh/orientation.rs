//! Which way a mesh faces: a file exported inside out (its triangles
//! wound clockwise seen from outside, or its normals pointing in) draws as
//! a dark disc, since the rasteriser keeps the triangles that face the
//! camera by their winding (glTF 2.0 and OBJ: counter-clockwise is the
//! front) and the shading lights the side its normals face.

use super::{Mesh, MAX_THICKNESS_MM};
use glam::Vec3;

/// How a mesh faces, judged over its whole surface about its bounding
/// box's centre (area-weighted, so a closed or an open surface such as a
/// bust with an open neck is judged by most of its skin).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Facing {
    /// The triangles are wound clockwise seen from outside.
    pub faces_inward: bool,
    /// The vertex normals point inside.
    pub normals_inward: bool,
}

impl Facing {
    /// Either is inward.
    pub fn inside_out(self) -> bool {
        self.faces_inward || self.normals_inward
    }

    /// What is inward, in words ("its faces", "its normals", "its faces
    /// and normals"); `None` when neither is.
    pub fn describe(self) -> Option<&'static str> {
        match (self.faces_inward, self.normals_inward) {
            (true, true) => Some("its faces and normals"),
            (true, false) => Some("its faces"),
            (false, true) => Some("its normals"),
            (false, false) => None,
        }
    }
}

/// How much of the surface's outward test must point in for a mesh to be
/// called inside out: a fifth of its largest possible size (a closed
/// sphere inside out scores the whole, a flat sheet nothing).
const INWARD_SHARE: f64 = 0.2;

impl Mesh {
    /// Which way the mesh faces: the sum over triangles of their outward
    /// test (the triangle's own normal, by winding, against the direction
    /// from the bounding box's centre to the triangle), area-weighted, and
    /// the same for the vertex normals.
    pub fn facing(&self) -> Facing {
        let (lo, hi) = self.bounds();
        let centre = 0.5 * (lo + hi);
        // Each sum beside the sum of its terms' sizes: a flat or nearly
        // flat surface (a scanned skin sample) sums to about nothing either
        // way, and is not called inward on float noise.
        let (mut by_winding, mut by_normals, mut size) = (0.0f64, 0.0f64, 0.0f64);
        for t in self.indices.chunks_exact(3) {
            let v = |i: u32| &self.vertices[i as usize];
            let p = |i: u32| Vec3::from(v(i).position);
            let cross = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            let out = (p(t[0]) + p(t[1]) + p(t[2])) / 3.0 - centre;
            by_winding += cross.dot(out) as f64;
            let n: Vec3 = t.iter().map(|&i| Vec3::from(v(i).normal)).sum();
            by_normals += (n.normalize_or_zero() * cross.length()).dot(out) as f64;
            size += (cross.length() * out.length()) as f64;
        }
        let inward = |sum: f64| sum < -INWARD_SHARE * size;
        Facing {
            faces_inward: inward(by_winding),
            normals_inward: inward(by_normals),
        }
    }

    /// Turns what faces inward outward: each triangle's winding reversed
    /// if the faces are inward, the normals negated (and the tangents'
    /// handedness, so the bitangent still runs up the image) if they are;
    /// then the curvature and the thickness, which follow the normals,
    /// are baked again. The coarse level of detail is turned with it.
    /// Returns what was turned.
    pub fn turn_outward(&mut self) -> Facing {
        let facing = self.facing();
        if facing.faces_inward {
            for t in self.indices.chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
        if facing.normals_inward {
            for v in &mut self.vertices {
                v.normal = v.normal.map(|c| -c);
                v.tangent[3] = -v.tangent[3];
            }
        }
        if facing.inside_out() {
            self.compute_curvature(2);
            self.bake_thickness(MAX_THICKNESS_MM);
        }
        if let Some(coarse) = self.coarse.as_mut() {
            coarse.turn_outward();
        }
        facing
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed box (a cube of side 2 at the origin) built as
    /// counter-clockwise triangles seen from outside, with outward normals
    /// (the cube's faces; glTF's and OBJ's front is counter-clockwise), then
    /// the same box turned inside out three ways, as a glTF with its own
    /// normals can be (an OBJ's normals follow its winding). Each is judged
    /// as built, and turning it outward gives back the outward box: its
    /// facing and its thickness bake.
    #[test]
    fn an_inside_out_cube_is_seen_and_turned() {
        use crate::render::gpu_types::Vertex;
        use bytemuck::Zeroable;
        // Each face: its outward normal and two in-plane axes with
        // u × v = n, so (0, u, u+v, v) runs counter-clockwise seen from n.
        let faces: [[Vec3; 3]; 6] = [
            [Vec3::X, Vec3::Y, Vec3::Z],
            [-Vec3::X, Vec3::Z, Vec3::Y],
            [Vec3::Y, Vec3::Z, Vec3::X],
            [-Vec3::Y, Vec3::X, Vec3::Z],
            [Vec3::Z, Vec3::X, Vec3::Y],
            [-Vec3::Z, Vec3::Y, Vec3::X],
        ];
        let cube = |flip_winding: bool, flip_normals: bool| {
            let (mut vertices, mut indices) = (Vec::new(), Vec::new());
            for (k, [n, u, v]) in faces.iter().enumerate() {
                assert!((u.cross(*v) - *n).length() < 1e-6);
                let normal = if flip_normals { -*n } else { *n };
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    vertices.push(Vertex {
                        position: (*n + *u * a + *v * b).to_array(),
                        normal: normal.to_array(),
                        uv: [0.5 + 0.4 * a, 0.5 + 0.4 * b],
                        ..Vertex::zeroed()
                    });
                }
                let i = 4 * k as u32;
                let quad = if flip_winding {
                    [0, 2, 1, 0, 3, 2]
                } else {
                    [0, 1, 2, 0, 2, 3]
                };
                indices.extend(quad.map(|j| i + j));
            }
            Mesh::from_triangles(vertices, indices, "cube", 1.0, true).unwrap()
        };
        let outward = cube(false, false);
        assert_eq!(outward.facing(), Facing::default());
        for (w, n) in [(true, false), (false, true), (true, true)] {
            let mut m = cube(w, n);
            let seen = m.facing();
            assert_eq!((seen.faces_inward, seen.normals_inward), (w, n));
            assert_eq!(m.turn_outward(), seen);
            assert_eq!(m.facing(), Facing::default(), "{w} {n}");
            // The thickness, baked again along the turned normals, is the
            // outward box's.
            for (a, b) in m.vertices.iter().zip(&outward.vertices) {
                assert!((a.thickness_mm - b.thickness_mm).abs() < 1e-3, "{w} {n}");
            }
        }
    }
}
