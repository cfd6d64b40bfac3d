//! What a mesh computes from its triangles once loaded: MikkTSpace
//! tangents, smooth normals, per-vertex curvature (FaceWorks' estimate)
//! and the thickness along the inward normal (ray cast), for the
//! transmission and pre-integrated methods.

use super::*;

impl Mesh {
    /// Per-vertex tangents by MikkTSpace (Mikkelsen 2008), the tangent
    /// space glTF 2.0 prescribes when a file has none and the one the
    /// normal-map bakers (Blender, Substance, xNormal) bake against, so
    /// baked maps show no seams. `bevy_mikktspace` is a safe Rust port,
    /// byte-identical to the reference C code; tests/real_clients.rs checks
    /// the result against Blender's own `calc_tangents`. MikkTSpace reads
    /// UVs with V up the image (OpenGL, Blender), so v is flipped from our
    /// top-left origin; B = w·N×T then runs up the image, as the shader's
    /// normal map (green up) expects. MikkTSpace answers per face corner;
    /// a vertex shared by corners that disagree (a mirror seam welded in
    /// the index buffer) keeps the last, as glTF importers do. Corners it
    /// cannot serve (degenerate UVs everywhere around) get any unit vector
    /// ⟂ N.
    pub fn compute_tangents(&mut self) {
        struct Corners<'a> {
            vertices: &'a [Vertex],
            indices: &'a [u32],
            out: Vec<Option<[f32; 4]>>,
        }
        impl Corners<'_> {
            fn v(&self, face: usize, vert: usize) -> &Vertex {
                &self.vertices[self.indices[3 * face + vert] as usize]
            }
        }
        impl bevy_mikktspace::Geometry for Corners<'_> {
            fn num_faces(&self) -> usize {
                self.indices.len() / 3
            }
            fn num_vertices_of_face(&self, _face: usize) -> usize {
                3
            }
            fn position(&self, face: usize, vert: usize) -> [f32; 3] {
                self.v(face, vert).position
            }
            fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
                self.v(face, vert).normal
            }
            fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
                let uv = self.v(face, vert).uv;
                [uv[0], 1.0 - uv[1]]
            }
            fn set_tangent(
                &mut self,
                tangent: Option<bevy_mikktspace::TangentSpace>,
                face: usize,
                vert: usize,
            ) {
                let i = self.indices[3 * face + vert] as usize;
                if let Some(t) = tangent {
                    self.out[i] = Some(t.tangent_encoded());
                }
            }
        }
        let mut g = Corners {
            vertices: &self.vertices,
            indices: &self.indices,
            out: vec![None; self.vertices.len()],
        };
        // An error means no face could be processed; every vertex then
        // takes the fallback below.
        let _ = bevy_mikktspace::generate_tangents(&mut g);
        let out = g.out;
        for (v, t) in self.vertices.iter_mut().zip(out) {
            let nrm = Vec3::from(v.normal);
            v.tangent = match t {
                Some(t) if Vec3::new(t[0], t[1], t[2]).is_finite() => t,
                _ => {
                    let t = nrm.any_orthonormal_vector();
                    [t.x, t.y, t.z, 1.0]
                }
            };
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

    /// Per-vertex curvature as FaceWorks computes it
    /// (`GFSDK_FaceWorks_CalculateMeshCurvature`): each edge's |ΔN|/|ΔP|,
    /// the mean of the smallest and largest at each vertex, then `passes`
    /// rounds of averaging over neighbours. Stored in 1/mm. Vertices that
    /// share a position (UV seams) share the result.
    pub fn compute_curvature(&mut self, passes: usize) {
        use std::collections::HashMap;
        let key = |p: [f32; 3]| (p[0].to_bits(), p[1].to_bits(), p[2].to_bits());
        let mut id: HashMap<(u32, u32, u32), usize> = HashMap::new();
        let vid: Vec<usize> = self
            .vertices
            .iter()
            .map(|v| {
                let n = id.len();
                *id.entry(key(v.position)).or_insert(n)
            })
            .collect();
        let n = id.len();
        let (mut lo, mut hi) = (vec![f32::INFINITY; n], vec![0.0f32; n]);
        let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
        for tri in self.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
                let dp =
                    Vec3::from(self.vertices[b].position) - Vec3::from(self.vertices[a].position);
                let dn = Vec3::from(self.vertices[b].normal) - Vec3::from(self.vertices[a].normal);
                if dp.length_squared() <= 0.0 {
                    continue;
                }
                let kappa = (dn.length_squared() / dp.length_squared()).sqrt();
                for (v, w) in [(vid[a], vid[b]), (vid[b], vid[a])] {
                    lo[v] = lo[v].min(kappa);
                    hi[v] = hi[v].max(kappa);
                    neighbours[v].push(w);
                }
            }
        }
        let mut curv: Vec<f32> = (0..n)
            .map(|i| {
                if lo[i].is_finite() {
                    0.5 * (lo[i] + hi[i])
                } else {
                    0.0
                }
            })
            .collect();
        for _ in 0..passes {
            curv = (0..n)
                .map(|i| {
                    if neighbours[i].is_empty() {
                        curv[i]
                    } else {
                        neighbours[i].iter().map(|&j| curv[j]).sum::<f32>()
                            / neighbours[i].len() as f32
                    }
                })
                .collect();
        }
        let per_mm = 1.0 / (self.metres_per_unit * 1000.0);
        for (v, i) in self.vertices.iter_mut().zip(vid) {
            v.curvature_per_mm = curv[i] * per_mm;
        }
    }

    /// Thickness per vertex the way texture bakers do it: a ray from the
    /// surface along the inward normal to the first surface it meets, over a
    /// uniform grid of triangles. Misses (open boundaries) get `max_mm`.
    pub fn bake_thickness(&mut self, max_mm: f32) {
        use std::sync::atomic::Ordering;
        BAKE_PROGRESS[1].store(self.vertices.len() as u32, Ordering::Relaxed);
        BAKE_PROGRESS[0].store(0, Ordering::Relaxed);
        let (lo, hi) = self.bounds();
        let n = 24usize;
        let cell = (hi - lo).max_element() / n as f32 + 1e-6;
        let idx = |p: Vec3| -> Option<usize> {
            let c = ((p - lo) / cell).floor();
            if c.min_element() < 0.0 || c.max_element() >= n as f32 {
                return None;
            }
            Some((c.x as usize * n + c.y as usize) * n + c.z as usize)
        };
        let mut grid: Vec<Vec<u32>> = vec![Vec::new(); n * n * n];
        let pos = |i: u32| Vec3::from(self.vertices[i as usize].position);
        for (t, tri) in self.indices.chunks_exact(3).enumerate() {
            let [a, b, c] = [pos(tri[0]), pos(tri[1]), pos(tri[2])];
            let (tl, th) = (a.min(b).min(c), a.max(b).max(c));
            let (cl, ch) = (((tl - lo) / cell).floor(), ((th - lo) / cell).floor());
            for x in cl.x as usize..=(ch.x as usize).min(n - 1) {
                for y in cl.y as usize..=(ch.y as usize).min(n - 1) {
                    for z in cl.z as usize..=(ch.z as usize).min(n - 1) {
                        grid[(x * n + y) * n + z].push(t as u32);
                    }
                }
            }
        }
        let mm_per_unit = self.metres_per_unit * 1000.0;
        let thickness: Vec<f32> = self
            .vertices
            .par_iter()
            .map(|v| {
                BAKE_PROGRESS[0].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let dir = -Vec3::from(v.normal);
                let origin = Vec3::from(v.position) + dir * (1e-3 * cell);
                // March through the grid in half-cell steps; test each cell's triangles.
                let mut best = f32::INFINITY;
                let mut t = 0.0;
                let mut seen = usize::MAX;
                // Half-cell steps across the grid's diagonal (√3·n cells),
                // bounded whatever the extent's arithmetic does.
                let mut steps = 0;
                while t < 2.0 * (hi - lo).length() && t < best && steps < 8 * n {
                    steps += 1;
                    if let Some(c) = idx(origin + dir * t) {
                        if c != seen {
                            seen = c;
                            for &tri in &grid[c] {
                                let k = 3 * tri as usize;
                                let (a, b, cc) = (
                                    pos(self.indices[k]),
                                    pos(self.indices[k + 1]),
                                    pos(self.indices[k + 2]),
                                );
                                if let Some(h) = ray_triangle(origin, dir, a, b, cc) {
                                    best = best.min(h);
                                }
                            }
                        }
                    }
                    t += 0.5 * cell;
                }
                if best.is_finite() {
                    (best * mm_per_unit).min(max_mm)
                } else {
                    max_mm
                }
            })
            .collect();
        for (v, d) in self.vertices.iter_mut().zip(thickness) {
            v.thickness_mm = d;
        }
    }
}

/// Möller–Trumbore: distance along `dir` to the triangle, if hit in front.
pub(super) fn ray_triangle(o: Vec3, dir: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some(t)
}
