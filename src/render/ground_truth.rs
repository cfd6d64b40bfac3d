//! The ground truth the SSS methods are judged against: the diffusion
//! profile integrated over the mesh surface in 3D, none of whose
//! approximations a screen-space method shares.
//!
//! This is the two-pass point-cloud integration of Jensen & Buhler 2002
//! (§3): (1) irradiance samples over the whole SSS surface, seen or not,
//! each with its own normal and area; (2) for every shaded point x_o,
//! M(x_o) = Σ R(‖x_o − x_i‖) · E(x_i) · A_i with the true 3D distance.
//! Here the samples are the cells of a quadtree over every SSS triangle
//! (midpoint splits down to at most `spacing_mm` on a side, default
//! 0.5 mm; each node holds the mean irradiance of its cells), and the sum
//! is an adaptive quadrature over that tree rather than Jensen & Buhler's
//! octree clustering:
//! - a node counts as one piece, by the edge-midpoint rule (exact for
//!   quadratics on a triangle), when its side is at most its distance
//!   (θ = 1) and at most √(24 τ ρ/|ρ''|) with τ = 3.4 %: for an exponential
//!   of length λ that is 0.9 λ, where the rule's error is about 1 % of the
//!   local density ρ (ρ'' numerically, per channel, ignoring a channel
//!   where ρ is under 1 % of its mean density inside its median radius);
//!   otherwise it is split into four;
//! - cells at and beside x_o (within three sides) are integrated exactly in
//!   polar coordinates about x_o through the profile's CDF (so the 1/r core,
//!   a Dirac part, Jimenez 2012's 1 − strength, and a cell behind x_o are
//!   exact); where such a cell's corners differ from its mean by more than
//!   2 % it is split and its pieces' irradiance evaluated afresh, so shadow
//!   edges stay sharp at the core; splitting stops at ε = 2 % of the
//!   profile's narrowest 25 %-energy radius;
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

use crate::model::RadialProfile;
use glam::Vec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// A piece is at most this fraction of its distance.
const THETA: f64 = 1.0;
/// Sets the largest piece against the profile's local length (see the
/// module): √(24 τ) = 0.9 λ for an exponential of length λ.
const TAU: f64 = 0.034;
/// Density (relative to a channel's mean inside its median radius) below
/// which that channel's accuracy stops setting the cell size.
const FLOOR: f64 = 1e-2;
/// Energy fraction inside the truncation radius, per channel.
pub const ENERGY_FRACTION: f64 = 0.999;

/// The profile as the gather reads it: normalised density ρ_c(r) =
/// R_c(r)/total_c (mm⁻²), the CDF, and the largest piece side at
/// each distance, on a logarithmic grid of radii.
#[derive(Debug, Clone)]
pub struct ProfileTable {
    ln_r0: f64,
    inv_step: f64,
    density: Vec<[f32; 3]>,
    cdf: Vec<[f32; 3]>,
    /// CDF at r = 0 (a Dirac part's share) and the grid's first radius:
    /// below it the CDF runs linearly from the one to the other.
    cdf_zero: [f32; 3],
    r0_mm: f64,
    leaf_mm: Vec<f32>,
    /// Radius (mm) beyond which nothing is summed: the widest channel's
    /// [`ENERGY_FRACTION`] radius.
    pub r_max_mm: f64,
    /// Splitting stops below this side (mm).
    pub epsilon_mm: f64,
}

const TABLE_SIZE: usize = 2048;

