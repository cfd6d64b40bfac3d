//! Pre-integrated skin lookup tables (Penner & Borshukov 2011) with
//! FaceWorks' encodings: D(θ, c), the profile integrated over a sphere of
//! radius c lit from angle θ, normalised by the energy that fits on it.
//!
//! A point y at angular distance γ from x, at azimuth φ about it, is at
//! chord r = 2c·sin(γ/2) from x (dA = c²·sin γ dγ dφ = r dr dφ) and sees
//! the light at cos θ_y = cos θ cos γ + sin θ sin γ cos φ (the spherical
//! law of cosines). So
//!
//! D(θ, c) = ∫₀^π 2π R_N(r) r (dr/dγ) · C(θ, γ) dγ / CDF(2c),
//!
//! with C the mean of cos⁺θ_y over the ring ([`ring_mean_cos`]) and
//! dr/dγ = c·cos(γ/2); the denominator is exactly CDF(2c). The survey our
//! seeds come from writes C as the two-point mean ½[cos⁺(θ + γ) +
//! cos⁺(θ − γ)] (its "improved ring integral", with Octave numbers that
//! reproduce exactly), which is the ring's value at φ = 0 and π only: at
//! the terminator it is too bright (the default skin at 90° on a 3 mm
//! sphere: red D 0.210 against the sphere's 0.134; mpmath, and the test
//! `d_is_the_spheres_average_by_nested_quadrature`). Penner 2011's own
//! integral is over the sphere, which this is.
//!
//! The table bake evaluates the profile once per row (curvature) at the
//! nodes of Gauss–Legendre panels shared by every column, and splits the
//! panel that holds a column's kink of C (where the ring starts or stops
//! crossing the terminator) in two there. Rows run in parallel (rayon).

use super::quad;
use super::{check_range, rgb_map, ModelError, RadialProfile, Rgb};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// The mean of cos⁺θ_y over the ring of points at angular distance γ from
/// a point at angle θ from the light, on a sphere: with a = cos θ cos γ and
/// b = sin θ sin γ ≥ 0, cos θ_y = a + b cos φ, and (1/π)∫₀^π max(0, a +
/// b cos φ) dφ is a where the whole ring is lit (a ≥ b), 0 where none of
/// it is (a ≤ −b), and (a·acos(−a/b) + √(b² − a²))/π between: the ring
/// is lit for cos φ > −a/b. (Closed form checked against quadrature over
/// φ in `ring_mean_matches_quadrature_over_the_ring`.)
pub fn ring_mean_cos(theta: f64, gamma: f64) -> f64 {
    let a = theta.cos() * gamma.cos();
    let b = (theta.sin() * gamma.sin()).abs();
    if a >= b {
        a
    } else if a <= -b {
        0.0
    } else {
        (a * (-a / b).clamp(-1.0, 1.0).acos() + (b * b - a * a).max(0.0).sqrt()) / PI
    }
}

/// Where the ring mean C(θ, ·) has a kink in γ ∈ (0, π): where a = ±b,
/// i.e. cos(θ ± γ) = 0.
fn ring_kinks(theta: f64) -> impl Iterator<Item = f64> {
    [
        FRAC_PI_2 - theta,
        theta - FRAC_PI_2,
        FRAC_PI_2 + theta,
        1.5 * PI - theta,
    ]
    .into_iter()
    .filter(|x| *x > 0.0 && *x < PI)
}

