//! The hierarchy of clusters over the SSS triangles (Jensen & Buhler
//! 2002's octree clustering, as a binary tree).

use super::*;

/// A cluster is taken as one term where its radius is at most this
/// fraction of its distance,
pub(super) const CLUSTER_THETA: f64 = 0.25;
/// this fraction of the largest piece the edge-midpoint rule takes at its
/// nearest point (a triangle of side s has a radius of s/√3 ≈ 0.58 s),
pub(super) const CLUSTER_LEAF: f64 = 0.25;
/// and this fraction of the profile's decay length |ρ/ρ'| there. The three
/// were set together at 0.25, the largest value (of 0.5, 0.35, 0.25) at
/// which the sphere's closed form (`penners_table_is_the_ground_truths_sphere`,
/// 1e-3) and the plane's energy (≤ 100.05 %) hold: at 0.5 the sphere was
/// 1.5e-3 off and the plane 100.14 %.
pub(super) const CLUSTER_DECAY: f64 = 0.25;
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
pub(super) struct Cluster {
    pub(super) centre: Vec3,
    /// Farthest corner of its triangles from `centre` (mm).
    pub(super) radius: f32,
    /// P per channel (irradiance × mm²).
    pub(super) power: [f32; 3],
    /// D per channel (irradiance × mm³).
    pub(super) dipole: [Vec3; 3],
    pub(super) kind: ClusterKind,
}

#[derive(Debug, Clone, Copy)]
pub(super) enum ClusterKind {
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
    pub(super) centre: glam::DVec3,
    pub(super) power: [f64; 3],
    pub(super) dipole: [glam::DVec3; 3],
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
    pub(super) fn build(roots: &[Root], node_e: &[[f32; 3]]) -> (Vec<Cluster>, Vec<u32>) {
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