impl ProfileTable {
    pub fn new(profile: &dyn RadialProfile) -> Self {
        let total = profile.total_reflectance();
        let live: Vec<usize> = (0..3).filter(|&c| total[c] > 0.0).collect();
        let r999 = profile.radius_for_energy(ENERGY_FRACTION);
        let r25 = profile.radius_for_energy(0.25);
        let r50 = profile.radius_for_energy(0.5);
        let r_max = live.iter().map(|&c| r999[c]).fold(0.0, f64::max).max(1e-6);
        let narrow = live
            .iter()
            .map(|&c| r25[c].max(1e-6 * r_max))
            .fold(f64::INFINITY, f64::min)
            .min(r_max);
        let epsilon = 0.02 * narrow;
        let r0 = 0.25 * epsilon;
        let ln_r0 = r0.ln();
        let step = ((1.01 * r_max).ln() - ln_r0) / (TABLE_SIZE - 1) as f64;
        let radii: Vec<f64> = (0..TABLE_SIZE)
            .map(|i| (ln_r0 + step * i as f64).exp())
            .collect();
        let norm = |c: usize| if total[c] > 0.0 { 1.0 / total[c] } else { 0.0 };
        let rho: Vec<[f64; 3]> = radii
            .iter()
            .map(|&r| {
                let v = profile.reflectance(r);
                [0, 1, 2].map(|c| v[c] * norm(c))
            })
            .collect();
        let cdf = radii
            .iter()
            .map(|&r| {
                let v = profile.cdf(r);
                [0, 1, 2].map(|c| if total[c] > 0.0 { v[c] as f32 } else { 1.0 })
            })
            .collect();
        // Density below which a channel's accuracy does not matter: a
        // hundredth of its mean density inside its median radius.
        let floor =
            [0, 1, 2].map(|c| FLOOR * 0.5 / (std::f64::consts::PI * r50[c].powi(2).max(1e-300)));
        let leaf_mm = (0..TABLE_SIZE)
            .map(|i| {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(TABLE_SIZE - 1));
                if a == i || b == i {
                    return f32::INFINITY;
                }
                let (ra, r, rb) = (radii[a], radii[i], radii[b]);
                live.iter()
                    .map(|&c| {
                        let d2 = 2.0
                            * ((rho[b][c] - rho[i][c]) / (rb - r)
                                - (rho[i][c] - rho[a][c]) / (r - ra))
                            / (rb - ra);
                        let s = (24.0 * TAU * (rho[i][c] + floor[c]) / d2.abs().max(1e-300)).sqrt();
                        s as f32
                    })
                    .fold(f32::INFINITY, f32::min)
            })
            .collect();
        let at_zero = profile.cdf(0.0);
        let cdf_zero = [0, 1, 2].map(|c| {
            if total[c] > 0.0 {
                at_zero[c] as f32
            } else {
                1.0
            }
        });
        Self {
            cdf_zero,
            r0_mm: r0,
            ln_r0,
            inv_step: 1.0 / step,
            density: rho.iter().map(|v| v.map(|x| x as f32)).collect(),
            cdf,
            leaf_mm,
            r_max_mm: r_max,
            epsilon_mm: epsilon,
        }
    }

    /// A hash of the table: equal tables give equal clouds.
    pub fn fingerprint(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for v in self.density.iter().chain(&self.cdf) {
            v.map(f32::to_bits).hash(&mut h);
        }
        self.r_max_mm.to_bits().hash(&mut h);
        h.finish()
    }

    /// (index, fraction) of r on the grid, clamped to its ends.
    fn locate(&self, r_mm: f64) -> (usize, f32) {
        let t = ((r_mm.max(1e-300).ln() - self.ln_r0) * self.inv_step).max(0.0);
        let i = (t as usize).min(TABLE_SIZE - 2);
        (i, (t - i as f64).min(1.0) as f32)
    }

    fn lerp(v: &[[f32; 3]], (i, f): (usize, f32)) -> [f32; 3] {
        [0, 1, 2].map(|c| v[i][c] + f * (v[i + 1][c] - v[i][c]))
    }

    /// ρ_c(r) = R_c(r)/total_c in mm⁻².
    pub fn density(&self, r_mm: f64) -> [f32; 3] {
        Self::lerp(&self.density, self.locate(r_mm))
    }

    /// Fraction of each channel's energy within r.
    pub fn cdf(&self, r_mm: f64) -> [f32; 3] {
        if r_mm < self.r0_mm {
            let f = (r_mm.max(0.0) / self.r0_mm) as f32;
            return [0, 1, 2].map(|c| self.cdf_zero[c] + f * (self.cdf[0][c] - self.cdf_zero[c]));
        }
        Self::lerp(&self.cdf, self.locate(r_mm))
    }

    /// Largest side (mm) of a cell used as one sample at distance r.
    pub fn leaf_mm(&self, r_mm: f64) -> f64 {
        let (i, _) = self.locate(r_mm);
        (self.leaf_mm[i] as f64).min(THETA * r_mm)
    }
}