/// (numerator, denominator) of D(θ, c) for one channel by adaptive
/// quadrature of the sphere integral (reference grade, used by the CLI).
pub fn ring_integral(
    profile: &dyn RadialProfile,
    channel: usize,
    theta: f64,
    curvature_radius_mm: f64,
) -> (f64, f64) {
    let c = curvature_radius_mm;
    let total = profile.total_reflectance()[channel];
    if total <= 0.0 {
        return (theta.cos().max(0.0), 1.0);
    }
    let dirac = profile.dirac_weight()[channel] / total;
    let g = |x: f64| {
        let r = 2.0 * c * (0.5 * x).sin();
        2.0 * PI * profile.r_reflectance(r)[channel] / total * c * (0.5 * x).cos()
    };
    let w = |x: f64| ring_mean_cos(theta, x);
    let mut breaks: Vec<f64> = ring_kinks(theta).collect();
    // Resolve a profile much narrower than the ring near x = 0.
    let narrow = 2.0 * (profile.length_scale_mm() / (2.0 * c)).min(1.0).asin();
    breaks.extend(
        [0.0, PI, narrow * 1e-3, narrow * 1e-1, narrow]
            .into_iter()
            .filter(|x| *x >= 0.0 && *x <= PI),
    );
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let num = quad::integrate_with_breaks(&|x| g(x) * w(x), &breaks, 1e-15, 1e-13)
        + dirac * theta.cos().max(0.0);
    let den = profile.cdf(2.0 * c)[channel];
    (num, den)
}

/// D(θ, c) per channel (reference quadrature).
pub fn preintegrated_d(profile: &dyn RadialProfile, theta: f64, curvature_radius_mm: f64) -> Rgb {
    rgb_map(|ch| {
        let (n, d) = ring_integral(profile, ch, theta, curvature_radius_mm);
        if d > 0.0 {
            n / d
        } else {
            theta.cos().max(0.0)
        }
    })
}

/// Checks θ ∈ [0, π] and c ∈ [1e-3, 1e4] mm for the CLI.
pub fn check_lut_inputs(theta: f64, c: f64) -> Result<(), ModelError> {
    check_range("theta", theta, 0.0, PI, " rad")?;
    check_range("curvature_radius_mm", c, 1e-3, 1e4, " mm")?;
    Ok(())
}

/// How table values are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LutEncoding {
    /// D itself, linear.
    Linear,
    /// FaceWorks' delta: 2·(D − saturate(N·L)) + ½, clamped to [0, 1]; the
    /// N·L part is added back at run time with one normal per channel.
    FaceWorksDelta,
}

impl LutEncoding {
    pub fn encode(self, d: f64, n_dot_l: f64) -> f64 {
        match self {
            LutEncoding::Linear => d,
            LutEncoding::FaceWorksDelta => (2.0 * (d - n_dot_l.max(0.0)) + 0.5).clamp(0.0, 1.0),
        }
    }
    pub fn decode(self, v: f64, n_dot_l: f64) -> f64 {
        match self {
            LutEncoding::Linear => v,
            LutEncoding::FaceWorksDelta => (v - 0.5) * 0.5 + n_dot_l.max(0.0),
        }
    }
}

/// Layout of a baked curvature table: x = N·L from −1 to 1 and y = 1/c
/// from 1/c_max to 1/c_min, both at texel centres (as FaceWorks lays it out).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LutLayout {
    pub width: usize,
    pub height: usize,
    pub curvature_radius_min_mm: f64,
    pub curvature_radius_max_mm: f64,
}

impl Default for LutLayout {
    fn default() -> Self {
        Self {
            width: 256,
            height: 256,
            curvature_radius_min_mm: 1.0,
            curvature_radius_max_mm: 100.0,
        }
    }
}

impl LutLayout {
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range("width", self.width as f64, 1.0, 8192.0, " texels")?;
        check_range("height", self.height as f64, 1.0, 8192.0, " texels")?;
        check_range(
            "curvature_radius_min_mm",
            self.curvature_radius_min_mm,
            1e-3,
            1e4,
            " mm",
        )?;
        check_range(
            "curvature_radius_max_mm",
            self.curvature_radius_max_mm,
            self.curvature_radius_min_mm,
            1e4,
            " mm",
        )?;
        Ok(())
    }
    /// N·L at column i.
    pub fn n_dot_l(&self, i: usize) -> f64 {
        -1.0 + (i as f64 + 0.5) * 2.0 / self.width as f64
    }
    /// Curvature radius (mm) at row j.
    pub fn curvature_radius(&self, j: usize) -> f64 {
        let (k0, k1) = (
            1.0 / self.curvature_radius_max_mm,
            1.0 / self.curvature_radius_min_mm,
        );
        1.0 / (k0 + (j as f64 + 0.5) * (k1 - k0) / self.height as f64)
    }
}

