//! The ground truth the SSS methods are judged against: the diffusion
//! profile integrated over the mesh surface in 3D. It shares the scene
//! pass's irradiance model with every method (the same light, shadow map
//! and 3 × 3 PCF, SH environment and maps, through the CPU twin
//! `render::scene_cpu`), and none of the screen-space approximations: no
//! projected disk, no pixel grid, no renormalisation over what the camera
//! sees. Its own floor (d → 0 against the unscattered frame, 2 × 2 points
//! a pixel against one) is measured per scene by `bench::floor`.
//!
//! This is the two-pass point-cloud integration of Jensen & Buhler 2002
//! (§3): (1) irradiance samples over the whole SSS surface, seen or not,
//! each with its own normal and area; (2) for every shaded point x_o,
//! M(x_o) = Σ R(‖x_o − x_i‖) · E(x_i) · A_i with the true 3D distance.
//! Here the samples are the cells of a quadtree over every SSS triangle
//! (midpoint splits down to at most `spacing_mm` on a side, 1 mm in the
//! renderer; each node holds the mean irradiance of its cells), and the
//! sum is an adaptive quadrature over that tree, below a hierarchy of
//! clusters of triangles (Jensen & Buhler's octree clustering, as a
//! binary tree: [`Cluster`]) that takes a distant group of triangles as
//! one term:
//! - a node counts as one piece, by the edge-midpoint rule (exact for
//!   quadratics on a triangle), when its side is at most its distance
//!   (θ = 1) and at most √(24 τ ρ/|ρ''|) with τ = 13.6 % (1.8 λ for an
//!   exponential of length λ; ρ'' numerically, per channel, ignoring a
//!   channel where ρ is under 1 % of its mean density inside its median
//!   radius); otherwise it is split into four. The bound is the centroid
//!   rule's error term, which the edge-midpoint rule's leading term
//!   cancels: on the default head's front view at 320 × 180, τ = 13.6 %
//!   with 1 mm cells is 0.13 % (relative RMSE) from τ = 0.85 % with
//!   0.5 mm cells, and τ = 3.4 % with 0.5 mm cells (the value before
//!   issue 23) is 0.09 % from it, under the ground truth's own d → 0
//!   floor (0.2–0.3 %) and a tenth of the closest method's error;
//! - a cell (or a piece of one) too wide for that rule at its distance is
//!   integrated exactly in polar coordinates about x_o through the
//!   profile's CDF (so the 1/r core, a Dirac part, Jimenez 2012's
//!   1 − strength, and a cell behind x_o are exact); where a corner's
//!   irradiance differs from the piece's mean by more than 1 % over the
//!   piece's share of the profile's energy (at most its annulus about
//!   x_o) it is split and its pieces' irradiance evaluated afresh, so
//!   shadow edges stay sharp at the core; splitting stops at ε = 2 % of
//!   the profile's narrowest 25 %-energy radius. Pieces within a pixel of
//!   x_o are read over the pixel's footprint (the d → 0 limit gives back
//!   the scene pass's pixel); the rest over their own width;
//! - cells farther than the widest channel's 0.999-energy radius are
//!   skipped: on a plane the sum then holds 99.9 % of each channel's energy
//!   or more, the truncation this ground truth states.
//!
//! The output is the scattered diffuse the screen-space methods produce:
//! Σ R·E·A / total per channel (the composite pass multiplies by the
//! albedo). Tests (`ground_truth_tests`) hold it against results it does
//! not share: the strip CDF across a straight edge (closed form for
//! Burley), energy on a uniformly lit plane, the thin-slab transmittance
//! T(t) of a back-lit slab, and a sphere lit from one side by quadrature
//! over the sphere.

mod cluster;
mod gather;
#[cfg(feature = "gpu")]
pub mod gpu;
mod table;

use cluster::{Cluster, ClusterKind};
pub use table::{ProfileTable, TruthBound, ENERGY_FRACTION};

use glam::Vec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// Probes gathered in turn on one thread with one [`Memo`]: neighbours in
/// the order given (the reference pass orders its pixels in tiles).
pub const MEMO_CHUNK: usize = 64;

/// The ground truth's progress in this process: [triangles or points done,
/// in all, phase] with phase 1 while the irradiance cloud is built and 2
/// while the gather runs, 0 when idle (for the editor's progress bar).
pub static PROGRESS: [std::sync::atomic::AtomicU32; 3] = [
    std::sync::atomic::AtomicU32::new(0),
    std::sync::atomic::AtomicU32::new(0),
    std::sync::atomic::AtomicU32::new(0),
];

