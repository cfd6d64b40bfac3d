//! The profile as the gather reads it: the tables of its density and CDF,
//! the largest piece each distance allows, and the exact polar integral of
//! a triangle about a point.

use super::*;
use crate::model::RadialProfile;

/// A piece is at most this fraction of its distance.
pub(super) const THETA: f64 = 1.0;
/// The error bound a ground truth is gathered to: the final one (the
/// yardstick's), or a loose one for a first look (issue 38). Both are the
/// same walk; the bound sets its two tolerances:
/// - τ, the edge-midpoint rule's error term, which sets the largest piece
///   at each distance (see the module): √(24 τ) = 1.8 λ for an
///   exponential of length λ at τ = 0.136;
/// - how far a near piece's corners may differ from its mean, over the
///   piece's share of the energy, before it is split (`gather.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "gpu", derive(clap::ValueEnum))]
pub enum TruthBound {
    /// τ = 0.136, corners within 1 %: the yardstick's own floor
    /// (docs/rendering.md, "The truth in seconds").
    #[default]
    Final,
    /// τ = 0.544 (leaves up to twice as wide), corners within 1 %: a first
    /// look, measured against the final bound in docs/rendering.md.
    Loose,
}

impl TruthBound {
    pub fn tau(self) -> f64 {
        match self {
            TruthBound::Final => 0.136,
            TruthBound::Loose => 0.544,
        }
    }

    /// A near piece is split where a corner's irradiance differs from the
    /// piece's mean by more than this fraction of it, over the piece's
    /// share of the profile's energy (at most 1).
    pub fn uneven(self) -> f32 {
        match self {
            // The loose bound splits as the final one does: at 4 % its
            // d → 0 floor on the back-lit ear rose from 0.44 % to 0.53 %
            // (quick bench, 320×180), for no time saved.
            TruthBound::Final | TruthBound::Loose => 0.01,
        }
    }
}
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
    pub(super) ln_r0: f64,
    pub(super) inv_step: f64,
    pub(super) density: Vec<[f32; 3]>,
    pub(super) cdf: Vec<[f32; 3]>,
    /// CDF at r = 0 (a Dirac part's share) and the grid's first radius:
    /// below it the CDF runs linearly from the one to the other.
    pub(super) cdf_zero: [f32; 3],
    pub(super) r0_mm: f64,
    pub(super) leaf_mm: Vec<f32>,
    /// dρ/dr (mm⁻³) by central differences on the grid, for the
    /// clusters' expansion ([`Cluster`]).
    pub(super) d1: Vec<[f32; 3]>,
    /// The profile's local decay length |ρ/ρ'| (mm), the shortest over
    /// the channels that are over a hundredth of their accuracy floor.
    pub(super) decay_mm: Vec<f32>,
    /// Radius (mm) beyond which nothing is summed: the widest channel's
    /// [`ENERGY_FRACTION`] radius.
    pub r_max_mm: f64,
    /// Splitting stops below this side (mm).
    pub epsilon_mm: f64,
    /// The error bound the leaf sizes were made for, and its splitting
    /// tolerance ([`TruthBound::uneven`]).
    pub bound: TruthBound,
    pub(super) uneven: f32,
}

const TABLE_SIZE: usize = 2048;

impl ProfileTable {
    /// The table at the final bound ([`TruthBound::Final`]).
    pub fn new(profile: &dyn RadialProfile) -> Self {
        Self::with_bound(profile, TruthBound::Final)
    }

    /// The table whose leaf sizes and splitting meet `bound`.
    pub fn with_bound(profile: &dyn RadialProfile, bound: TruthBound) -> Self {
        let tau = bound.tau();
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
                        let s = (24.0 * tau * (rho[i][c] + floor[c]) / d2.abs().max(1e-300)).sqrt();
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
            bound,
            uneven: bound.uneven(),
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
        self.bound.hash(&mut h);
        h.finish()
    }

    /// (index, fraction) of r on the grid, clamped to its ends.
    fn locate(&self, r_mm: f64) -> (usize, f32) {
        self.locate_ln(fast_ln(r_mm as f32) as f64)
    }

