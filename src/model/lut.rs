//! Pre-integrated skin lookup tables (Penner & Borshukov 2011), with the
//! improved ring integral of Penner 2011 and FaceWorks' encodings.
//!
//! D(θ, c) = ∫₀^{2c} 2π R_N(r) r·cos⁺θᵢ dr / ∫₀^{2c} 2π R_N(r) r dr, with the
//! ring parameterisation r = 2c|sin(x/2)|, dr/dx = c·cos(x/2) and
//! θᵢ = θ ± x. The denominator is exactly CDF(2c).
//!
//! The table bake integrates g(x) = 2πR_N(r)r·dr/dx against cos x and sin x
//! once per row (curvature) with Gauss–Legendre panels that end exactly on
//! every kink of cos⁺(θ ± x) of every column; each entry is then a
//! combination of four cumulative integrals. Rows run in parallel (rayon).

use super::quad;
use super::{check_range, rgb_map, ModelError, RadialProfile, Rgb};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// (numerator, denominator) of D(θ, c) for one channel by adaptive
/// quadrature of the ring integral (reference grade, used by the CLI).
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
    let w = |x: f64| 0.5 * ((theta + x).cos().max(0.0) + (theta - x).cos().max(0.0));
    let mut breaks: Vec<f64> = [
        FRAC_PI_2 - theta,
        1.5 * PI - theta,
        theta - FRAC_PI_2,
        theta + FRAC_PI_2,
    ]
    .into_iter()
    .filter(|x| *x > 0.0 && *x < PI)
    .collect();
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
    // Break points: every kink of every column, plus nodes that resolve a
    // narrow profile near x = 0 (geometric) and the rest of the ring.
    let mut pts: Vec<f64> = thetas
        .iter()
        .flat_map(|&t| [FRAC_PI_2 - t, 1.5 * PI - t, t - FRAC_PI_2, t + FRAC_PI_2])
        .filter(|x| *x > 0.0 && *x < PI)
        .collect();
    let narrow = 2.0
        * (profile.length_scale_mm().max(profile.r_floor_mm()) / (2.0 * c))
            .min(1.0)
            .asin();
    pts.extend(
        (0..48)
            .map(|k| narrow * 1e-4 * 1.25f64.powi(k))
            .filter(|x| *x < PI),
    );
    pts.extend((0..=64).map(|k| PI * k as f64 / 64.0));
    pts.sort_by(f64::total_cmp);
    pts.dedup();
    // Cumulative ∫g·cos and ∫g·sin at every point, per channel.
    let (gx, gw) = quad::gl8();
    let mut cum_cos = vec![[0.0; 3]; pts.len()];
    let mut cum_sin = vec![[0.0; 3]; pts.len()];
    for i in 1..pts.len() {
        let (a, b) = (pts[i - 1], pts[i]);
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let mut acc_c = [0.0; 3];
        let mut acc_s = [0.0; 3];
        for (x0, w0) in gx.iter().zip(gw) {
            let x = mid + half * x0;
            let r = 2.0 * c * (0.5 * x).sin();
            let rr = profile.r_reflectance(r);
            let jac = c * (0.5 * x).cos();
            let (cx, sx) = (x.cos(), x.sin());
            for ch in 0..3 {
                let g = if total[ch] > 0.0 {
                    2.0 * PI * rr[ch] / total[ch] * jac
                } else {
                    0.0
                };
                acc_c[ch] += w0 * g * cx;
                acc_s[ch] += w0 * g * sx;
            }
        }
        for ch in 0..3 {
            cum_cos[i][ch] = cum_cos[i - 1][ch] + half * acc_c[ch];
            cum_sin[i][ch] = cum_sin[i - 1][ch] + half * acc_s[ch];
        }
    }
    let at = |x: f64| -> usize {
        let x = x.clamp(0.0, PI);
        pts.partition_point(|p| *p < x).min(pts.len() - 1)
    };
    thetas
        .iter()
        .map(|&t| {
            let (ct, st) = (t.cos(), t.sin());
            // cos⁺(θ + x): x ∈ [0, π/2 − θ) ∪ (3π/2 − θ, π]
            let p1 = [
                (0.0, (FRAC_PI_2 - t).max(0.0)),
                ((1.5 * PI - t).min(PI), PI),
            ];
            // cos⁺(θ − x): x ∈ [max(0, θ − π/2), min(π, θ + π/2)]
            let p2 = [((t - FRAC_PI_2).max(0.0), (t + FRAC_PI_2).min(PI))];
            rgb_map(|ch| {
                if total[ch] <= 0.0 || den[ch] <= 0.0 {
                    return ct.max(0.0);
                }
                let seg = |a: f64, b: f64| {
                    if b <= a {
                        return (0.0, 0.0);
                    }
                    let (ia, ib) = (at(a), at(b));
                    (
                        cum_cos[ib][ch] - cum_cos[ia][ch],
                        cum_sin[ib][ch] - cum_sin[ia][ch],
                    )
                };
                let mut num = 0.0;
                for (a, b) in p1 {
                    let (ic, is) = seg(a, b);
                    num += 0.5 * (ct * ic - st * is);
                }
                for (a, b) in p2 {
                    let (ic, is) = seg(a, b);
                    num += 0.5 * (ct * ic + st * is);
                }
                num += dirac[ch] / total[ch] * ct.max(0.0);
                (num / den[ch]).max(0.0)
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

    /// Seed 000's Octave check: S = 1/0.7568628, c = 3 mm, θ = π/4 prints
    /// numerator 0.563473 and denominator 0.946522 (six decimals). mpmath
    /// at 30 digits, split at the kinks x = π/4 and 3π/4, gives
    /// 0.563473121128181846 and 0.946521806008770057.
    #[test]
    fn reproduces_seed_reference_values() {
        let b = Burley::from_scattering_distance([1.0; 3], [0.756_862_8; 3]).unwrap();
        let (num, den) = ring_integral(&b, 0, PI / 4.0, 3.0);
        assert!((num - 0.563_473).abs() < 5e-7, "{num}");
        assert!((den - 0.946_522).abs() < 5e-7, "{den}");
        assert!((num - 0.563_473_121_128_181_8).abs() < 1e-12, "{num}");
        assert!((den - 0.946_521_806_008_770_1).abs() < 1e-12, "{den}");
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