/// A baked RGB table of linear D values, row-major (row = curvature).
#[derive(Debug, Clone, PartialEq)]
pub struct Lut {
    pub layout: LutLayout,
    pub d: Vec<Rgb>,
}

impl Lut {
    /// Bakes D for every texel of `layout` (the fast row method).
    pub fn bake(profile: &dyn RadialProfile, layout: LutLayout) -> Result<Self, ModelError> {
        layout.validate()?;
        let thetas: Vec<f64> = (0..layout.width)
            .map(|i| layout.n_dot_l(i).clamp(-1.0, 1.0).acos())
            .collect();
        let d: Vec<Rgb> = (0..layout.height)
            .into_par_iter()
            .flat_map_iter(|j| bake_row(profile, &thetas, layout.curvature_radius(j)))
            .collect();
        Ok(Self { layout, d })
    }

    /// 8-bit RGB pixels with the given encoding (linear values, no sRGB curve).
    pub fn to_rgb8(&self, encoding: LutEncoding) -> Vec<u8> {
        let w = self.layout.width;
        self.d
            .iter()
            .enumerate()
            .flat_map(|(k, v)| {
                let ndl = self.layout.n_dot_l(k % w);
                v.map(|x| (encoding.encode(x, ndl).clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
            })
            .collect()
    }
}

/// One row of D for a fixed curvature radius `c` at the given θ columns.
fn bake_row(profile: &dyn RadialProfile, thetas: &[f64], c: f64) -> Vec<Rgb> {
    let total = profile.total_reflectance();
    let dirac = profile.dirac_weight();
    let den = profile.cdf(2.0 * c);
    // g(γ) = 2π R_N(r) r dr/dγ per channel.
    let g = |x: f64| -> Rgb {
        let r = 2.0 * c * (0.5 * x).sin();
        let rr = profile.r_reflectance(r);
        let jac = c * (0.5 * x).cos();
        rgb_map(|ch| {
            if total[ch] > 0.0 {
                2.0 * PI * rr[ch] / total[ch] * jac
            } else {
                0.0
            }
        })
    };
    // Panel edges shared by every column: geometric towards γ = 0 (a
    // profile much narrower than the sphere) and uniform over the ring.
    let narrow = 2.0
        * (profile.length_scale_mm().max(profile.r_floor_mm()) / (2.0 * c))
            .min(1.0)
            .asin();
    let mut edges: Vec<f64> = (0..48)
        .map(|k| narrow * 1e-4 * 1.25f64.powi(k))
        .filter(|x| *x < PI)
        .chain((0..=64).map(|k| PI * k as f64 / 64.0))
        .collect();
    edges.sort_by(f64::total_cmp);
    edges.dedup();
    let (gx, gw) = quad::gl8();
    // Each panel's nodes (γ, weight) and g there.
    type Nodes = Vec<(f64, f64, Rgb)>;
    let panel_nodes = |a: f64, b: f64| -> Nodes {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        gx.iter()
            .zip(gw)
            .map(|(x0, w0)| {
                let x = mid + half * x0;
                (x, w0 * half, g(x))
            })
            .collect()
    };
    let panels: Vec<(f64, f64, Nodes)> = edges
        .windows(2)
        .map(|e| (e[0], e[1], panel_nodes(e[0], e[1])))
        .collect();
    thetas
        .iter()
        .map(|&t| {
            let kinks: Vec<f64> = ring_kinks(t).collect();
            let mut num = [0.0; 3];
            let mut add = |nodes: &[(f64, f64, Rgb)]| {
                for (x, w, gv) in nodes {
                    let cm = ring_mean_cos(t, *x);
                    for ch in 0..3 {
                        num[ch] += w * gv[ch] * cm;
                    }
                }
            };
            for (a, b, nodes) in &panels {
                // A kink inside the panel: integrate each side separately.
                let inner: Vec<f64> = kinks.iter().copied().filter(|k| k > a && k < b).collect();
                if inner.is_empty() {
                    add(nodes);
                    continue;
                }
                let mut cuts = vec![*a];
                cuts.extend(inner);
                cuts.push(*b);
                for w in cuts.windows(2) {
                    add(&panel_nodes(w[0], w[1]));
                }
            }
            rgb_map(|ch| {
                if total[ch] <= 0.0 || den[ch] <= 0.0 {
                    return t.cos().max(0.0);
                }
                let n = num[ch] + dirac[ch] / total[ch] * t.cos().max(0.0);
                (n / den[ch]).max(0.0)
            })
        })
        .collect()
}

/// Layout of the shadow-penumbra table: x = the unscattered shadow value
/// u ∈ (0, 1) at texel centres, y = 1/w for penumbra widths w from
/// `width_max_mm` to `width_min_mm` (as FaceWorks lays it out).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowLayout {
    pub width: usize,
    pub height: usize,
    pub penumbra_min_mm: f64,
    pub penumbra_max_mm: f64,
}

impl Default for ShadowLayout {
    fn default() -> Self {
        Self {
            width: 64,
            height: 64,
            penumbra_min_mm: 1.0,
            penumbra_max_mm: 100.0,
        }
    }
}

/// The scattered shadow across a penumbra (Penner 2011's second table).
///
/// The penumbra is a straight edge, so irradiance is additively separable
/// and the pre-integrated 1D kernel is exact for it (Jimenez 2015 §4): with
/// s(t) = smoothstep(t) across the penumbra, t = s⁻¹(u) and X distributed
/// as the strip CDF Φ, the value is E[s(t + X/w)] = ∫₀¹ s′(y)(1 − Φ((y − t)w)) dy.
pub fn bake_shadow(
    profile: &dyn RadialProfile,
    layout: ShadowLayout,
) -> Result<Vec<Rgb>, ModelError> {
    check_range("width", layout.width as f64, 1.0, 4096.0, " texels")?;
    check_range("height", layout.height as f64, 1.0, 4096.0, " texels")?;
    check_range("penumbra_min_mm", layout.penumbra_min_mm, 1e-3, 1e4, " mm")?;
    check_range(
        "penumbra_max_mm",
        layout.penumbra_max_mm,
        layout.penumbra_min_mm,
        1e4,
        " mm",
    )?;
    let strip = StripTable::new(profile);
    let (k0, k1) = (1.0 / layout.penumbra_max_mm, 1.0 / layout.penumbra_min_mm);
    let (gx, gw) = quad::gauss_legendre(24);
    Ok((0..layout.height)
        .into_par_iter()
        .flat_map_iter(|j| {
            let w = 1.0 / (k0 + (j as f64 + 0.5) * (k1 - k0) / layout.height as f64);
            let strip = &strip;
            let (gx, gw) = (&gx, &gw);
            (0..layout.width).map(move |i| {
                let u = (i as f64 + 0.5) / layout.width as f64;
                let t = 0.5 - ((1.0 - 2.0 * u).asin() / 3.0).sin(); // smoothstep⁻¹
                rgb_map(|ch| {
                    // Split [0, 1] at y = t where Φ may jump (Dirac).
                    let mut acc = 0.0;
                    for (a, b) in [(0.0, t), (t, 1.0)] {
                        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
                        for (x, wt) in gx.iter().zip(gw.iter()) {
                            let y = m + h * x;
                            acc +=
                                wt * h * 6.0 * y * (1.0 - y) * (1.0 - strip.eval(ch, (y - t) * w));
                        }
                    }
                    acc.clamp(0.0, 1.0)
                })
            })
        })
        .collect())
}

/// The strip CDF Φ tabulated on a symmetric grid (linear interpolation).
struct StripTable {
    half: f64,
    values: [Vec<f64>; 3],
}

impl StripTable {
    const NODES: usize = 2049;
    fn new(profile: &dyn RadialProfile) -> Self {
        let r = profile.radius_for_energy(0.9999);
        let half = r.into_iter().fold(1e-9, f64::max);
        let xs: Vec<f64> = (0..Self::NODES)
            .map(|i| -half + 2.0 * half * i as f64 / (Self::NODES - 1) as f64)
            .collect();
        let rows: Vec<Rgb> = xs.par_iter().map(|&x| profile.strip_cdf(x)).collect();
        Self {
            half,
            values: [0, 1, 2].map(|c| rows.iter().map(|v| v[c]).collect()),
        }
    }
    fn eval(&self, c: usize, x: f64) -> f64 {
        if x <= -self.half {
            return 0.0;
        }
        if x >= self.half {
            return 1.0;
        }
        let f = (x + self.half) / (2.0 * self.half) * (Self::NODES - 1) as f64;
        let i = (f.floor() as usize).min(Self::NODES - 2);
        let t = f - i as f64;
        self.values[c][i] * (1.0 - t) + self.values[c][i + 1] * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::burley::Burley;
    use crate::model::gaussian::GaussianSum;

    /// The survey's two-point ring mean ½[cos⁺(θ + γ) + cos⁺(θ − γ)]
    /// reproduces its Octave check (S = 1/0.7568628, c = 3 mm, θ = π/4:
    /// numerator 0.563473, denominator 0.946522; mpmath at 30 digits, split
    /// at the kinks, 0.563473121128181846 and 0.946521806008770057), so
    /// our reading of its integral is right; the sphere's exact ring mean
    /// gives less there (0.5763 against the two-point 0.5953 in D, mpmath),
    /// and at the terminator the two part (0.1335 against 0.2097 at 90°).
    #[test]
    fn the_seeds_two_point_mean_reproduces_its_numbers_and_is_not_the_sphere() {
        let b = Burley::from_scattering_distance([1.0; 3], [0.756_862_8; 3]).unwrap();
        let c = 3.0;
        let g = |x: f64| {
            let r = 2.0 * c * (0.5 * x).sin();
            2.0 * PI * b.r_reflectance(r)[0] * c * (0.5 * x).cos()
        };
        let two_point =
            |t: f64| move |x: f64| 0.5 * ((t + x).cos().max(0.0) + (t - x).cos().max(0.0));
        let seed_num = |t: f64| {
            let w = two_point(t);
            let mut breaks: Vec<f64> = vec![0.0, 1e-4, 1e-2, 0.3, PI];
            breaks.extend(ring_kinks(t));
            breaks.sort_by(f64::total_cmp);
            quad::integrate_with_breaks(&|x| g(x) * w(x), &breaks, 1e-15, 1e-13)
        };
        let num = seed_num(PI / 4.0);
        let den = b.cdf(2.0 * c)[0];
        assert!((num - 0.563_473_121_128_181_8).abs() < 1e-10, "{num}");
        assert!((den - 0.946_521_806_008_770_1).abs() < 1e-12, "{den}");
        // The sphere's exact ring mean (mpmath at 20 digits, typed here).
        let exact = preintegrated_d(&b, PI / 4.0, c)[0];
        assert!((exact - 0.576_285).abs() < 1e-5, "{exact}");
        let at_90 = preintegrated_d(&b, FRAC_PI_2, c)[0];
        assert!((at_90 - 0.133_477).abs() < 1e-5, "{at_90}");
        assert!((seed_num(FRAC_PI_2) / den - 0.209_665).abs() < 1e-5);
    }

    /// The ring mean's closed form against adaptive quadrature over φ of
    /// max(0, cos θ cos γ + sin θ sin γ cos φ)/π, over a grid of θ and γ.
    #[test]
    fn ring_mean_matches_quadrature_over_the_ring() {
        for i in 0..=12 {
            for j in 0..=12 {
                let (t, g) = (PI * i as f64 / 12.0, PI * j as f64 / 12.0 + 1e-3);
                let f = |p: f64| (t.cos() * g.cos() + t.sin() * g.sin() * p.cos()).max(0.0) / PI;
                // The kink in φ where the ring crosses the terminator.
                let (a, b) = (t.cos() * g.cos(), t.sin() * g.sin());
                let mut breaks = vec![0.0, PI];
                if b > a.abs() {
                    breaks.push((-a / b).acos());
                }
                breaks.sort_by(f64::total_cmp);
                let want = quad::integrate_with_breaks(&f, &breaks, 1e-14, 1e-12);
                let got = ring_mean_cos(t, g);
                assert!((got - want).abs() < 1e-10, "θ {t} γ {g}: {got} vs {want}");
            }
        }
    }

    /// Penner's D is the profile integrated over the sphere (issue 22's
    /// check, within 0.01 at 45°, 90° and 110° on 3 mm and 10 mm
    /// spheres): against a 2D quadrature over the lit half of the sphere
    /// in the light's own coordinates (y at polar angle α from the light
    /// axis and azimuth β, its chord to x from the dot product) — a second
    /// derivation that shares no ring formula — for the default skin.
    /// Composite Gauss–Legendre in α and β, the panels graded
    /// geometrically towards x (α = θ, β = 0), where the density has its
    /// integrable 1/r core.
    #[test]
    fn d_is_the_spheres_average_by_nested_quadrature() {
        let skin = Burley::from_scattering_distance(
            [0.91058, 0.338275, 0.2718],
            [0.7568628, 0.32156864, 0.2],
        )
        .unwrap();
        let total = skin.total_reflectance();
        let graded = |a: f64, b: f64, at: f64| -> Vec<f64> {
            let mut e: Vec<f64> = (0..=32).map(|k| a + (b - a) * k as f64 / 32.0).collect();
            for k in 0..40 {
                let h = (b - a) * 0.7f64.powi(k);
                e.extend([at - h, at + h]);
            }
            e.push(at);
            e.retain(|x| *x >= a && *x <= b);
            e.sort_by(f64::total_cmp);
            e.dedup_by(|x, y| (*x - *y).abs() < 1e-14);
            e
        };
        let (gx, gw) = quad::gl8();
        let rule = |edges: &[f64]| -> Vec<(f64, f64)> {
            edges
                .windows(2)
                .flat_map(|p| {
                    let (m, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
                    gx.iter().zip(gw).map(move |(x, w)| (m + h * x, h * w))
                })
                .collect()
        };
        for c in [3.0f64, 10.0] {
            for deg in [45.0f64, 90.0, 110.0] {
                let t = deg.to_radians();
                let x = [t.sin(), 0.0, t.cos()];
                let got = preintegrated_d(&skin, t, c);
                let alphas = rule(&graded(0.0, FRAC_PI_2, t.min(FRAC_PI_2)));
                // y is symmetric in β ↦ −β: twice [0, π].
                let betas = rule(&graded(0.0, PI, 0.0));
                let mut sum = [0.0f64; 3];
                for &(alpha, wa) in &alphas {
                    for &(beta, wb) in &betas {
                        let y = [
                            alpha.sin() * beta.cos(),
                            alpha.sin() * beta.sin(),
                            alpha.cos(),
                        ];
                        let dot = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
                        let chord = c * (2.0 - 2.0 * dot).max(0.0).sqrt();
                        let r = skin.reflectance(chord.max(1e-12));
                        let da = 2.0 * c * c * alpha.sin() * wa * wb;
                        for ch in 0..3 {
                            sum[ch] += r[ch] / total[ch] * alpha.cos() * da;
                        }
                    }
                }
                for ch in 0..3 {
                    let want = sum[ch] / skin.cdf(2.0 * c)[ch];
                    eprintln!(
                        "c {c} θ {deg}° channel {ch}: D {:.5} vs sphere {want:.5}",
                        got[ch]
                    );
                    // Measured: equal to 5 decimals everywhere (the
                    // issue asks for 0.01).
                    assert!(
                        (got[ch] - want).abs() < 1e-4,
                        "c {c} θ {deg}° {ch}: {} vs {want}",
                        got[ch]
                    );
                }
            }
        }
    }

    /// The fast bake agrees with the adaptive ring integral everywhere.
    #[test]
    fn bake_matches_reference_quadrature() {
        let layout = LutLayout {
            width: 33,
            height: 9,
            curvature_radius_min_mm: 0.5,
            curvature_radius_max_mm: 80.0,
        };
        for p in [
            Box::new(
                Burley::from_scattering_distance([0.8, 0.5, 0.3], [0.7568628, 0.32156864, 0.2])
                    .unwrap(),
            ) as Box<dyn RadialProfile>,
            Box::new(GaussianSum::deon_skin()),
        ] {
            let lut = Lut::bake(p.as_ref(), layout).unwrap();
            for j in 0..layout.height {
                for i in 0..layout.width {
                    let theta = layout.n_dot_l(i).acos();
                    let reference = preintegrated_d(p.as_ref(), theta, layout.curvature_radius(j));
                    let v = lut.d[j * layout.width + i];
                    for c in 0..3 {
                        assert!(
                            (v[c] - reference[c]).abs() < 1e-6,
                            "i={i} j={j} c={c}: {} vs {}",
                            v[c],
                            reference[c]
                        );
                    }
                }
            }
        }
    }

    /// Flat limit: for a huge curvature radius D → saturate(cos θ); and D is
    /// non-decreasing in N·L along every row.
    #[test]
    fn flat_limit_and_monotone_rows() {
        let b = Burley::from_scattering_distance([1.0; 3], [1.0, 0.5, 0.25]).unwrap();
        for theta in [0.0, 0.7, 1.5, 2.5] {
            let d = preintegrated_d(&b, theta, 1e4);
            assert!((d[0] - theta.cos().max(0.0)).abs() < 1e-3, "{theta}: {d:?}");
        }
        let lut = Lut::bake(
            &b,
            LutLayout {
                width: 64,
                height: 8,
                ..Default::default()
            },
        )
        .unwrap();
        for row in lut.d.chunks(64) {
            for w in row.windows(2) {
                for c in 0..3 {
                    assert!(w[1][c] >= w[0][c] - 1e-12);
                }
            }
        }
    }

    #[test]
    fn delta_encoding_round_trips_and_matches_faceworks() {
        let e = LutEncoding::FaceWorksDelta;
        for (d, ndl) in [(0.3, 0.2), (0.1, -0.5), (0.62, 0.6)] {
            assert!((e.decode(e.encode(d, ndl), ndl) - d).abs() < 1e-15);
        }
        // FaceWorks: rgb·2 + (−saturate(N·L)·2 + 0.5).
        assert_eq!(e.encode(0.4, 0.3), 0.4 * 2.0 - 0.3 * 2.0 + 0.5);
    }

    /// The shadow table is 0 deep in shadow, 1 fully lit, rises along x, and
    /// for a very wide penumbra approaches the unscattered shadow u.
    #[test]
    fn shadow_table_limits() {
        let b = Burley::from_scattering_distance([1.0; 3], [1.0, 0.5, 0.25]).unwrap();
        let wide = ShadowLayout {
            width: 32,
            height: 1,
            penumbra_min_mm: 1e4,
            penumbra_max_mm: 1e4,
        };
        let t = bake_shadow(&b, wide).unwrap();
        // A 10 m penumbra: scattering changes nothing.
        for i in 0..32 {
            let u = (i as f64 + 0.5) / 32.0;
            assert!((t[i][2] - u).abs() < 2e-3, "{} vs {u}", t[i][2]);
        }
        let narrow = ShadowLayout {
            width: 32,
            height: 4,
            penumbra_min_mm: 0.5,
            penumbra_max_mm: 20.0,
        };
        let t = bake_shadow(&b, narrow).unwrap();
        for row in t.chunks(32) {
            for w in row.windows(2) {
                assert!(w[1][0] >= w[0][0] - 1e-9);
            }
            // Red bleeds further into the shadow than blue.
            assert!(row[2][0] > row[2][2]);
        }
    }
}