/// The ground truth's progress in this process: [triangles or points done,
/// in all, phase] with phase 1 while the irradiance cloud is built and 2
/// while the gather runs, 0 when idle (for the editor's progress bar).
pub static PROGRESS: [std::sync::atomic::AtomicU32; 3] = [
    std::sync::atomic::AtomicU32::new(0),
    std::sync::atomic::AtomicU32::new(0),
    std::sync::atomic::AtomicU32::new(0),
];

/// (phase, fraction done) of the ground truth running now, if any.
pub fn progress() -> Option<(u32, f32)> {
    use std::sync::atomic::Ordering;
    let phase = PROGRESS[2].load(Ordering::Relaxed);
    let total = PROGRESS[1].load(Ordering::Relaxed);
    (phase > 0 && total > 0).then(|| {
        (
            phase,
            (PROGRESS[0].load(Ordering::Relaxed) as f32 / total as f32).min(1.0),
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

/// What the SSS methods blur, at a point of an SSS triangle: the scene
/// pass's diffuse target (irradiance/π × albedo^pre × mask), linear RGB.
pub trait SurfaceIrradiance: Sync {
    fn at(&self, triangle: usize, bary: Vec3) -> [f32; 3];
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
}

/// The irradiance samples over a mesh's SSS surface and the profile.
pub struct Cloud {
    roots: Vec<Root>,
    /// Each root's bucket range (lowest and highest bucket of its box).
    boxes: Vec<([i32; 3], [i32; 3])>,
    node_e: Vec<[f32; 3]>,
    buckets: HashMap<[i32; 3], Vec<u32>>,
    bucket_mm: f64,
    reach_mm: f64,
    table: ProfileTable,
    /// Largest cell side (mm).
    pub spacing_mm: f64,
}

fn level_start(level: u32) -> usize {
    ((1usize << (2 * level)) - 1) / 3
}

impl Cloud {
    /// Splits every triangle with `include` (corners in mm) into cells at
    /// most `spacing_mm` on a side, evaluates the irradiance at each cell's
    /// centroid and averages it up each triangle's quadtree.
    pub fn build(
        positions_mm: &[Vec3],
        triangles: &[[u32; 3]],
        include: impl Fn(usize) -> bool + Sync,
        irradiance: &dyn SurfaceIrradiance,
        table: ProfileTable,
        spacing_mm: f64,
    ) -> Self {
        start(1, triangles.len());
        let trees: Vec<(Root, Vec<[f32; 3]>)> = triangles
            .par_iter()
            .enumerate()
            .inspect(|_| step())
            .filter(|(t, _)| include(*t))
            .map(|(t, tri)| {
                let corners = tri.map(|i| positions_mm[i as usize]);
                let side = longest_side(&corners);
                let levels = if side > spacing_mm {
                    (side / spacing_mm).log2().ceil() as u32
                } else {
                    0
                };
                let levels = levels.min(10);
                // The cells (deepest level) in quadtree order, then each
                // level above as the mean of its four children.
                let mut nodes = vec![[0.0f32; 3]; level_start(levels + 1)];
                let bary0 = [Vec3::X, Vec3::Y, Vec3::Z];
                let mut stack = vec![(bary0, 0u32, 0usize)];
                while let Some((b, level, i)) = stack.pop() {
                    if level == levels {
                        nodes[level_start(level) + i] =
                            irradiance.at(t, (b[0] + b[1] + b[2]) / 3.0);
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
                (
                    Root {
                        tri: t as u32,
                        corners,
                        levels,
                        offset: 0,
                    },
                    nodes,
                )
            })
            .collect();
        finish();
        let mut roots = Vec::with_capacity(trees.len());
        let mut node_e = Vec::new();
        for (mut root, nodes) in trees {
            root.offset = node_e.len() as u32;
            node_e.extend(nodes);
            roots.push(root);
        }
        // Each root goes into every bucket its bounding box touches; a query
        // visits a root once, from the first bucket it shares with it.
        let bucket_mm = (0.5 * table.r_max_mm).max(spacing_mm);
        let mut buckets: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        let mut boxes = Vec::with_capacity(roots.len());
        for (i, r) in roots.iter().enumerate() {
            let lo = bucket_of(r.corners[0].min(r.corners[1]).min(r.corners[2]), bucket_mm);
            let hi = bucket_of(r.corners[0].max(r.corners[1]).max(r.corners[2]), bucket_mm);
            for bx in lo[0]..=hi[0] {
                for by in lo[1]..=hi[1] {
                    for bz in lo[2]..=hi[2] {
                        buckets.entry([bx, by, bz]).or_default().push(i as u32);
                    }
                }
            }
            boxes.push((lo, hi));
        }
        Self {
            boxes,
            reach_mm: table.r_max_mm,
            roots,
            node_e,
            buckets,
            bucket_mm,
            table,
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

    pub fn table(&self) -> &ProfileTable {
        &self.table
    }

    /// Σ R(‖x − y‖)·E(y)·dA / total per channel over the SSS surface: the
    /// scattered diffuse at the surface point `x_mm`.
    pub fn gather(&self, x_mm: Vec3, irradiance: &dyn SurfaceIrradiance) -> [f32; 3] {
        let reach = self.reach_mm as f32;
        let lo = bucket_of(x_mm - Vec3::splat(reach), self.bucket_mm);
        let hi = bucket_of(x_mm + Vec3::splat(reach), self.bucket_mm);
        let mut acc = [0.0f64; 3];
        for bx in lo[0]..=hi[0] {
            for by in lo[1]..=hi[1] {
                for bz in lo[2]..=hi[2] {
                    let Some(list) = self.buckets.get(&[bx, by, bz]) else {
                        continue;
                    };
                    for &i in list {
                        // Visit the root from the first bucket of the
                        // query's range that holds it.
                        let (blo, _) = self.boxes[i as usize];
                        let first = [0, 1, 2].map(|k| blo[k].max(lo[k]));
                        if first != [bx, by, bz] {
                            continue;
                        }
                        let r = &self.roots[i as usize];
                        let node = Node {
                            bary: [Vec3::X, Vec3::Y, Vec3::Z],
                            corners: r.corners,
                            level: 0,
                            index: 0,
                        };
                        self.integrate(x_mm, r, node, irradiance, &mut acc);
                    }
                }
            }
        }
        acc.map(|v| v as f32)
    }

    /// The gather at many points, in parallel.
    pub fn gather_all(
        &self,
        points_mm: &[Vec3],
        irradiance: &dyn SurfaceIrradiance,
    ) -> Vec<[f32; 3]> {
        start(2, points_mm.len());
        let out = points_mm
            .par_iter()
            .map(|&x| {
                step();
                self.gather(x, irradiance)
            })
            .collect();
        finish();
        out
    }

    /// Adds the integral of ρ(‖x − y‖)·E(y) over one quadtree node (or,
    /// below the cells, one piece of a cell).
    fn integrate(
        &self,
        x: Vec3,
        root: &Root,
        node: Node,
        irradiance: &dyn SurfaceIrradiance,
        acc: &mut [f64; 3],
    ) {
        let corners = node.corners;
        let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
        let side = longest_side(&corners);
        let dist = (x - centre).length() as f64;
        // Truncate at r_max: a piece across it counts with the fraction of
        // its extent inside (the density there is the profile's last
        // 0.1 %, so this costs nothing measurable).
        // (Every point of a triangle lies within 0.58 of its longest side
        // of its centroid.)
        let reach = 0.58 * side;
        let inside = ((self.table.r_max_mm - (dist - reach)) / (2.0 * reach)).clamp(0.0, 1.0);
        if inside <= 0.0 {
            return;
        }
        // The piece's irradiance: the quadtree's mean down to the cells;
        // below them (only ever beside x) evaluated afresh.
        let cached = node.level <= root.levels;
        let e = if cached {
            self.node_e[root.offset as usize + level_start(node.level) + node.index]
        } else {
            irradiance.at(
                root.tri as usize,
                (node.bary[0] + node.bary[1] + node.bary[2]) / 3.0,
            )
        };
        if node.level >= root.levels && dist < 3.0 * side {
            // A cell (or piece of one) at or beside x. Where the irradiance
            // is even across it (its corners within 2 % of its mean, or it
            // is already tiny), the profile is integrated exactly in polar
            // coordinates about x (`polar_weight`); otherwise it is split
            // and each piece evaluated afresh, so a shadow edge stays sharp
            // at the profile's core.
            let even = side <= self.table.epsilon_mm
                || node.bary.iter().all(|b| {
                    let v = irradiance.at(root.tri as usize, *b);
                    (0..3).all(|c| (v[c] - e[c]).abs() <= 0.02 * e[c].abs().max(1e-6))
                });
            if even {
                if e != [0.0; 3] {
                    let w = self.polar_weight(x, corners);
                    for c in 0..3 {
                        acc[c] += e[c] as f64 * w[c];
                    }
                }
                return;
            }
        } else if side <= self.table.leaf_mm(dist) {
            if e == [0.0; 3] {
                return;
            }
            let area = 0.5
                * (corners[1] - corners[0])
                    .cross(corners[2] - corners[0])
                    .length() as f64;
            // The edge-midpoint rule, exact for quadratics on a triangle.
            let mut w = [0.0f64; 3];
            for k in 0..3 {
                let m = 0.5 * (corners[k] + corners[(k + 1) % 3]);
                let d = self.table.density((x - m).length() as f64);
                for c in 0..3 {
                    w[c] += d[c] as f64 / 3.0;
                }
            }
            for c in 0..3 {
                acc[c] += e[c] as f64 * w[c] * area * inside;
            }
            return;
        }
        let bary = split(node.bary);
        let pieces = split(corners);
        for k in 0..4 {
            let child = Node {
                bary: bary[k],
                corners: pieces[k],
                level: node.level + 1,
                index: if node.level < root.levels {
                    4 * node.index + k
                } else {
                    0
                },
            };
            self.integrate(x, root, child, irradiance, acc);
        }
    }
}

/// A node of a root's quadtree during the gather.
#[derive(Debug, Clone, Copy)]
struct Node {
    bary: [Vec3; 3],
    corners: [Vec3; 3],
    level: u32,
    index: usize,
}

impl Cloud {
    /// ∫ ρ(‖x − y‖) dA over the triangle `corners`. With x at height h
    /// above the triangle's plane and x' its foot, ‖x − y‖² = r² + h² for
    /// r = ‖x' − y‖, and ∫₀^R ρ(√(r² + h²)) r dr = (CDF(√(R² + h²)) −
    /// CDF(h))/2π. The triangle is the signed sum over its edges (a, b) of
    /// the triangles (x', a, b), each integrated over the angle φ it spans;
    /// with φ running along the edge P(u) = a + u(b − a), dφ = |(a − x') ×
    /// (b − a)| / ‖P(u) − x'‖² du; 8-point Gauss–Legendre in u. Exact for
    /// the 1/r core, for a Dirac part (at h = 0) and for a cell behind x
    /// (a slab's far face), and additive over cells, where a disk of equal
    /// area per cell is not (a fan of thin cells around x, as at a
    /// sphere's pole, summed their disks' √area and counted the core
    /// hundreds of times).
    fn polar_weight(&self, x: Vec3, corners: [Vec3; 3]) -> [f64; 3] {
        let n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let n2 = n.length_squared();
        if n2 <= 0.0 {
            return [0.0; 3];
        }
        let along = (x - corners[0]).dot(n) / n2;
        let h = (along.abs() * n2.sqrt()) as f64;
        // Under 1 µm off the plane is the f32 depth reconstruction's noise
        // (~0.1 µm), not a surface behind x: x is on the cell.
        let h = if h < 1e-3 { 0.0 } else { h };
        let cdf_h = if h > 0.0 { self.table.cdf(h) } else { [0.0; 3] };
        let x = x - n * along;
        let (nodes, weights) = crate::model::quad::gl8();
        let mut w = [0.0f64; 3];
        for k in 0..3 {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let span = (a - x).cross(b - a);
            let sign = span.dot(n).signum() as f64;
            let span_len = span.length() as f64;
            if span_len <= 0.0 {
                continue;
            }
            for (t, q) in nodes.iter().zip(weights) {
                // gl8 is on [−1, 1]: u = (t + 1)/2, du = dt/2.
                let u = 0.5 * (t + 1.0);
                let d = (a + (b - a) * u as f32 - x).length() as f64;
                let cdf = self.table.cdf((d * d + h * h).sqrt());
                let dphi = 0.5 * q * span_len / (d * d).max(1e-300);
                for c in 0..3 {
                    w[c] += sign * (cdf[c] - cdf_h[c]) as f64 * dphi / (2.0 * std::f64::consts::PI);
                }
            }
        }
        w
    }
}

fn bucket_of(p: Vec3, size: f64) -> [i32; 3] {
    [p.x, p.y, p.z].map(|v| (v as f64 / size).floor() as i32)
}

#[cfg(test)]
mod ground_truth_tests;