/// (phase, fraction done, items in the phase) of the ground truth running
/// now, if any.
pub fn progress() -> Option<(u32, f32, u32)> {
    use std::sync::atomic::Ordering;
    let phase = PROGRESS[2].load(Ordering::Relaxed);
    let total = PROGRESS[1].load(Ordering::Relaxed);
    (phase > 0 && total > 0).then(|| {
        (
            phase,
            (PROGRESS[0].load(Ordering::Relaxed) as f32 / total as f32).min(1.0),
            total,
        )
    })
}

fn start(phase: u32, total: usize) {
    use std::sync::atomic::Ordering;
    PROGRESS[0].store(0, Ordering::Relaxed);
    PROGRESS[1].store(total.min(u32::MAX as usize) as u32, Ordering::Relaxed);
    PROGRESS[2].store(phase, Ordering::Relaxed);
}

fn step() {
    PROGRESS[0].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
}

fn finish() {
    PROGRESS[2].store(0, std::sync::atomic::Ordering::Relaxed);
}

/// The region of surface a value of the irradiance stands for: a pixel's
/// steps on the surface (mm) one pixel right and one down, as the GPU's
/// texture derivatives see them, and a width (mm) it is at least.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Footprint {
    pub pixel_dx_mm: Vec3,
    pub pixel_dy_mm: Vec3,
    pub width_mm: f32,
}

impl Footprint {
    /// A piece of surface `width_mm` across, seen by no pixel.
    pub fn width(width_mm: f32) -> Self {
        Self {
            width_mm,
            ..Self::default()
        }
    }
}

/// What the SSS methods blur, at a point of an SSS triangle: the scene
/// pass's diffuse target (irradiance/π × albedo^pre), linear RGB, as it
/// stands for the region `footprint` around the point (the twin reads its
/// maps at the mip level of that region, as the GPU reads them at the
/// level of a pixel's).
pub trait SurfaceIrradiance: Sync {
    fn at(&self, triangle: usize, bary: Vec3, footprint: Footprint) -> [f32; 3];
}

/// A point the ground truth is gathered at: a pixel's point on the surface
/// (mm) and how the surface moves under it from one pixel to the next
/// (the camera ray's differentials, Igehy 1999), which sets the width of
/// surface the pixel stands for, as the GPU's texture derivatives do.
#[derive(Debug, Clone, Copy)]
pub struct Probe {
    pub x_mm: Vec3,
    pub camera_mm: Vec3,
    /// The ray through the pixel, scaled to unit view depth, and its
    /// change per pixel in screen x and y.
    pub ray: Vec3,
    pub ray_dx: Vec3,
    pub ray_dy: Vec3,
    /// The pixel's place in its 2 × 2 quad (0 or 1 in x and y), for the
    /// GPU's derivatives ([`Probe::pixel_steps_mm`]).
    pub quad: glam::Vec2,
    /// The pixel's SSS mask, which scales the profile's radii there, as
    /// the screen-space passes scale their kernels by it (and HDRP its
    /// subsurface mask): 1 = the profile as it is.
    pub profile_scale: f32,
}

impl Probe {
    /// A point with no pixel: its near field is read at the pieces' own
    /// widths.
    pub fn point(x_mm: Vec3) -> Self {
        Self {
            x_mm,
            camera_mm: x_mm + Vec3::Z,
            ray: -Vec3::Z,
            ray_dx: Vec3::ZERO,
            ray_dy: Vec3::ZERO,
            quad: glam::Vec2::ZERO,
            profile_scale: 1.0,
        }
    }

    /// The surface steps (mm) one pixel to the right and one down make on
    /// the plane through x with normal `n`, as a GPU's derivatives see
    /// them: the differences between the pixels of the 2 × 2 quad the
    /// pixel shades in (Vulkan's coarse derivatives, from the quad's first
    /// pixel), each pixel's point P = C + t·D with t = (x − C)·n / (D·n)
    /// (the ray met with the plane; Igehy 1999). At a grazing view the
    /// quad's difference and the tangent at the pixel differ by much.
    pub fn pixel_steps_mm(&self, n: Vec3) -> (Vec3, Vec3) {
        let on_plane = |d: Vec3| -> Option<Vec3> {
            let dn = d.dot(n);
            (dn.abs() >= 1e-6)
                .then(|| self.camera_mm + d * ((self.x_mm - self.camera_mm).dot(n) / dn))
        };
        let first = self.ray - self.ray_dx * self.quad.x - self.ray_dy * self.quad.y;
        match (
            on_plane(first),
            on_plane(first + self.ray_dx),
            on_plane(first + self.ray_dy),
        ) {
            (Some(p0), Some(px), Some(py)) => (px - p0, py - p0),
            _ => (Vec3::ZERO, Vec3::ZERO),
        }
    }
}

