//! The gather: the cells' contribution at a probe's point, by the
//! quadtree walk, the clusters and the exact polar near field.

use super::cluster::{CLUSTER_DECAY, CLUSTER_LEAF, CLUSTER_THETA};
use super::table::{Scaled, THETA};
use super::*;
use rayon::prelude::*;
use std::collections::HashMap;

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
    fn on_surface(&self, probe: &Probe) -> GatherPoint {
        let (x_mm, pixel_dx_mm, pixel_dy_mm) = self.moved_on_surface(probe);
        GatherPoint {
            x_mm,
            pixel_dx_mm,
            pixel_dy_mm,
            profile_scale: probe.profile_scale,
        }
    }

    fn moved_on_surface(&self, probe: &Probe) -> (Vec3, Vec3, Vec3) {
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
        let points = self.gather_points(probe, k)?;
        let mut acc = [0.0f64; 3];
        for p in &points {
            let v = self.gather_at(p, irradiance, memo);
            for c in 0..3 {
                acc[c] += v[c] as f64;
            }
        }
        Some(acc.map(|v| (v / points.len() as f64) as f32))
    }

    /// The points a probe's pixel is gathered at, k × k of them (k = 1:
    /// the probe's own point moved onto the surface), each with its
    /// pixel's steps there; the CPU and GPU gathers both read these
    /// ([`Cloud::gather_supersampled`] says when there are none).
    pub fn gather_points(&self, probe: &Probe, k: u32) -> Option<Vec<GatherPoint>> {
        let Some((corners, _)) = self.nearest(probe.x_mm, 10e-3).filter(|_| k > 1) else {
            return Some(vec![self.on_surface(probe)]);
        };
        let n = normal_of(corners);
        let (dx, dy) = probe.pixel_steps_mm(n);
        let tolerance = 0.05 * dx.length().max(dy.length()) + 1e-3;
        let mut out = Vec::with_capacity((k * k) as usize);
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
                out.push(self.on_surface(&sub));
            }
        }
        Some(out)
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
        self.gather_at(&self.on_surface(probe), irradiance, memo)
    }

    /// The gather at a point already on the surface ([`Cloud::gather_points`]).
    pub(super) fn gather_at(
        &self,
        point: &GatherPoint,
        irradiance: &dyn SurfaceIrradiance,
        memo: &Memo,
    ) -> [f32; 3] {
        let (x, dx, dy) = (point.x_mm, point.pixel_dx_mm, point.pixel_dy_mm);
        let pixel = Footprint {
            pixel_dx_mm: dx,
            pixel_dy_mm: dy,
            width_mm: 0.0,
        };
        let profile = Scaled::new(&self.table, (point.profile_scale as f64).clamp(1e-3, 1.0));
        let query = Query {
            x,
            pixel,
            pixel_mm: dx.length().max(dy.length()) as f64,
            r_max_mm: profile.r_max_mm(),
            epsilon_mm: profile.epsilon_mm(),
            profile,
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
    /// `progress`: report it to [`super::progress`] (a whole frame; the
    /// editor's tiles report their own).
    pub fn gather_all(
        &self,
        probes: &[Probe],
        supersample: u32,
        irradiance: &dyn SurfaceIrradiance,
        cancel: &std::sync::atomic::AtomicBool,
        progress: bool,
    ) -> Option<Vec<Option<[f32; 3]>>> {
        let cancelled = || cancel.load(std::sync::atomic::Ordering::Relaxed);
        if progress {
            start(2, probes.len());
        }
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
                        if progress {
                            step();
                        }
                        self.supersampled_with(p, supersample, irradiance, &memo)
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        if progress {
            finish();
        }
        (!cancelled()).then_some(out)
    }

    /// The gather at points already on the surface, in parallel (the
    /// points the GPU's walk did not finish, `sss/reference.rs`).
    pub fn gather_at_points(
        &self,
        points: &[GatherPoint],
        irradiance: &dyn SurfaceIrradiance,
    ) -> Vec<[f32; 3]> {
        points
            .par_chunks(MEMO_CHUNK)
            .flat_map_iter(|chunk| {
                let memo = Memo::default();
                chunk
                    .iter()
                    .map(|p| self.gather_at(p, irradiance, &memo))
                    .collect::<Vec<_>>()
            })
            .collect()
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
                    self.integrate(q, r, Node::root(r), irradiance, acc);
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
        // The node's side and reach are its root's, halved per level (the
        // farthest point of a triangle from its centroid is a corner, up
        // to 2/3 of the longest side for a sliver: a fixed 0.58 of the
        // side skipped slivers' tips beside x when r_max is short).
        let side = node.side_mm as f64;
        let reach = (node.reach_mm as f64).max(1e-9);
        let dist = (x - centre).length() as f64;
        // Truncate at r_max: a piece across it counts with the fraction of
        // its extent inside (the density there is the profile's last
        // 0.1 %, so this costs nothing measurable).
        if dist - reach >= q.r_max_mm {
            return;
        }
        let inside = ((q.r_max_mm - (dist - reach)) / (2.0 * reach)).min(1.0);
        // The largest piece the edge-midpoint rule takes at this distance
        // (never wider than θ times the distance: the table is read only
        // where that does not already rule the piece out).
        let leaf = side <= THETA * dist && side <= table.leaf_mm(dist);
        let near = node.level >= root.levels && !leaf;
        // The piece's irradiance: the quadtree's mean down to the cells;
        // at x, where a piece is narrower than the pixel and within a
        // pixel of x, evaluated afresh over the pixel's footprint (the
        // pixel's mean, as the GPU's mip level makes it: the d → 0 limit);
        // below the cells (only ever beside x) afresh over the piece.
        let by_pixel = near && q.pixel_mm > side && dist - reach < q.pixel_mm;
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
            let even = side <= q.epsilon_mm
                || share.iter().all(|w| *w <= self.table.uneven)
                || node.bary.iter().all(|b| {
                    let v = q.memo.at(irradiance, root.tri, *b, footprint);
                    (0..3).all(|c| {
                        (v[c] - e[c]).abs() * share[c] <= self.table.uneven * e[c].abs().max(1e-6)
                    })
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
        } else if leaf {
            if e == [0.0; 3] {
                return;
            }
            // The edge-midpoint rule, exact for quadratics on a triangle.
            let mut w = [0.0f32; 3];
            for k in 0..3 {
                let m = 0.5 * (corners[k] + corners[(k + 1) % 3]);
                let d = table.density_sq((x - m).length_squared());
                for c in 0..3 {
                    w[c] += d[c];
                }
            }
            let scale = node.area_mm2 as f64 / 3.0 * inside;
            for c in 0..3 {
                acc[c] += e[c] as f64 * w[c] as f64 * scale;
            }
            return;
        }
        for child in node.children(root.levels) {
            self.integrate(q, root, child, irradiance, acc);
        }
    }
}

/// One gather: the point, its pixel and the profile there, with what the
/// walk reads at every node worked out once.
struct Query<'a> {
    x: Vec3,
    pixel: Footprint,
    profile: Scaled<'a>,
    memo: &'a Memo,
    /// The pixel's larger surface step (mm).
    pixel_mm: f64,
    /// The profile's truncation radius and its smallest split (mm), at
    /// this pixel's scale.
    r_max_mm: f64,
    epsilon_mm: f64,
}

/// A node of a root's quadtree during the gather.
#[derive(Debug, Clone, Copy)]
struct Node {
    bary: [Vec3; 3],
    corners: [Vec3; 3],
    level: u32,
    index: usize,
    /// Its root's side, reach and area at this level ([`Root`]).
    side_mm: f32,
    reach_mm: f32,
    area_mm2: f32,
}

impl Node {
    /// The node's four pieces (midpoint subdivision); below the cells'
    /// `levels` they have no index of their own.
    fn children(&self, levels: u32) -> [Node; 4] {
        let bary = split(self.bary);
        let pieces = split(self.corners);
        std::array::from_fn(|k| Node {
            bary: bary[k],
            corners: pieces[k],
            level: self.level + 1,
            index: if self.level < levels {
                4 * self.index + k
            } else {
                0
            },
            side_mm: 0.5 * self.side_mm,
            reach_mm: 0.5 * self.reach_mm,
            area_mm2: 0.25 * self.area_mm2,
        })
    }

    fn root(r: &Root) -> Self {
        Self {
            bary: [Vec3::X, Vec3::Y, Vec3::Z],
            corners: r.corners,
            level: 0,
            index: 0,
            side_mm: r.side_mm,
            reach_mm: r.reach_mm,
            area_mm2: r.area_mm2,
        }
    }
}
