//! The mesh as a Wavefront OBJ in metres, for another renderer to draw
//! the same surface (`scatterlab render --scene-obj`; Cycles in
//! tests/clients/blender_head.py).

use super::Mesh;
use crate::render::gpu_types::SurfaceKind;
use std::fmt::Write;

impl Mesh {
    /// The triangles in the renderer's world frame (y up, the mesh's units
    /// times `metres_per_unit`), with the smooth normals it shades with
    /// (`vn`, one per vertex) and its UVs (`vt`, v up as OBJ has it; the
    /// renderer flips it on load). Triangles are grouped by surface as
    /// [`Mesh::from_obj_text`] reads them back: `skin`, `eyes`, `teeth`.
    pub fn to_obj_metres(&self) -> String {
        let m = self.metres_per_unit;
        let mut out = format!(
            "# scatterlab {}: {} vertices, {} triangles, metres, y up\n",
            env!("CARGO_PKG_VERSION"),
            self.vertices.len(),
            self.indices.len() / 3
        );
        for v in &self.vertices {
            let [x, y, z] = v.position;
            let _ = writeln!(out, "v {} {} {}", x * m, y * m, z * m);
        }
        for v in &self.vertices {
            let [x, y, z] = v.normal;
            let _ = writeln!(out, "vn {x} {y} {z}");
        }
        for v in &self.vertices {
            let _ = writeln!(out, "vt {} {}", v.uv[0], 1.0 - v.uv[1]);
        }
        for (kind, name) in [
            (SurfaceKind::Skin, "skin"),
            (SurfaceKind::Eye, "eyes"),
            (SurfaceKind::Teeth, "teeth"),
        ] {
            let of_kind =
                |t: &&[u32]| SurfaceKind::of(self.vertices[t[0] as usize].material) == kind;
            let mut triangles = self.indices.chunks_exact(3).filter(of_kind).peekable();
            if triangles.peek().is_none() {
                continue;
            }
            let _ = writeln!(out, "g {name}");
            for t in triangles {
                let [a, b, c] = [t[0] + 1, t[1] + 1, t[2] + 1];
                let _ = writeln!(out, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Read back by the OBJ loader, the export gives the same triangles in
    /// metres (at 1 m per unit) and the same surfaces; its `vn` lines are
    /// the normals the renderer shades with (the loader recomputes its
    /// own, so they are read from the text) and its `vt` lines the UVs with
    /// v up, as OBJ has it.
    #[test]
    fn obj_in_metres_reads_back() {
        let head =
            Mesh::from_obj_text(crate::render::mesh::DEFAULT_HEAD_OBJ, "head.obj", 0.1).unwrap();
        let text = head.to_obj_metres();
        let back = Mesh::from_obj_text(&text, "export.obj", 1.0).unwrap();
        assert_eq!(back.indices.len(), head.indices.len());
        let kinds = |m: &Mesh| {
            let mut n = [0usize; 3];
            for t in m.indices.chunks_exact(3) {
                n[SurfaceKind::of(m.vertices[t[0] as usize].material).code() as usize] += 1;
            }
            n
        };
        assert_eq!(kinds(&back), kinds(&head));
        assert!(kinds(&head)[1] > 0, "the default head has eyes");
        // The same place and size: bounds in metres (0.1 m per unit), and
        // the skin's area.
        let ((lo, hi), (blo, bhi)) = (head.bounds(), back.bounds());
        assert!((lo * 0.1 - blo).abs().max_element() < 1e-6, "{lo} {blo}");
        assert!((hi * 0.1 - bhi).abs().max_element() < 1e-6, "{hi} {bhi}");
        let skin_area = |m: &Mesh| -> f32 {
            m.indices
                .chunks_exact(3)
                .filter(|t| {
                    SurfaceKind::of(m.vertices[t[0] as usize].material) == SurfaceKind::Skin
                })
                .map(|t| {
                    let p = |i: u32| glam::Vec3::from(m.vertices[i as usize].position);
                    0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length()
                })
                .sum()
        };
        let (a, b) = (skin_area(&head) * 0.01, skin_area(&back));
        assert!(
            (a / b - 1.0).abs() < 1e-4,
            "skin area {a} m² against {b} m²"
        );
        let lines = |tag: &str| -> Vec<Vec<f32>> {
            text.lines()
                .filter(|l| l.split_whitespace().next() == Some(tag))
                .map(|l| {
                    l.split_whitespace()
                        .skip(1)
                        .map(|w| w.parse().unwrap())
                        .collect()
                })
                .collect()
        };
        let (vn, vt) = (lines("vn"), lines("vt"));
        assert_eq!(vn.len(), head.vertices.len());
        assert_eq!(vt.len(), head.vertices.len());
        for (k, v) in head.vertices.iter().enumerate() {
            for c in 0..3 {
                assert!(
                    (vn[k][c] - v.normal[c]).abs() < 1e-6,
                    "vertex {k}: vn {:?}",
                    vn[k]
                );
            }
            assert!(
                (vt[k][0] - v.uv[0]).abs() < 1e-6,
                "vertex {k}: vt {:?}",
                vt[k]
            );
            assert!(
                (vt[k][1] - (1.0 - v.uv[1])).abs() < 1e-6,
                "vertex {k}: vt {:?}",
                vt[k]
            );
        }
    }
}