/// A point the gather adds the surface's light up at: on the SSS surface
/// (mm), with its pixel's steps there (zero where no pixel sees it) and
/// the pixel's SSS mask ([`Probe::profile_scale`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GatherPoint {
    pub x_mm: Vec3,
    pub pixel_dx_mm: Vec3,
    pub pixel_dy_mm: Vec3,
    pub profile_scale: f32,
}

/// The split of a triangle at its edge midpoints into four, in the order
/// the quadtrees below index children: three corners, then the middle.
fn split<T: Copy + std::ops::Add<Output = T> + std::ops::Mul<f32, Output = T>>(
    v: [T; 3],
) -> [[T; 3]; 4] {
    let m = [0, 1, 2].map(|k| (v[k] + v[(k + 1) % 3]) * 0.5);
    [
        [v[0], m[0], m[2]],
        [m[0], v[1], m[1]],
        [m[2], m[1], v[2]],
        [m[0], m[1], m[2]],
    ]
}

fn longest_side(c: &[Vec3; 3]) -> f64 {
    (c[1] - c[0])
        .length()
        .max((c[2] - c[1]).length())
        .max((c[0] - c[2]).length()) as f64
}

/// One SSS triangle and the quadtree of its irradiance: `levels` levels
/// of midpoint splits down to cells at most `spacing_mm` on a side, each
/// node holding the area-weighted mean of its cells (all cells of a
/// triangle have equal area). Level ℓ's nodes start at (4^ℓ − 1)/3 in
/// `Cloud::node_e`, after `offset`; child k of node i is node 4i + k of
/// the next level.
#[derive(Debug, Clone, Copy)]
struct Root {
    tri: u32,
    corners: [Vec3; 3],
    levels: u32,
    offset: u32,
    /// Longest side, farthest corner from the centroid (mm) and area
    /// (mm²): a midpoint split halves the first two and quarters the
    /// third in each of its four pieces (each is the triangle scaled by
    /// ½, the middle one turned by 180°), so the gather reads them off
    /// the level.
    side_mm: f32,
    reach_mm: f32,
    area_mm2: f32,
}

/// The irradiance cells over a mesh's SSS surface: what a light and a
/// look's lighting give, whatever the profile (so a profile edit, or the
/// floor's d → 0 twin of a look, reuses them).
pub struct Cells {
    roots: Vec<Root>,
    /// The hierarchy over the roots; `clusters[0]` holds them all.
    clusters: Vec<Cluster>,
    /// Root indices in the clusters' leaf order.
    order: Vec<u32>,
    node_e: Vec<[f32; 3]>,
    /// Largest cell side (mm).
    pub spacing_mm: f64,
}

/// The cells and the profile, with the buckets that find the cells within
/// the profile's reach.
pub struct Cloud {
    cells: std::sync::Arc<Cells>,
    /// Each root's bucket range (lowest and highest bucket of its box).
    boxes: Vec<([i32; 3], [i32; 3])>,
    buckets: HashMap<[i32; 3], Vec<u32>>,
    bucket_mm: f64,
    reach_mm: f64,
    table: ProfileTable,
}

fn level_start(level: u32) -> usize {
    ((1usize << (2 * level)) - 1) / 3
}

impl Cloud {
    /// [`Cells::build`] and [`Cloud::new`] in one.
    pub fn build(
        positions_mm: &[Vec3],
        triangles: &[[u32; 3]],
        include: impl Fn(usize) -> bool + Sync,
        irradiance: &dyn SurfaceIrradiance,
        table: ProfileTable,
        spacing_mm: f64,
    ) -> Self {
        let cells = Cells::build(positions_mm, triangles, include, irradiance, spacing_mm);
        Self::new(std::sync::Arc::new(cells), table)
    }
}