    /// (index, fraction) of the radius whose logarithm is `ln_r`.
    fn locate_ln(&self, ln_r: f64) -> (usize, f32) {
        let t = ((ln_r - self.ln_r0) * self.inv_step).max(0.0);
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
pub(super) fn fast_ln(x: f32) -> f32 {
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

/// The profile at a probe: the table with its radii scaled by m (the
/// pixel's SSS mask): ρ_m(r) = ρ(r/m)/m², CDF_m(r) = CDF(r/m).
#[derive(Clone, Copy)]
pub(super) struct Scaled<'a> {
    pub(super) table: &'a ProfileTable,
    pub(super) m: f64,
    /// ln m and 1/m², for lookups by the squared distance.
    ln_m: f64,
    inv_m2: f32,
}

impl<'a> Scaled<'a> {
    pub(super) fn new(table: &'a ProfileTable, m: f64) -> Self {
        Self {
            table,
            m,
            ln_m: m.ln(),
            inv_m2: (1.0 / (m * m)) as f32,
        }
    }

    /// ρ_m at the distance whose square is `r2_mm2` (no square root: ln r
    /// = ½ ln r²).
    pub(super) fn density_sq(&self, r2_mm2: f32) -> [f32; 3] {
        let at = self
            .table
            .locate_ln(0.5 * fast_ln(r2_mm2) as f64 - self.ln_m);
        ProfileTable::lerp(&self.table.density, at).map(|v| v * self.inv_m2)
    }

    /// CDF_m at the distance whose square is `r2_mm2`.
    pub(super) fn cdf_sq(&self, r2_mm2: f64) -> [f32; 3] {
        let r0 = self.table.r0_mm * self.m;
        if r2_mm2 < r0 * r0 {
            return self.cdf(r2_mm2.max(0.0).sqrt());
        }
        let at = self
            .table
            .locate_ln(0.5 * fast_ln(r2_mm2 as f32) as f64 - self.ln_m);
        ProfileTable::lerp(&self.table.cdf, at)
    }

    pub(super) fn cdf(&self, r_mm: f64) -> [f32; 3] {
        self.table.cdf(r_mm / self.m)
    }

    /// ρ_m and ρ_m' at r: ρ(r/m)/m², ρ'(r/m)/m³.
    pub(super) fn density_and_slope(&self, r_mm: f64) -> [[f32; 3]; 2] {
        let [a, b] = self.table.density_and_slope(r_mm / self.m);
        let k = (1.0 / self.m) as f32;
        [a.map(|v| v * k * k), b.map(|v| v * k * k * k)]
    }

    pub(super) fn leaf_mm(&self, r_mm: f64) -> f64 {
        self.table.leaf_mm(r_mm / self.m) * self.m
    }

    pub(super) fn decay_mm(&self, r_mm: f64) -> f64 {
        self.table.decay_mm(r_mm / self.m) * self.m
    }

    pub(super) fn r_max_mm(&self) -> f64 {
        self.table.r_max_mm * self.m
    }

    pub(super) fn epsilon_mm(&self) -> f64 {
        self.table.epsilon_mm * self.m
    }
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
    pub(super) fn polar_weight(&self, x: Vec3, corners: [Vec3; 3]) -> [f64; 3] {
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
            edge_fan(a, b, unit_n, |r2_mm2, weight| {
                let cdf = self.cdf_sq(r2_mm2 + h * h);
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
/// signed by the triangle's orientation about n: calls `node(R², weight)`.
/// The angle is measured from the foot of the perpendicular onto the
/// edge's line, at distance p: R(ψ) = p / cos ψ. In ψ the integrand is
/// smooth however close 0 lies to the edge (along the edge, as this
/// once integrated, dφ = p/(p² + t²) dt peaks in a width p that 8 nodes
/// miss when p ≪ the edge: the ground truth went negative beside cell
/// edges; `polar_weight_is_exact_beside_an_edge`). ψ runs in pieces of
/// at most π/4, split at the foot, 8-point Gauss–Legendre in each (π/8
/// pieces moved the default head's front view by 1e-5 relative RMSE and
/// cost a tenth more of the whole frame, issue 23). The nodes' cosines
/// are the piece's middle turned by each node's offset δ (|δ| ≤ π/8),
/// cos(s + δ) = cos s cos δ − sin s sin δ, with cos δ and sin δ by their
/// Taylor series to δ⁸ and δ⁹ (the next terms are under 1e-9): one libm
/// sin/cos a piece instead of one cos a node.
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
    let p2 = p * p;
    let mut piece = |lo: f64, hi: f64| {
        let pieces = ((hi - lo) / (std::f64::consts::PI / 4.0)).ceil().max(1.0);
        let step = (hi - lo) / pieces;
        // cos δ and sin δ of each node's offset from a piece's middle.
        let turns: [(f64, f64); 8] = std::array::from_fn(|i| {
            let d = 0.5 * step * nodes[i];
            let d2 = d * d;
            let cos = 1.0 - d2 / 2.0 * (1.0 - d2 / 12.0 * (1.0 - d2 / 30.0 * (1.0 - d2 / 56.0)));
            let sin =
                d * (1.0 - d2 / 6.0 * (1.0 - d2 / 20.0 * (1.0 - d2 / 42.0 * (1.0 - d2 / 72.0))));
            (cos, sin)
        });
        for k in 0..pieces as usize {
            let (sin_mid, cos_mid) = (lo + (k as f64 + 0.5) * step).sin_cos();
            for ((cos, sin), q) in turns.iter().zip(weights) {
                let c = cos_mid * cos - sin_mid * sin;
                node(p2 / (c * c), sign * 0.5 * step * q);
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
