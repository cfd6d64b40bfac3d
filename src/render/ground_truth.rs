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

use crate::model::RadialProfile;
use glam::Vec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// A piece is at most this fraction of its distance.
const THETA: f64 = 1.0;
/// Sets the largest piece against the profile's local length (see the
/// module): √(24 τ) = 1.8 λ for an exponential of length λ.
const TAU: f64 = 0.136;
/// Density (relative to a channel's mean inside its median radius) below
/// which that channel's accuracy stops setting the cell size.
const FLOOR: f64 = 1e-2;
/// A near piece is split where a corner's irradiance differs from the
/// piece's mean by more than this fraction of it, over the piece's share
/// of the profile's energy (at most 1).
const UNEVEN: f32 = 0.01;
/// Probes gathered in turn on one thread with one [`Memo`]: neighbours in
/// the order given (the reference pass orders its pixels in tiles).
pub const MEMO_CHUNK: usize = 64;
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
    /// dρ/dr (mm⁻³) by central differences on the grid, for the
    /// clusters' expansion ([`Cluster`]).
    d1: Vec<[f32; 3]>,
    /// The profile's local decay length |ρ/ρ'| (mm), the shortest over
    /// the channels that are over a hundredth of their accuracy floor.
    decay_mm: Vec<f32>,
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
        // Central differences on the uneven grid (one-sided at its ends).
        let d1: Vec<[f32; 3]> = (0..TABLE_SIZE)
            .map(|i| {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(TABLE_SIZE - 1));
                [0, 1, 2].map(|c| ((rho[b][c] - rho[a][c]) / (radii[b] - radii[a])) as f32)
            })
            .collect();
        let decay_mm = (0..TABLE_SIZE)
            .map(|i| {
                live.iter()
                    .filter(|&&c| rho[i][c] >= 0.01 * floor[c])
                    .map(|&c| (rho[i][c] / (d1[i][c] as f64).abs().max(1e-300)) as f32)
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
            d1,
            decay_mm,
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
        let t = ((fast_ln(r_mm as f32) as f64 - self.ln_r0) * self.inv_step).max(0.0);
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

    /// The profile's local decay length at r (mm).
    pub fn decay_mm(&self, r_mm: f64) -> f64 {
        self.decay_mm[self.locate(r_mm).0] as f64
    }

    /// ρ and dρ/dr per channel at r.
    pub fn density_and_slope(&self, r_mm: f64) -> [[f32; 3]; 2] {
        let at = self.locate(r_mm);
        [Self::lerp(&self.density, at), Self::lerp(&self.d1, at)]
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

/// ln x for the table's index, without libm's f64 log (a tenth of the
/// gather's time): x = m·2^e with m in [√½, √2), ln m = 2 atanh(z) for
/// z = (m − 1)/(m + 1), |z| ≤ 0.172, to z⁷ (the series' next term is
/// under 3e-8; `fast_ln_matches_ln` holds it to 4e-6 against std's ln,
/// f32's rounding, a thousandth of a table step). x is clamped to [1e-30, f32::MAX].
fn fast_ln(x: f32) -> f32 {
    let bits = x.clamp(1e-30, f32::MAX).to_bits();
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > std::f32::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    e as f32 * std::f32::consts::LN_2
        + 2.0 * z * (1.0 + z2 * (1.0 / 3.0 + z2 * (1.0 / 5.0 + z2 / 7.0)))
}

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
            roots.push(Root {
                tri: t as u32,
                corners,
                levels,
                offset: total as u32,
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

impl Cloud {
    /// The cells with the profile `table`: each root goes into every bucket
    /// its bounding box touches (buckets half the profile's reach wide); a
    /// query visits a root once, from the first bucket it shares with it.
    pub fn new(cells: std::sync::Arc<Cells>, table: ProfileTable) -> Self {
        let bucket_mm = (0.5 * table.r_max_mm).max(cells.spacing_mm);
        let mut buckets: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        let mut boxes = Vec::with_capacity(cells.roots.len());
        for (i, r) in cells.roots.iter().enumerate() {
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
            cells,
            buckets,
            bucket_mm,
            table,
        }
    }

    /// The irradiance cells (shared by clouds of other profiles).
    pub fn cells(&self) -> &std::sync::Arc<Cells> {
        &self.cells
    }

    /// Number of cells (the quadtrees' deepest nodes).
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    pub fn table(&self) -> &ProfileTable {
        &self.table
    }

    /// Calls `visit` once for each root whose bucket range meets the box of
    /// half-width `reach_mm` about `x_mm`.
    fn roots_near(&self, x_mm: Vec3, reach_mm: f32, mut visit: impl FnMut(&Root)) {
        let lo = bucket_of(x_mm - Vec3::splat(reach_mm), self.bucket_mm);
        let hi = bucket_of(x_mm + Vec3::splat(reach_mm), self.bucket_mm);
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
                        if first == [bx, by, bz] {
                            visit(&self.cells.roots[i as usize]);
                        }
                    }
                }
            }
        }
    }

    /// The SSS triangle nearest x within `within_mm` (its corners), and
    /// its nearest point to x.
    fn nearest(&self, x_mm: Vec3, within_mm: f32) -> Option<([Vec3; 3], Vec3)> {
        let mut best = (within_mm, None);
        self.roots_near(x_mm, within_mm, |r| {
            let q = closest_on_triangle(x_mm, r.corners);
            let d = (q - x_mm).length();
            if d < best.0 {
                best = (d, Some((r.corners, q)));
            }
        });
        best.1
    }

    /// The probe's point on the SSS surface and its pixel's surface steps
    /// (mm) there. The rasteriser snaps vertices to a fraction of a pixel
    /// (lavapipe: 1/256), so where the surface is seen at a grazing angle
    /// the depth it interpolates at a pixel's centre puts the point off
    /// the triangle by microns (5.7 µm at 75°, measured): the point is
    /// moved onto the nearest triangle when that is within 1 % of the
    /// pixel's footprint (else it stays, off the skin, with no footprint).
    fn on_surface(&self, probe: &Probe) -> (Vec3, Vec3, Vec3) {
        let reach = 0.01
            * (probe.ray_dx.length().max(probe.ray_dy.length()))
            * (probe.x_mm - probe.camera_mm).length()
            / probe.ray.length().max(1e-12);
        let Some((c, q)) = self.nearest(probe.x_mm, reach.max(1e-3)) else {
            return (probe.x_mm, Vec3::ZERO, Vec3::ZERO);
        };
        let (dx, dy) = probe.pixel_steps_mm(normal_of(c));
        let within = 0.01 * dx.length().max(dy.length()) + 1e-3;
        if (q - probe.x_mm).length() <= within {
            (q, dx, dy)
        } else {
            (probe.x_mm, Vec3::ZERO, Vec3::ZERO)
        }
    }

    /// The gather averaged over k × k points of the probe's pixel on its own
    /// surface (each subpixel's ray met with the plane of the pixel's
    /// triangle, then moved to the nearest point of the SSS surface), each
    /// with the maps read over the pixel's footprint: the check that one
    /// point per pixel is enough (k = 1 is [`Cloud::gather`]). `None` where the
    /// pixel's footprint is not one smooth surface (a subpixel's point lies
    /// off the surface by over 5 % of the pixel, or on a facet turned by
    /// over 30°: a silhouette, a crease, the lips' line), where a pixel's centre stands for a mix of
    /// surfaces in every rasteriser, the scene pass's included, and a
    /// finer grid changes the image whatever the method.
    pub fn gather_supersampled(
        &self,
        probe: &Probe,
        k: u32,
        irradiance: &dyn SurfaceIrradiance,
    ) -> Option<[f32; 3]> {
        self.supersampled_with(probe, k, irradiance, &Memo::default())
    }

    fn supersampled_with(
        &self,
        probe: &Probe,
        k: u32,
        irradiance: &dyn SurfaceIrradiance,
        memo: &Memo,
    ) -> Option<[f32; 3]> {
        let Some((corners, _)) = self.nearest(probe.x_mm, 10e-3).filter(|_| k > 1) else {
            return Some(self.gather_with(probe, irradiance, memo));
        };
        let n = normal_of(corners);
        let (dx, dy) = probe.pixel_steps_mm(n);
        let tolerance = 0.05 * dx.length().max(dy.length()) + 1e-3;
        let mut acc = [0.0f64; 3];
        for j in 0..k {
            for i in 0..k {
                let (fx, fy) = (
                    (i as f32 + 0.5) / k as f32 - 0.5,
                    (j as f32 + 0.5) / k as f32 - 0.5,
                );
                let ray = probe.ray + probe.ray_dx * fx + probe.ray_dy * fy;
                let t = (probe.x_mm - probe.camera_mm).dot(n) / ray.dot(n);
                let on_plane = probe.camera_mm + ray * t;
                let (corners, x) = self.nearest(on_plane, tolerance)?;
                // A crease (the lips' line, an eyelid's rim) within the
                // footprint: the surface turns by over 30° under the pixel.
                if normal_of(corners).dot(n) < 0.866 {
                    return None;
                }
                // The maps are read over the pixel's own footprint at every
                // point (the scene pass's filter, which defines the pixel's
                // value for every method): finer points test the gather's
                // spatial sampling, not a finer texture filter.
                let sub = Probe {
                    x_mm: x,
                    ray,
                    ..*probe
                };
                let v = self.gather_with(&sub, irradiance, memo);
                for c in 0..3 {
                    acc[c] += v[c] as f64;
                }
            }
        }
        Some(acc.map(|v| (v / (k * k) as f64) as f32))
    }

    /// Σ R(‖x − y‖)·E(y)·dA / total per channel over the SSS surface: the
    /// scattered diffuse at the probe's point, for the width of surface its
    /// pixel covers (the pieces beside x are read at least that wide: the
    /// pixel's mean, as the GPU's mip level makes it).
    pub fn gather(&self, probe: &Probe, irradiance: &dyn SurfaceIrradiance) -> [f32; 3] {
        self.gather_with(probe, irradiance, &Memo::default())
    }

    /// [`Cloud::gather`] with the evaluations of earlier gathers in `memo`.
    fn gather_with(
        &self,
        probe: &Probe,
        irradiance: &dyn SurfaceIrradiance,
        memo: &Memo,
    ) -> [f32; 3] {
        let (x, dx, dy) = self.on_surface(probe);
        let pixel = Footprint {
            pixel_dx_mm: dx,
            pixel_dy_mm: dy,
            width_mm: 0.0,
        };
        let query = Query {
            x,
            pixel,
            profile: Scaled {
                table: &self.table,
                m: (probe.profile_scale as f64).clamp(1e-3, 1.0),
            },
            memo,
        };
        let mut acc = [0.0f64; 3];
        let reach = self.reach_mm * query.profile.m;
        if !self.cells.clusters.is_empty() {
            self.visit(&query, 0, reach, irradiance, &mut acc);
        }
        acc.map(|v| v as f32)
    }

    /// The gather at many probes, in parallel, each over k × k points of
    /// its pixel ([`Cloud::gather_supersampled`]); `None` when `cancel`
    /// was set meanwhile (it is read before each chunk of probes).
    pub fn gather_all(
        &self,
        probes: &[Probe],
        supersample: u32,
        irradiance: &dyn SurfaceIrradiance,
        cancel: &std::sync::atomic::AtomicBool,
    ) -> Option<Vec<Option<[f32; 3]>>> {
        let cancelled = || cancel.load(std::sync::atomic::Ordering::Relaxed);
        start(2, probes.len());
        let out = probes
            .par_chunks(MEMO_CHUNK)
            .flat_map_iter(|chunk| {
                if cancelled() {
                    return vec![None; chunk.len()];
                }
                let memo = Memo::default();
                chunk
                    .iter()
                    .map(|p| {
                        step();
                        self.supersampled_with(p, supersample, irradiance, &memo)
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        finish();
        (!cancelled()).then_some(out)
    }

    /// Adds the integral over cluster `i`: by its expansion where it is
    /// small enough for the rule at its distance, else over its children
    /// or, at a leaf, over each root's quadtree.
    fn visit(
        &self,
        q: &Query,
        i: usize,
        reach_mm: f64,
        irradiance: &dyn SurfaceIrradiance,
        acc: &mut [f64; 3],
    ) {
        let cl = &self.cells.clusters[i];
        let to = cl.centre - q.x;
        let d = to.length() as f64;
        let radius = cl.radius as f64;
        if d - radius > reach_mm {
            return;
        }
        // The criteria at the cluster's nearest point: the profile there
        // is the steepest the cluster meets.
        let near = (d - radius).max(0.0);
        if radius <= CLUSTER_THETA * d
            && radius <= CLUSTER_LEAF * q.profile.leaf_mm(near)
            && radius <= CLUSTER_DECAY * q.profile.decay_mm(near)
        {
            let [rho, d1] = q.profile.density_and_slope(d);
            let u = to / d as f32;
            for ch in 0..3 {
                let term = cl.power[ch] * rho[ch] + d1[ch] * u.dot(cl.dipole[ch]);
                acc[ch] += term as f64;
            }
            return;
        }
        match cl.kind {
            ClusterKind::Inner(left) => {
                self.visit(q, left as usize, reach_mm, irradiance, acc);
                self.visit(q, left as usize + 1, reach_mm, irradiance, acc);
            }
            ClusterKind::Leaf { first, count } => {
                for &k in &self.cells.order[first as usize..(first + count) as usize] {
                    let r = &self.cells.roots[k as usize];
                    let node = Node {
                        bary: [Vec3::X, Vec3::Y, Vec3::Z],
                        corners: r.corners,
                        level: 0,
                        index: 0,
                    };
                    self.integrate(q, r, node, irradiance, acc);
                }
            }
        }
    }

    /// Adds the integral of ρ(‖x − y‖)·E(y) over one quadtree node (or,
    /// below the cells, one piece of a cell).
    fn integrate(
        &self,
        q: &Query,
        root: &Root,
        node: Node,
        irradiance: &dyn SurfaceIrradiance,
        acc: &mut [f64; 3],
    ) {
        let (x, pixel, table) = (q.x, q.pixel, &q.profile);
        let corners = node.corners;
        let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
        let side = longest_side(&corners);
        let dist = (x - centre).length() as f64;
        // Truncate at r_max: a piece across it counts with the fraction of
        // its extent inside (the density there is the profile's last
        // 0.1 %, so this costs nothing measurable).
        // The farthest point of a triangle from its centroid is a corner
        // (up to 2/3 of the longest side, for a sliver: a fixed 0.58 skipped
        // slivers' tips beside x when r_max is short).
        let reach = corners
            .iter()
            .map(|c| (*c - centre).length() as f64)
            .fold(0.0, f64::max)
            .max(1e-9);
        let inside = ((table.r_max_mm() - (dist - reach)) / (2.0 * reach)).clamp(0.0, 1.0);
        if inside <= 0.0 {
            return;
        }
        // The largest piece the edge-midpoint rule takes at this distance.
        let leaf_mm = table.leaf_mm(dist);
        let near = node.level >= root.levels && side > leaf_mm;
        // The piece's irradiance: the quadtree's mean down to the cells;
        // at x, where a piece is narrower than the pixel and within a
        // pixel of x, evaluated afresh over the pixel's footprint (the
        // pixel's mean, as the GPU's mip level makes it: the d → 0 limit);
        // below the cells (only ever beside x) afresh over the piece.
        let pixel_mm = pixel.pixel_dx_mm.length().max(pixel.pixel_dy_mm.length()) as f64;
        let by_pixel = near && pixel_mm > side && dist - reach < pixel_mm;
        let footprint = if by_pixel {
            Footprint {
                width_mm: side as f32,
                ..pixel
            }
        } else {
            Footprint::width(side as f32)
        };
        let e = if node.level <= root.levels && !by_pixel {
            self.cells.node_e[root.offset as usize + level_start(node.level) + node.index]
        } else {
            q.memo.at(
                irradiance,
                root.tri,
                (node.bary[0] + node.bary[1] + node.bary[2]) / 3.0,
                footprint,
            )
        };
        if near {
            // A cell (or piece of one) too wide for the rule at its
            // distance. Where the irradiance is even across it (below), the
            // profile is integrated exactly in polar coordinates about x
            // (`polar_weight`); otherwise it is split and each piece
            // evaluated afresh, so a shadow edge stays sharp at the
            // profile's core. The piece lies in the annulus about x from dist − reach to
            // dist + reach, so its share of each channel's energy is at
            // most that annulus's: a corner's difference from the mean
            // moves the sum by at most that much times the share.
            let (lo, hi) = (table.cdf((dist - reach).max(0.0)), table.cdf(dist + reach));
            let share = [0, 1, 2].map(|c| (hi[c] - lo[c]).max(0.0));
            let even = side <= table.epsilon_mm()
                || share.iter().all(|w| *w <= UNEVEN)
                || node.bary.iter().all(|b| {
                    let v = q.memo.at(irradiance, root.tri, *b, footprint);
                    (0..3).all(|c| (v[c] - e[c]).abs() * share[c] <= UNEVEN * e[c].abs().max(1e-6))
                });
            if even {
                if e != [0.0; 3] {
                    let w = table.polar_weight(x, corners);
                    for c in 0..3 {
                        acc[c] += e[c] as f64 * w[c];
                    }
                }
                return;
            }
        } else if side <= leaf_mm {
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
                let d = table.density((x - m).length() as f64);
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
            self.integrate(q, root, child, irradiance, acc);
        }
    }
}

/// A cluster is taken as one term where its radius is at most this
/// fraction of its distance,
const CLUSTER_THETA: f64 = 0.25;
/// this fraction of the largest piece the edge-midpoint rule takes at its
/// nearest point (a triangle of side s has a radius of s/√3 ≈ 0.58 s),
const CLUSTER_LEAF: f64 = 0.25;
/// and this fraction of the profile's decay length |ρ/ρ'| there. The three
/// were set together at 0.25, the largest value (of 0.5, 0.35, 0.25) at
/// which the sphere's closed form (`penners_table_is_the_ground_truths_sphere`,
/// 1e-3) and the plane's energy (≤ 100.05 %) hold: at 0.5 the sphere was
/// 1.5e-3 off and the plane 100.14 %.
const CLUSTER_DECAY: f64 = 0.25;
/// Roots in a leaf cluster at most.
const LEAF_ROOTS: usize = 4;

/// A node of the hierarchy over the SSS triangles (Jensen & Buhler 2002
/// §3.2 cluster the irradiance samples in an octree and take a distant
/// cluster as one sample; this is a binary tree split at the median of
/// the widest axis). A cluster far enough away counts by its expansion
/// about its area centroid c to first order in the irradiance's spread:
/// with u = (c − x)/d and d = ‖c − x‖,
///   ∫ ρ(‖y − x‖) E(y) dA ≈ P ρ(d) + ρ'(d) u·D,
/// for P = ∫E dA and D = ∫E (y − c) dA (the dipole: where in the cluster
/// its light lies). A second-order term ½ P tr(H Σ), with Σ the area's
/// covariance, was tried and made the plane's energy worse (102.6 % with
/// the criteria at the cluster's centre): the criteria below keep the
/// clusters small enough that the first-order sum is within the rule's
/// own error (0.03 % relative RMSE from the frame without clusters on the
/// default head's front view at 640 × 360).
#[derive(Debug, Clone, Copy)]
struct Cluster {
    centre: Vec3,
    /// Farthest corner of its triangles from `centre` (mm).
    radius: f32,
    /// P per channel (irradiance × mm²).
    power: [f32; 3],
    /// D per channel (irradiance × mm³).
    dipole: [Vec3; 3],
    kind: ClusterKind,
}

#[derive(Debug, Clone, Copy)]
enum ClusterKind {
    /// Children at `left` and `left + 1`.
    Inner(u32),
    /// Roots `order[first..first + count]`.
    Leaf { first: u32, count: u32 },
}

/// One root's part of a cluster: area, centroid, and P and D about the
/// centroid.
#[derive(Clone, Copy)]
struct Moments {
    area: f64,
    centre: glam::DVec3,
    power: [f64; 3],
    dipole: [glam::DVec3; 3],
}

impl Moments {
    fn of_root(r: &Root, node_e: &[[f32; 3]]) -> Self {
        let c = r.corners.map(|v| v.as_dvec3());
        let area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).length();
        let g = (c[0] + c[1] + c[2]) / 3.0;
        let e = node_e[r.offset as usize];
        // D about g from the quadtree's first level: each quarter's mean
        // at its centroid (the middle quarter's centroid is g).
        let mut dipole = [glam::DVec3::ZERO; 3];
        if r.levels >= 1 {
            for (k, quarter) in split(r.corners).iter().enumerate() {
                let gk = ((quarter[0] + quarter[1] + quarter[2]) / 3.0).as_dvec3();
                let ek = node_e[r.offset as usize + 1 + k];
                for ch in 0..3 {
                    dipole[ch] += (gk - g) * (0.25 * area * ek[ch] as f64);
                }
            }
        }
        Self {
            area,
            centre: g,
            power: e.map(|v| v as f64 * area),
            dipole,
        }
    }

    /// The union's moments about its own centroid.
    fn merge(parts: impl Iterator<Item = Moments> + Clone) -> Self {
        let area: f64 = parts.clone().map(|m| m.area).sum();
        let centre = if area > 0.0 {
            parts
                .clone()
                .map(|m| m.centre * m.area)
                .sum::<glam::DVec3>()
                / area
        } else {
            parts.clone().next().map_or(glam::DVec3::ZERO, |m| m.centre)
        };
        let mut out = Self {
            area,
            centre,
            power: [0.0; 3],
            dipole: [glam::DVec3::ZERO; 3],
        };
        for m in parts {
            let off = m.centre - centre;
            for ch in 0..3 {
                out.power[ch] += m.power[ch];
                out.dipole[ch] += m.dipole[ch] + off * m.power[ch];
            }
        }
        out
    }
}

impl Cluster {
    /// The hierarchy over `roots` and the roots in its leaf order.
    fn build(roots: &[Root], node_e: &[[f32; 3]]) -> (Vec<Cluster>, Vec<u32>) {
        let moments: Vec<Moments> = roots.iter().map(|r| Moments::of_root(r, node_e)).collect();
        let mut order: Vec<u32> = (0..roots.len() as u32).collect();
        let mut clusters = Vec::with_capacity(2 * roots.len() / LEAF_ROOTS + 1);
        if !roots.is_empty() {
            clusters.push(Self::placeholder());
            Self::fill(
                0,
                0,
                roots.len(),
                roots,
                &moments,
                &mut order,
                &mut clusters,
            );
        }
        (clusters, order)
    }

    fn placeholder() -> Self {
        Cluster {
            centre: Vec3::ZERO,
            radius: 0.0,
            power: [0.0; 3],
            dipole: [Vec3::ZERO; 3],
            kind: ClusterKind::Leaf { first: 0, count: 0 },
        }
    }

    /// Makes cluster `at` over `order[lo..hi]`, splitting it in two at the
    /// median centroid along the widest axis of their box.
    fn fill(
        at: usize,
        lo: usize,
        hi: usize,
        roots: &[Root],
        moments: &[Moments],
        order: &mut [u32],
        clusters: &mut Vec<Cluster>,
    ) {
        let part = || order[lo..hi].iter().map(|&k| moments[k as usize]);
        let m = Moments::merge(part());
        let centre = m.centre.as_vec3();
        let radius = order[lo..hi]
            .iter()
            .flat_map(|&k| roots[k as usize].corners)
            .map(|v| (v - centre).length())
            .fold(0.0f32, f32::max);
        let mut cl = Cluster {
            centre,
            radius,
            power: m.power.map(|v| v as f32),
            dipole: m.dipole.map(|d| d.as_vec3()),
            kind: ClusterKind::Leaf {
                first: lo as u32,
                count: (hi - lo) as u32,
            },
        };
        if hi - lo > LEAF_ROOTS {
            let (mut bmin, mut bmax) = (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN));
            for &k in &order[lo..hi] {
                bmin = bmin.min(moments[k as usize].centre);
                bmax = bmax.max(moments[k as usize].centre);
            }
            let ext = bmax - bmin;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = (lo + hi) / 2;
            order[lo..hi].select_nth_unstable_by(mid - lo, |a, b| {
                moments[*a as usize].centre[axis].total_cmp(&moments[*b as usize].centre[axis])
            });
            let left = clusters.len();
            clusters.push(Self::placeholder());
            clusters.push(Self::placeholder());
            cl.kind = ClusterKind::Inner(left as u32);
            Self::fill(left, lo, mid, roots, moments, order, clusters);
            Self::fill(left + 1, mid, hi, roots, moments, order, clusters);
        }
        clusters[at] = cl;
    }
}

/// One gather: the point, its pixel and the profile there.
struct Query<'a> {
    x: Vec3,
    pixel: Footprint,
    profile: Scaled<'a>,
    memo: &'a Memo,
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

/// The profile at a probe: the table with its radii scaled by m (the
/// pixel's SSS mask): ρ_m(r) = ρ(r/m)/m², CDF_m(r) = CDF(r/m).
#[derive(Clone, Copy)]
struct Scaled<'a> {
    table: &'a ProfileTable,
    m: f64,
}

impl Scaled<'_> {
    fn density(&self, r_mm: f64) -> [f32; 3] {
        let k = (1.0 / (self.m * self.m)) as f32;
        self.table.density(r_mm / self.m).map(|v| v * k)
    }

    fn cdf(&self, r_mm: f64) -> [f32; 3] {
        self.table.cdf(r_mm / self.m)
    }

    /// ρ_m and ρ_m' at r: ρ(r/m)/m², ρ'(r/m)/m³.
    fn density_and_slope(&self, r_mm: f64) -> [[f32; 3]; 2] {
        let [a, b] = self.table.density_and_slope(r_mm / self.m);
        let k = (1.0 / self.m) as f32;
        [a.map(|v| v * k * k), b.map(|v| v * k * k * k)]
    }

    fn leaf_mm(&self, r_mm: f64) -> f64 {
        self.table.leaf_mm(r_mm / self.m) * self.m
    }

    fn decay_mm(&self, r_mm: f64) -> f64 {
        self.table.decay_mm(r_mm / self.m) * self.m
    }

    fn r_max_mm(&self) -> f64 {
        self.table.r_max_mm * self.m
    }

    fn epsilon_mm(&self) -> f64 {
        self.table.epsilon_mm * self.m
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

impl Scaled<'_> {
    /// ∫ ρ(‖x − y‖) dA over the triangle `corners`. With x at height h
    /// above the triangle's plane and x' its foot, ‖x − y‖² = r² + h² for
    /// r = ‖x' − y‖, and ∫₀^R ρ(√(r² + h²)) r dr = (CDF(√(R² + h²)) −
    /// CDF(h))/2π. The triangle is the signed sum over its edges (a, b) of
    /// the triangles (x', a, b), each integrated over the angle it spans
    /// at x' ([`edge_fan`]). Exact for the 1/r core, for a Dirac part (at
    /// h = 0) and for a cell behind x (a slab's far face), and additive over
    /// cells, where a disk of equal area per cell is not (a fan of thin
    /// cells around x, as at a sphere's pole, summed their disks' √area and
    /// counted the core hundreds of times).
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
        let cdf_h = if h > 0.0 { self.cdf(h) } else { [0.0; 3] };
        let foot = x - n * along;
        let unit_n = n / n2.sqrt();
        let mut w = [0.0f64; 3];
        for k in 0..3 {
            let (a, b) = (corners[k] - foot, corners[(k + 1) % 3] - foot);
            edge_fan(a, b, unit_n, |r_mm, weight| {
                let cdf = self.cdf((r_mm * r_mm + h * h).sqrt());
                for c in 0..3 {
                    w[c] += weight * (cdf[c] - cdf_h[c]) as f64;
                }
            });
        }
        w.map(|v| v / (2.0 * std::f64::consts::PI))
    }
}

/// The quadrature of ∫ f(R(φ)) dφ over the triangle (0, a, b) in the plane
/// of unit normal n, R(φ) the distance from 0 to the edge (a, b) along φ,
/// signed by the triangle's orientation about n: calls `node(R, weight)`.
/// The angle is measured from the foot of the perpendicular onto the
/// edge's line, at distance p: R(ψ) = p / cos ψ. In ψ the integrand is
/// smooth however close 0 lies to the edge (along the edge, as this
/// once integrated, dφ = p/(p² + t²) dt peaks in a width p that 8 nodes
/// miss when p ≪ the edge: the ground truth went negative beside cell
/// edges; `polar_weight_is_exact_beside_an_edge`). ψ runs in pieces of
/// at most π/4, split at the foot, 8-point Gauss–Legendre in each (π/8
/// pieces moved the default head's front view by 1e-5 relative RMSE and
/// cost a tenth more of the whole frame, issue 23).
fn edge_fan(a: Vec3, b: Vec3, n: Vec3, mut node: impl FnMut(f64, f64)) {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    let n = n.as_dvec3();
    let edge = b - a;
    let len2 = edge.length_squared();
    if len2 <= 0.0 {
        return;
    }
    // The foot of the perpendicular from 0 onto the line, and its distance.
    let t_foot = -a.dot(edge) / len2;
    let foot = a + edge * t_foot;
    let p = foot.length();
    let orientation = a.cross(b).dot(n);
    // On the line (or nearly, at f32's resolution of the corners): the
    // triangle (0, a, b) has no area.
    if p <= 1e-9 * len2.sqrt() || orientation == 0.0 {
        return;
    }
    let sign = orientation.signum();
    // ψ of a point at parameter t along the edge: its distance from the
    // foot over p, signed along the edge.
    let len = len2.sqrt();
    let psi = |t: f64| ((t - t_foot) * len / p).atan();
    let (psi_a, psi_b) = (psi(0.0), psi(1.0));
    let (nodes, weights) = crate::model::quad::gl8();
    let mut piece = |lo: f64, hi: f64| {
        let pieces = ((hi - lo) / (std::f64::consts::PI / 4.0)).ceil().max(1.0);
        let step = (hi - lo) / pieces;
        for k in 0..pieces as usize {
            let mid = lo + (k as f64 + 0.5) * step;
            for (t, q) in nodes.iter().zip(weights) {
                let s = mid + 0.5 * step * t;
                node(p / s.cos(), sign * 0.5 * step * q);
            }
        }
    };
    if psi_a < 0.0 && psi_b > 0.0 {
        piece(psi_a, 0.0);
        piece(0.0, psi_b);
    } else {
        piece(psi_a, psi_b);
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