impl Cells {
    /// Splits every triangle with `include` (corners in mm) into cells at
    /// most `spacing_mm` on a side, evaluates the irradiance at each cell's
    /// centroid (over the cell's width) and averages it up each triangle's
    /// quadtree.
    pub fn build(
        positions_mm: &[Vec3],
        triangles: &[[u32; 3]],
        include: impl Fn(usize) -> bool + Sync,
        irradiance: &dyn SurfaceIrradiance,
        spacing_mm: f64,
    ) -> Self {
        // Each included triangle's depth and its quadtree's place in one
        // array, so the trees are written where they stay (collecting them
        // and then copying them into one array held both at once: 324 MB
        // at the peak for the default head's 10.1 M cells, issue 23).
        let mut roots = Vec::new();
        let mut total = 0usize;
        for (t, tri) in triangles.iter().enumerate() {
            if !include(t) {
                continue;
            }
            let corners = tri.map(|i| positions_mm[i as usize]);
            let side = longest_side(&corners);
            let levels = if side > spacing_mm {
                ((side / spacing_mm).log2().ceil() as u32).min(10)
            } else {
                0
            };
            let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
            roots.push(Root {
                tri: t as u32,
                corners,
                levels,
                offset: total as u32,
                side_mm: side as f32,
                reach_mm: corners
                    .iter()
                    .map(|c| (*c - centre).length())
                    .fold(0.0, f32::max),
                area_mm2: 0.5
                    * (corners[1] - corners[0])
                        .cross(corners[2] - corners[0])
                        .length(),
            });
            total += level_start(levels + 1);
        }
        let mut node_e = vec![[0.0f32; 3]; total];
        let mut trees = Vec::with_capacity(roots.len());
        let mut rest = node_e.as_mut_slice();
        for r in &roots {
            let (tree, tail) = rest.split_at_mut(level_start(r.levels + 1));
            trees.push(tree);
            rest = tail;
        }
        start(1, roots.len());
        roots
            .par_iter()
            .zip(trees.into_par_iter())
            .for_each(|(root, nodes)| {
                step();
                let (t, levels, side) =
                    (root.tri as usize, root.levels, longest_side(&root.corners));
                // The cells (deepest level) in quadtree order, then each
                // level above as the mean of its four children.
                let bary0 = [Vec3::X, Vec3::Y, Vec3::Z];
                let mut stack = vec![(bary0, 0u32, 0usize)];
                // Midpoint splits halve every side: each cell's mean is
                // the irradiance at its width.
                let cell_mm = (side / (1u64 << levels) as f64) as f32;
                while let Some((b, level, i)) = stack.pop() {
                    if level == levels {
                        nodes[level_start(level) + i] =
                            irradiance.at(t, (b[0] + b[1] + b[2]) / 3.0, Footprint::width(cell_mm));
                        continue;
                    }
                    for (k, child) in split(b).into_iter().enumerate() {
                        stack.push((child, level + 1, 4 * i + k));
                    }
                }
                for level in (0..levels).rev() {
                    for i in 0..(1usize << (2 * level)) {
                        let first = level_start(level + 1) + 4 * i;
                        let mut m = [0.0f32; 3];
                        for k in 0..4 {
                            for c in 0..3 {
                                m[c] += 0.25 * nodes[first + k][c];
                            }
                        }
                        nodes[level_start(level) + i] = m;
                    }
                }
            });
        finish();
        let (clusters, order) = Cluster::build(&roots, &node_e);
        Self {
            roots,
            clusters,
            order,
            node_e,
            spacing_mm,
        }
    }

    /// Number of cells (the quadtrees' deepest nodes).
    pub fn len(&self) -> usize {
        self.roots.iter().map(|r| 1usize << (2 * r.levels)).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.roots.is_empty()
    }
}

/// The irradiance evaluated afresh during the gathers of neighbouring
/// pixels (one chunk of [`Cloud::gather_all`]'s probes, on one thread):
/// the corners of the cells beside x (each shared by up to six cells) and
/// the pieces below the cells, which the next pixels split the same way.
/// The key is every input of the evaluation (triangle, barycentric
/// coordinates, footprint, as bits), so a hit returns what evaluating
/// would: the frame is the same with or without it (issue 23).
#[derive(Default)]
pub struct Memo(std::cell::RefCell<HashMap<MemoKey, [f32; 3], rustc_hash::FxBuildHasher>>);

type MemoKey = (u32, [u32; 3], [u32; 7]);

impl Memo {
    fn at(
        &self,
        irradiance: &dyn SurfaceIrradiance,
        tri: u32,
        bary: Vec3,
        footprint: Footprint,
    ) -> [f32; 3] {
        let f = footprint;
        let key = (
            tri,
            bary.to_array().map(f32::to_bits),
            [
                f.width_mm,
                f.pixel_dx_mm.x,
                f.pixel_dx_mm.y,
                f.pixel_dx_mm.z,
                f.pixel_dy_mm.x,
                f.pixel_dy_mm.y,
                f.pixel_dy_mm.z,
            ]
            .map(f32::to_bits),
        );
        if let Some(v) = self.0.borrow().get(&key) {
            return *v;
        }
        let v = irradiance.at(tri as usize, bary, footprint);
        self.0.borrow_mut().insert(key, v);
        v
    }
}

/// The nearest point of the triangle to p (Ericson 2005, Real-Time
/// Collision Detection §5.1.5, by Voronoi regions).
fn closest_on_triangle(p: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

fn normal_of(c: [Vec3; 3]) -> Vec3 {
    (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero()
}

fn bucket_of(p: Vec3, size: f64) -> [i32; 3] {
    [p.x, p.y, p.z].map(|v| (v as f64 / size).floor() as i32)
}

#[cfg(test)]
mod ground_truth_tests;
